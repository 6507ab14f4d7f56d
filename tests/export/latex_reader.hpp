// A reader for the mathematics the LaTeX exporter writes, for the tests: parses the align*
// environments of a document or fragment into definitions and f, and evaluates them in double.
// It is an independent reference for the exporter's meaning (signs, precedence, flattening,
// cases), and its grammar is a strict syntax check: anything it does not know is an error.
#pragma once

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "frep/expr/semantics.hpp"

namespace frep::test {

class LatexMath {
 public:
  // Throws std::runtime_error with the position on anything unexpected.
  explicit LatexMath(const std::string& doc) {
    std::string label, rhs;
    std::size_t at = 0;
    int rows = 0;
    auto finish = [&] {
      if (label.empty()) return;
      rhs_text_.push_back(rhs);
      Parser p(rhs, *this);
      Node n = p.parse_all();
      if (label.rfind("d_{", 0) == 0) {
        const int k = std::stoi(label.substr(3));
        if (k != static_cast<int>(defs_.size()) + 1) throw std::runtime_error("definition " + label + " out of order");
        defs_.push_back(std::move(n));
      } else {
        if (label.rfind("f", 0) != 0) throw std::runtime_error("unknown label " + label);
        f_ = std::make_unique<Node>(std::move(n));
        ++roots_;
      }
      label.clear();
      rhs.clear();
    };
    while ((at = doc.find("\\begin{align*}", at)) != std::string::npos) {
      const std::size_t end = doc.find("\\end{align*}", at);
      if (end == std::string::npos) throw std::runtime_error("unterminated align*");
      const std::string body = doc.substr(at + 14, end - at - 14);
      at = end + 12;
      // Rows are separated by "\\" outside braces and cases environments.
      std::vector<std::string> row_texts;
      int depth = 0;
      std::string cur;
      for (std::size_t i = 0; i < body.size(); ++i) {
        if (body.compare(i, 13, "\\begin{cases}") == 0) ++depth;
        if (body.compare(i, 11, "\\end{cases}") == 0) --depth;
        if (depth == 0 && body.compare(i, 2, "\\\\") == 0) {
          row_texts.push_back(cur);
          cur.clear();
          ++i;
          continue;
        }
        cur += body[i];
      }
      row_texts.push_back(cur);
      for (const std::string& r : row_texts) {
        ++rows;
        const std::size_t amp = r.find('&');
        if (amp == std::string::npos) throw std::runtime_error("row without &: " + r);
        std::string left = trim(r.substr(0, amp));
        std::string right = r.substr(amp + 1);
        if (left.empty()) {  // continuation
          if (right.compare(0, 8, "\\qquad {") != 0 && right.compare(0, 7, "\\qquad ") != 0)
            throw std::runtime_error("continuation without \\qquad: " + r);
          if (label.empty()) throw std::runtime_error("continuation before any definition");
          rhs += " " + right.substr(7);
        } else {
          finish();
          if (right.compare(0, 1, "=") != 0) throw std::runtime_error("row without &=: " + r);
          label = left;
          rhs = right.substr(1);
        }
      }
    }
    finish();
    if (roots_ != 1) throw std::runtime_error("expected exactly one f, found " + std::to_string(roots_));
    rows_ = rows;
  }

  double eval(double x, double y, double z) const {
    vals_.assign(defs_.size(), 0.0);
    Ctx c{x, y, z, &vals_};
    for (std::size_t i = 0; i < defs_.size(); ++i) vals_[i] = defs_[i].eval(c);
    return f_->eval(c);
  }
  std::size_t definitions() const { return defs_.size(); }
  int rows() const { return rows_; }

 private:
  static std::string trim(const std::string& s) {
    const std::size_t a = s.find_first_not_of(" \n"), b = s.find_last_not_of(" \n");
    return a == std::string::npos ? "" : s.substr(a, b - a + 1);
  }

  struct Ctx {
    double x, y, z;
    const std::vector<double>* defs;
  };

  enum class K {
    Num, X, Y, Z, Def, Sum, Prod, Frac, Pow, Sqrt, Abs, Floor, Ceil, Round, Sin, Cos, Tan, Asin, Acos, Atan,
    Exp, Ln, Atan2, Min, Max, Sgn, Mod, Iverson, Cases, Neq, Eq, Land, Lor
  };

  struct Node {
    K k = K::Num;
    double v = 0;                // Num: value; Def: index
    std::vector<Node> kids;      // Cases: value, condition pairs; the last condition may be "otherwise"
    std::vector<bool> minus;     // Sum: which terms are subtracted
    std::vector<bool> otherwise; // Cases

