// Writing an expression as a Rhai script that Fidget runs and parse_rhai reads back exactly.
//
// Every node used twice or more becomes `let vN = ...;`; so does any subexpression whose line
// would grow past kMaxLine characters or kMaxDepth levels of nesting (Fidget's engine refuses
// expressions nested deeper than 64). Operators are Rhai's: `+ - * /`, unary `-`, and `%`, which
// Fidget maps to its mod opcode; the other opcodes are Fidget's functions by their names
// (`compare`, `and`, `or`, `not`, `atan2`, `square`, ...). `recip a` has no function in Fidget
// and is written `1.0 / a` (frep's graph turns that back into recip). Constants use the
// shortest text that reads back to the same f32 through f64 (as both Fidget and frep read
// numbers), with a decimal point so they are floats; infinities and NaN, which Rhai has no
// literals for, are written parse_float("inf") and parse_float("NaN").
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "frep/script/rhai.hpp"
#include "frep/util/atomic_file.hpp"
#include "frep/io/field_comments.hpp"
#include "frep/expr/copy.hpp"

namespace frep {
namespace {

constexpr int kMaxDepth = 12;
constexpr std::size_t kMaxLine = 100;

// Rhai precedence of how a node is written: additive 150, multiplicative 180, unary 250,
// atoms and calls 300.
int precedence(Op op) {
  switch (op) {
    case Op::Add:
    case Op::Sub: return 150;
    case Op::Mul:
    case Op::Div:
    case Op::Mod:
    case Op::Recip: return 180;
    case Op::Neg: return 250;
    default: return 300;
  }
}

const char* infix(Op op) {
  switch (op) {
    case Op::Add: return " + ";
    case Op::Sub: return " - ";
    case Op::Mul: return " * ";
    case Op::Div: return " / ";
    case Op::Mod: return " % ";
    default: return nullptr;
  }
}

std::string constant_text(float v) {
  if (std::isnan(v)) return "parse_float(\"NaN\")";
  if (std::isinf(v)) return v > 0 ? "parse_float(\"inf\")" : "parse_float(\"-inf\")";
  // The shortest text that reads back to v as f32 (std::to_chars), checked through f64 as the
  // readers parse it; %.9g, which is always exact, if that check ever fails.
  char buf[48];
  const auto r = std::to_chars(buf, buf + sizeof buf - 1, v);
  *r.ptr = '\0';
  const float back = static_cast<float>(std::strtod(buf, nullptr));
  if (std::memcmp(&back, &v, sizeof v) != 0) std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(v));
  std::string s = buf;
  const std::size_t e = s.find('e');
  if (s.find('.') == std::string::npos) {
    if (e == std::string::npos) s += ".0";  // 3 -> 3.0: a float, not Rhai's integer
    else s.insert(e, ".0");                 // 1e+10 -> 1.0e+10
  }
  return s;
}

class Writer {
 public:
  Writer(const Graph& g, NodeId root) : g_(g), root_(root) {}

  void write(std::ostream& out, const FieldInfo& info) {
    const std::vector<NodeId> order = reachable_nodes(g_, root_);
    uses_.assign(root_ + 1, 0);
    name_.assign(root_ + 1, kNoName);
    len_.assign(root_ + 1, 0);
    depth_.assign(root_ + 1, 0);
    for (NodeId id : order) {
      const Node& n = g_.node(id);
      const int ar = op_arity(n.op);
      if (ar > 0) ++uses_[n.a];
      if (ar > 1) ++uses_[n.b];
    }
    for (NodeId id : order) {
      measure(id);
      if (id != root_ && op_arity(g_.node(id).op) > 0 && uses_[id] > 1) name_[id] = 0;  // numbered below
    }
    std::size_t bound = 0;
    for (NodeId id : order) bound += name_[id] != kNoName;
    // Number the bindings in order and write them.
    std::string buf;
    buf.reserve(1 << 16);
    buf += "// Written by frep: " + std::to_string(order.size()) + " nodes";
    buf += bound ? ", " + std::to_string(bound) + " variables" : std::string();
    buf += ". The last expression is the shape.\n";
    buf += detail::field_info_comments(info, "//");
    std::uint32_t next = 0;
    for (NodeId id : order) {
      if (name_[id] == kNoName) continue;
      name_[id] = kNoName;  // render the definition itself inline
      std::string rhs;
      render(id, rhs);
      name_[id] = next++;
      buf += "let v";
      buf += std::to_string(name_[id]);
      buf += " = ";
      buf += rhs;
      buf += ";\n";
      if (buf.size() > (1 << 16) - 256) {
        out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
        buf.clear();
      }
    }
    render(root_, buf);
    buf += '\n';
    out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
  }