    bool holds(const Ctx& c) const {
      switch (k) {
        case K::Neq: return kids[0].eval(c) != kids[1].eval(c);
        case K::Eq: return kids[0].eval(c) == kids[1].eval(c);
        case K::Land: for (const Node& n : kids) if (!n.holds(c)) return false; return true;
        case K::Lor: for (const Node& n : kids) if (n.holds(c)) return true; return false;
        default: throw std::logic_error("not a condition");
      }
    }

    double eval(const Ctx& c) const {
      auto a = [&] { return kids[0].eval(c); };
      auto b = [&] { return kids[1].eval(c); };
      switch (k) {
        case K::Num: return v;
        case K::X: return c.x;
        case K::Y: return c.y;
        case K::Z: return c.z;
        case K::Def: return (*c.defs)[static_cast<std::size_t>(v)];
        case K::Sum: {
          // Starts from the first term, not from 0: keeps -0 where f32 would (atan2 cares).
          double s = minus[0] ? -kids[0].eval(c) : kids[0].eval(c);
          for (std::size_t i = 1; i < kids.size(); ++i) s += minus[i] ? -kids[i].eval(c) : kids[i].eval(c);
          return s;
        }
        case K::Prod: {
          double p = 1;
          for (const Node& n : kids) p *= n.eval(c);
          return p;
        }
        case K::Frac: return a() / b();
        case K::Pow: return kids[1].k == K::Num && kids[1].v == 2 ? a() * a() : std::pow(a(), b());
        case K::Sqrt: return std::sqrt(a());
        case K::Abs: return std::fabs(a());
        case K::Floor: return std::floor(a());
        case K::Ceil: return std::ceil(a());
        case K::Round: return std::round(a());
        case K::Sin: return std::sin(a());
        case K::Cos: return std::cos(a());
        case K::Tan: return std::tan(a());
        case K::Asin: return std::asin(a());
        case K::Acos: return std::acos(a());
        case K::Atan: return std::atan(a());
        case K::Exp: return std::exp(a());
        case K::Ln: return std::log(a());
        case K::Atan2: return std::atan2(a(), b());
        case K::Min:
        case K::Max: {
          double r = a();
          for (std::size_t i = 1; i < kids.size(); ++i)
            r = k == K::Min ? op_min(r, kids[i].eval(c)) : op_max(r, kids[i].eval(c));
          return r;
        }
        case K::Sgn: {
          const double s = a();
          return std::isnan(s) ? s : (s < 0 ? -1.0 : (s > 0 ? 1.0 : 0.0));
        }
        case K::Mod: return op_mod(a(), b());
        case K::Iverson: return kids[0].holds(c) ? 1.0 : 0.0;
        case K::Cases:
          for (std::size_t i = 0; i + 1 < kids.size(); i += 2)
            if (otherwise[i / 2] || kids[i + 1].holds(c)) return kids[i].eval(c);
          return std::numeric_limits<double>::quiet_NaN();  // no row applies
        default: throw std::logic_error("a condition used as a value");
      }
    }
  };

  class Parser {
   public:
    Parser(const std::string& s, const LatexMath& owner) : s_(s), owner_(owner) {}

    Node parse_all() {
      Node n = expr();
      skip();
      if (i_ != s_.size()) fail("unexpected text");
      return n;
    }

   private:
    [[noreturn]] void fail(const std::string& what) const {
      throw std::runtime_error(what + " at " + std::to_string(i_) + ": '" + s_.substr(i_, 60) + "' in '" +
                               s_.substr(0, 200) + "'");
    }
    void skip() {
      while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\n')) ++i_;
    }
    bool peek(const char* t) {
      skip();
      return s_.compare(i_, std::strlen(t), t) == 0 &&
             !(std::isalpha(static_cast<unsigned char>(t[std::strlen(t) - 1])) && t[0] == '\\' &&
               i_ + std::strlen(t) < s_.size() && std::isalpha(static_cast<unsigned char>(s_[i_ + std::strlen(t)])));
    }
    bool eat(const char* t) {
      if (!peek(t)) return false;
      i_ += std::strlen(t);
      return true;
    }
    void expect(const char* t) {
      if (!eat(t)) fail(std::string("expected ") + t);
    }

    static Node make(K k, std::vector<Node> kids = {}) {
      Node n;
      n.k = k;
      n.kids = std::move(kids);
      return n;
    }

    Node expr() {
      Node a = sum();
      if (eat("\\bmod")) return make(K::Mod, {std::move(a), sum()});
      return a;
    }

    Node sum() {
      Node n = make(K::Sum);
      eat("{}");  // a continuation line starts with {} so that its + stays binary
      bool neg = eat("-");
      for (;;) {
        n.kids.push_back(term());
        n.minus.push_back(neg);
        if (eat("{}")) {}
        if (eat("+")) neg = false;
        else if (eat("-")) neg = true;
        else break;
      }
      if (n.kids.size() == 1 && !n.minus[0]) return std::move(n.kids[0]);
      return n;
    }

    bool starts_factor() {
      skip();
      if (i_ >= s_.size()) return false;
      const char c = s_[i_];
      if (std::isdigit(static_cast<unsigned char>(c)) || c == '(' || c == '[' || c == 'x' || c == 'y' || c == 'z' ||
          c == 'd' || c == 'e')
        return true;
      if (c != '\\') return false;
      for (const char* stop : {"\\cdot", "\\bmod", "\\neq", "\\land", "\\lor", "\\right", "\\bigr", "\\end", "\\text", "\\\\"})
        if (peek(stop)) return false;
      return true;
    }

    Node term() {
      Node n = make(K::Prod);
      n.kids.push_back(factor());
      for (;;) {
        if (eat("\\cdot")) n.kids.push_back(factor());
        else if (starts_factor()) n.kids.push_back(factor());
        else break;
      }
      if (n.kids.size() == 1) return std::move(n.kids[0]);
      return n;
    }

    Node factor() {
      Node base = primary();
      if (eat("^{")) {
        Node e = expr();
        expect("}");
        if (base.k == K::Num && base.v == 10 && e.k == K::Num) return number_from(1, e.v);
        if (base.k == K::Num && base.v == 10 && e.k == K::Sum && e.kids.size() == 1 && e.kids[0].k == K::Num)
          return number_from(1, -e.kids[0].v);
        return make(K::Pow, {std::move(base), std::move(e)});
      }
      return base;
    }

    // The f32 constant the text names (the exporter writes the shortest text that reads back).
    static Node number_from(double mant, double exp10) {
      Node n;
      const std::string text = std::to_string(mant) + "e" + std::to_string(static_cast<int>(exp10));
      n.v = static_cast<double>(std::strtof(text.c_str(), nullptr));
      return n;
    }

    Node args(K k, int count) {
      const bool big = eat("\\bigl("), left = !big && eat("\\left(");
      if (!big && !left) expect("(");
      Node n = make(k);
      n.kids.push_back(expr());
      while (eat(",")) n.kids.push_back(expr());
      expect(big ? "\\bigr)" : left ? "\\right)" : ")");
      if (count > 0 && static_cast<int>(n.kids.size()) != count) fail("wrong argument count");
      if (n.kids.empty()) fail("no arguments");
      return n;
    }

    Node braced() {
      expect("{");
      Node n = expr();
      expect("}");
      return n;
    }