 private:
  static constexpr std::uint32_t kNoName = 0xFFFFFFFFu;

  bool is_leaf(NodeId id) const { return op_arity(g_.node(id).op) == 0; }
  bool inline_node(NodeId id) const { return name_[id] == kNoName; }

  std::size_t leaf_len(NodeId id) const {
    const Node& n = g_.node(id);
    return n.op == Op::Const ? constant_text(n.value).size() : 1;
  }

  // Inline length and depth of a node given its children's, binding children where needed.
  void measure(NodeId id) {
    const Node& n = g_.node(id);
    const int ar = op_arity(n.op);
    if (ar == 0) {
      len_[id] = static_cast<std::uint32_t>(leaf_len(id));
      return;
    }
    for (;;) {
      std::size_t len = std::string_view(op_name(n.op)).size() + 6;
      int depth = 0;
      NodeId biggest = kNoNode;  // the compound inline child with the longest text
      for (int k = 0; k < ar; ++k) {
        const NodeId c = k == 0 ? n.a : n.b;
        if (inline_node(c)) {
          len += len_[c];
          depth = std::max(depth, depth_[c]);
          if (!is_leaf(c) && (biggest == kNoNode || len_[c] > len_[biggest])) biggest = c;
        } else {
          len += 8;
        }
      }
      len_[id] = static_cast<std::uint32_t>(std::min<std::size_t>(len, 1u << 30));
      depth_[id] = depth + 1;
      if ((depth_[id] <= kMaxDepth && len <= kMaxLine) || biggest == kNoNode) return;
      // Too long or too deep: the longest compound child gets a name of its own.
      name_[biggest] = 0;  // any value other than kNoName; numbered when written
    }
  }

  void operand(NodeId c, int min_prec, std::string& s) {
    const bool paren = inline_node(c) && !is_leaf(c) && precedence(g_.node(c).op) < min_prec;
    if (paren) s += '(';
    render(c, s);
    if (paren) s += ')';
  }

  void render(NodeId id, std::string& s) {
    if (!inline_node(id)) {
      s += 'v';
      s += std::to_string(name_[id]);
      return;
    }
    const Node& n = g_.node(id);
    switch (n.op) {
      case Op::VarX: s += 'x'; return;
      case Op::VarY: s += 'y'; return;
      case Op::VarZ: s += 'z'; return;
      case Op::Const: s += constant_text(n.value); return;
      case Op::Neg:
        s += '-';
        operand(n.a, 250, s);
        return;
      case Op::Recip:
        s += "1.0 / ";
        operand(n.a, 181, s);
        return;
      default: break;
    }
    if (const char* op = infix(n.op)) {
      const int p = precedence(n.op);
      operand(n.a, p, s);  // left-associative: an equal precedence on the left needs no parentheses
      s += op;
      operand(n.b, p + 1, s);
      return;
    }
    s += op_name(n.op);  // Fidget's function names are the opcode names
    s += '(';
    render(n.a, s);
    if (op_arity(n.op) == 2) {
      s += ", ";
      render(n.b, s);
    }
    s += ')';
  }

  const Graph& g_;
  NodeId root_;
  std::vector<std::uint32_t> uses_, name_, len_;
  std::vector<int> depth_;
};

}  // namespace

void write_rhai(std::ostream& out, const Graph& g, NodeId root, const FieldInfo& info) {
  if (has_oracles(g, root)) {
    const Model m = expand_oracles(g, root);
    return write_rhai(out, *m.graph, m.root, info);
  }
  Writer(g, root).write(out, info);
}

void save_rhai(const std::string& path, const Graph& g, NodeId root, const FieldInfo& info) {
  write_file_atomically(path, [&](std::ostream& out) { write_rhai(out, g, root, info); });
}

}  // namespace frep