    Node primary() {
      skip();
      if (i_ >= s_.size()) fail("unexpected end");
      const char c = s_[i_];
      if (std::isdigit(static_cast<unsigned char>(c))) {
        std::size_t j = i_;
        while (j < s_.size() && (std::isdigit(static_cast<unsigned char>(s_[j])) || s_[j] == '.')) ++j;
        std::string text = s_.substr(i_, j - i_);
        i_ = j;
        // "2.5 \cdot 10^{-7}" is one constant
        const std::size_t save = i_;
        if (eat("\\cdot") && eat("10^{")) {
          const bool neg = eat("-");
          skip();
          std::size_t k = i_;
          while (k < s_.size() && std::isdigit(static_cast<unsigned char>(s_[k]))) ++k;
          text += "e" + std::string(neg ? "-" : "") + s_.substr(i_, k - i_);
          i_ = k;
          expect("}");
        } else {
          i_ = save;
        }
        Node n;
        n.v = static_cast<double>(std::strtof(text.c_str(), nullptr));
        return n;
      }
      if (eat("x")) return make(K::X);
      if (eat("y")) return make(K::Y);
      if (eat("z")) return make(K::Z);
      if (eat("d_{")) {
        std::size_t j = i_;
        while (j < s_.size() && std::isdigit(static_cast<unsigned char>(s_[j]))) ++j;
        const int k = std::stoi(s_.substr(i_, j - i_));
        i_ = j;
        expect("}");
        if (k < 1 || k > static_cast<int>(owner_.defs_.size())) fail("d_" + std::to_string(k) + " used before it is defined");
        Node n = make(K::Def);
        n.v = k - 1;
        return n;
      }
      if (eat("e^{")) {
        Node n = make(K::Exp, {expr()});
        expect("}");
        return n;
      }
      if (eat("(")) {
        Node n = expr();
        expect(")");
        return n;
      }
      if (eat("\\left(")) {
        Node n = expr();
        expect("\\right)");
        return n;
      }
      if (eat("\\left|")) {
        Node n = make(K::Abs, {expr()});
        expect("\\right|");
        return n;
      }
      if (eat("\\left\\lfloor")) {
        Node n = make(K::Floor, {expr()});
        expect("\\right\\rfloor");
        return n;
      }
      if (eat("\\left\\lceil")) {
        Node n = make(K::Ceil, {expr()});
        expect("\\right\\rceil");
        return n;
      }
      if (eat("\\frac")) {
        Node a = braced();
        return make(K::Frac, {std::move(a), braced()});
      }
      if (eat("\\sqrt")) return make(K::Sqrt, {braced()});
      if (eat("\\infty")) {
        Node n;
        n.v = std::numeric_limits<double>::infinity();
        return n;
      }
      if (eat("\\mathrm{NaN}")) {
        Node n;
        n.v = std::numeric_limits<double>::quiet_NaN();
        return n;
      }
      if (eat("[")) {
        Node n = make(K::Iverson, {pred()});
        expect("]");
        return n;
      }
      if (eat("\\begin{cases}")) return cases();
      static const std::pair<const char*, K> fns[] = {
          {"\\min", K::Min}, {"\\max", K::Max}, {"\\sin", K::Sin}, {"\\cos", K::Cos}, {"\\tan", K::Tan},
          {"\\arcsin", K::Asin}, {"\\arccos", K::Acos}, {"\\arctan", K::Atan}, {"\\exp", K::Exp}, {"\\ln", K::Ln},
          {"\\operatorname{round}", K::Round}, {"\\operatorname{sgn}", K::Sgn}, {"\\operatorname{atan2}", K::Atan2}};
      for (const auto& [name, k] : fns)
        if (eat(name)) return args(k, k == K::Min || k == K::Max ? 0 : k == K::Atan2 ? 2 : 1);
      fail("unknown syntax");
    }

    Node cases() {
      Node n = make(K::Cases);
      for (bool first = true;; first = false) {
        if (!first) expect("\\\\");
        n.kids.push_back(expr());
        expect("&");
        if (eat("\\text{otherwise}")) {
          n.kids.push_back(make(K::Land));  // placeholder
          n.otherwise.push_back(true);
          expect("\\end{cases}");
          return n;
        }
        if (!eat(first ? "\\text{if }" : "\\text{else if }")) fail("expected a condition");
        n.kids.push_back(pred());
        n.otherwise.push_back(false);
        if (eat("\\end{cases}")) return n;
      }
    }

    Node pred() {
      Node a = pred_and();
      if (!peek("\\lor")) return a;
      Node n = make(K::Lor, {std::move(a)});
      while (eat("\\lor")) n.kids.push_back(pred_and());
      return n;
    }
    Node pred_and() {
      Node a = pred_atom();
      if (!peek("\\land")) return a;
      Node n = make(K::Land, {std::move(a)});
      while (eat("\\land")) n.kids.push_back(pred_atom());
      return n;
    }
    Node pred_atom() {
      const std::size_t save = i_;
      if (eat("(")) {  // a parenthesized condition, or an expression that starts with (
        try {
          Node p = pred();
          expect(")");
          if (!peek("\\neq") && !peek("=")) return p;
        } catch (const std::runtime_error&) {
        }
        i_ = save;
      }
      Node a = expr();
      K k;
      if (eat("\\neq")) k = K::Neq;
      else if (eat("=")) k = K::Eq;
      else fail("expected \\neq or =");
      return make(k, {std::move(a), expr()});
    }

    const std::string& s_;
    const LatexMath& owner_;
    std::size_t i_ = 0;
  };

  std::vector<Node> defs_;
  std::unique_ptr<Node> f_;
  std::vector<std::string> rhs_text_;
  int roots_ = 0;
  int rows_ = 0;
  mutable std::vector<double> vals_;
};

}  // namespace frep::test
