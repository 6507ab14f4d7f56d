// The Rhai lexer (see rhai_lexer.hpp).
#include "rhai_lexer.hpp"

#include <array>
#include <charconv>
#include <cstdio>
#include <cstring>

#include "frep/util/parse_number.hpp"

namespace frep::rhai {

std::string tok_text(Tok t) {
  switch (t) {
    case Tok::End: return "the end of the script";
    case Tok::Ident: return "a name";
    case Tok::Int:
    case Tok::Float: return "a number";
    case Tok::String: return "a string";
    case Tok::Let: return "`let`";
    case Tok::Const: return "`const`";
    case Tok::Fn: return "`fn`";
    case Tok::If: return "`if`";
    case Tok::Else: return "`else`";
    case Tok::While: return "`while`";
    case Tok::Loop: return "`loop`";
    case Tok::Do: return "`do`";
    case Tok::Until: return "`until`";
    case Tok::For: return "`for`";
    case Tok::In: return "`in`";
    case Tok::Break: return "`break`";
    case Tok::Continue: return "`continue`";
    case Tok::Return: return "`return`";
    case Tok::Throw: return "`throw`";
    case Tok::True: return "`true`";
    case Tok::False: return "`false`";
    case Tok::LParen: return "`(`";
    case Tok::RParen: return "`)`";
    case Tok::LBracket: return "`[`";
    case Tok::RBracket: return "`]`";
    case Tok::LBrace: return "`{`";
    case Tok::RBrace: return "`}`";
    case Tok::MapOpen: return "`#{`";
    case Tok::Comma: return "`,`";
    case Tok::Semicolon: return "`;`";
    case Tok::Colon: return "`:`";
    case Tok::Dot: return "`.`";
    case Tok::DotDot: return "`..`";
    case Tok::DotDotEq: return "`..=`";
    case Tok::Plus: return "`+`";
    case Tok::Minus: return "`-`";
    case Tok::Star: return "`*`";
    case Tok::Slash: return "`/`";
    case Tok::Percent: return "`%`";
    case Tok::StarStar: return "`**`";
    case Tok::Shl: return "`<<`";
    case Tok::Shr: return "`>>`";
    case Tok::Amp: return "`&`";
    case Tok::Pipe: return "`|`";
    case Tok::Caret: return "`^`";
    case Tok::AmpAmp: return "`&&`";
    case Tok::PipePipe: return "`||`";
    case Tok::Bang: return "`!`";
    case Tok::Assign: return "`=`";
    case Tok::EqEq: return "`==`";
    case Tok::NotEq: return "`!=`";
    case Tok::Lt: return "`<`";
    case Tok::Le: return "`<=`";
    case Tok::Gt: return "`>`";
    case Tok::Ge: return "`>=`";
    case Tok::PlusEq: return "`+=`";
    case Tok::MinusEq: return "`-=`";
    case Tok::StarEq: return "`*=`";
    case Tok::SlashEq: return "`/=`";
    case Tok::PercentEq: return "`%=`";
    case Tok::StarStarEq: return "`**=`";
    case Tok::ShlEq: return "`<<=`";
    case Tok::ShrEq: return "`>>=`";
    case Tok::AmpEq: return "`&=`";
    case Tok::PipeEq: return "`|=`";
    case Tok::CaretEq: return "`^=`";
  }
  return "?";
}

// ---------------------------------------------------------------------------------------------
// Symbols

namespace {
constexpr std::uint64_t kEmptySlot = ~0ull;
std::uint64_t slot_of(std::uint64_t h, std::uint32_t id) { return (h & 0xFFFFFFFF00000000ull) | id; }
}  // namespace

Symbols::Symbols() : slots_(1024, kEmptySlot) {}

std::uint64_t Symbols::hash(std::string_view s) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a, then a final mix
  for (char c : s) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  h ^= h >> 29;
  return h * 0x9E3779B97F4A7C15ull;  // the slot index comes from the low bits, the tag from the high
}

void Symbols::grow() {
  std::vector<std::uint64_t> bigger(slots_.size() * 2, kEmptySlot);
  const std::size_t mask = bigger.size() - 1;
  for (std::uint32_t id = 0; id < names_.size(); ++id) {
    const std::uint64_t h = hash(names_[id]);
    std::size_t s = (h >> 16) & mask;
    while (bigger[s] != kEmptySlot) s = (s + 1) & mask;
    bigger[s] = slot_of(h, id);
  }
  slots_.swap(bigger);
}

std::uint32_t Symbols::intern(std::string_view name) {
  if ((names_.size() + 1) * 2 > slots_.size()) grow();
  const std::size_t mask = slots_.size() - 1;
  const std::uint64_t h = hash(name);
  std::size_t s = (h >> 16) & mask;
  while (slots_[s] != kEmptySlot) {
    const std::uint64_t e = slots_[s];
    if ((e >> 32) == (h >> 32) && names_[static_cast<std::uint32_t>(e)] == name) return static_cast<std::uint32_t>(e);
    s = (s + 1) & mask;
  }
  const auto id = static_cast<std::uint32_t>(names_.size());
  names_.push_back(name);
  slots_[s] = slot_of(h, id);
  return id;
}

std::uint32_t Symbols::find(std::string_view name) const {
  const std::size_t mask = slots_.size() - 1;
  const std::uint64_t h = hash(name);
  std::size_t s = (h >> 16) & mask;
  while (slots_[s] != kEmptySlot) {
    const std::uint64_t e = slots_[s];
    if ((e >> 32) == (h >> 32) && names_[static_cast<std::uint32_t>(e)] == name) return static_cast<std::uint32_t>(e);
    s = (s + 1) & mask;
  }
  return kNone;
}

// ---------------------------------------------------------------------------------------------

LineCol line_col(std::string_view text, std::uint32_t pos) {
  LineCol lc{1, 1};
  const std::size_t end = pos < text.size() ? pos : text.size();
  for (std::size_t i = 0; i < end; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c == '\n') {
      ++lc.line;
      lc.column = 1;
    } else if ((c & 0xC0) != 0x80) {  // count UTF-8 characters, not bytes
      ++lc.column;
    }
  }
  return lc;
}

namespace {

bool is_ident_start(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
bool is_ident_char(char c) { return is_ident_start(c) || (c >= '0' && c <= '9'); }
bool is_digit(char c) { return c >= '0' && c <= '9'; }

struct Keyword {
  std::string_view word;
  Tok tok;
};
constexpr Keyword kKeywords[] = {
    {"let", Tok::Let},       {"const", Tok::Const},       {"fn", Tok::Fn},         {"if", Tok::If},
    {"else", Tok::Else},     {"while", Tok::While},       {"loop", Tok::Loop},     {"do", Tok::Do},
    {"until", Tok::Until},   {"for", Tok::For},           {"in", Tok::In},         {"break", Tok::Break},
    {"continue", Tok::Continue}, {"return", Tok::Return}, {"throw", Tok::Throw},   {"true", Tok::True},
    {"false", Tok::False},
};
// Rhai keywords for features this reader does not have: a clear error instead of a confusing one.
constexpr std::string_view kUnsupported[] = {"switch", "import", "export", "private", "this",
                                             "try",    "catch",  "global", "as",      "Fn"};

// First letters of the keywords above, so that most names skip the keyword comparisons.
constexpr auto kMaybeKeyword = [] {
  std::array<bool, 256> t{};
  for (const Keyword& k : kKeywords) t[static_cast<unsigned char>(k.word[0])] = true;
  for (std::string_view u : kUnsupported) t[static_cast<unsigned char>(u[0])] = true;
  return t;
}();

std::string printable(char c) {
  const auto u = static_cast<unsigned char>(c);
  if (u >= 32 && u < 127) return std::string("`") + c + "`";
  char buf[16];
  std::snprintf(buf, sizeof buf, "byte 0x%02x", u);
  return buf;
}

}  // namespace

Lexer::Lexer(std::string_view text, Symbols& symbols, std::vector<std::string>& strings)
    : text_(text), symbols_(symbols), strings_(strings) {
  if (text_.substr(0, 2) == "#!") {  // shebang line
    while (p_ < text_.size() && text_[p_] != '\n') ++p_;
  }
}

void Lexer::fail(std::uint32_t pos, std::string msg) const { throw SyntaxError{pos, std::move(msg)}; }

void Lexer::skip_space_and_comments() {
  const std::uint32_t n = static_cast<std::uint32_t>(text_.size());
  while (p_ < n) {
    const char c = text_[p_];
    if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v') {
      ++p_;
    } else if (c == '/' && p_ + 1 < n && text_[p_ + 1] == '/') {
      while (p_ < n && text_[p_] != '\n') ++p_;
    } else if (c == '/' && p_ + 1 < n && text_[p_ + 1] == '*') {
      const std::uint32_t start = p_;
      p_ += 2;
      int level = 1;  // Rhai's block comments nest
      while (level > 0) {
        if (p_ >= n) fail(start, "unterminated block comment `/*`");
        if (text_[p_] == '/' && p_ + 1 < n && text_[p_ + 1] == '*') {
          ++level;
          p_ += 2;
        } else if (text_[p_] == '*' && p_ + 1 < n && text_[p_ + 1] == '/') {
          --level;
          p_ += 2;
        } else {
          ++p_;
        }
      }
    } else {
      return;
    }
  }
}

Token Lexer::next() {
  skip_space_and_comments();
  Token t;
  t.pos = p_;
  const std::uint32_t n = static_cast<std::uint32_t>(text_.size());
  if (p_ >= n) {
    t.kind = Tok::End;
    return t;
  }
  const char c = text_[p_];
  const char c1 = p_ + 1 < n ? text_[p_ + 1] : '\0';
  const char c2 = p_ + 2 < n ? text_[p_ + 2] : '\0';
  if (is_ident_start(c)) {
    std::uint32_t e = p_ + 1;
    while (e < n && is_ident_char(text_[e])) ++e;
    const std::string_view word = text_.substr(p_, e - p_);
    p_ = e;
    if (word.size() >= 2 && word.size() <= 8 && kMaybeKeyword[static_cast<unsigned char>(word[0])]) {
      for (const Keyword& k : kKeywords)
        if (k.word == word) {
          t.kind = k.tok;
          return t;
        }
      for (std::string_view u : kUnsupported)
        if (u == word) fail(t.pos, "`" + std::string(word) + "` is not supported by frep's Rhai reader");
    }
    t.kind = Tok::Ident;
    t.sym = symbols_.intern(word);
    return t;
  }
  if (is_digit(c)) return number(p_);
  auto op = [&](Tok k, std::uint32_t len) {
    t.kind = k;
    p_ += len;
    return t;
  };
  switch (c) {
    case '"':
    case '`':
    case '\'': return string_literal(p_, c);
    case '(': return op(Tok::LParen, 1);
    case ')': return op(Tok::RParen, 1);
    case '[': return op(Tok::LBracket, 1);
    case ']': return op(Tok::RBracket, 1);
    case '{': return op(Tok::LBrace, 1);
    case '}': return op(Tok::RBrace, 1);
    case ',': return op(Tok::Comma, 1);
    case ';': return op(Tok::Semicolon, 1);
    case '#':
      if (c1 == '{') return op(Tok::MapOpen, 2);
      break;
    case ':':
      if (c1 == ':') fail(t.pos, "namespaces (`::`) are not supported by frep's Rhai reader");
      return op(Tok::Colon, 1);
    case '.':
      if (c1 == '.') return c2 == '=' ? op(Tok::DotDotEq, 3) : op(Tok::DotDot, 2);
      return op(Tok::Dot, 1);
    case '+':
      if (c1 == '+') fail(t.pos, "`++` is not an operator in Rhai; write `+= 1`");
      return c1 == '=' ? op(Tok::PlusEq, 2) : op(Tok::Plus, 1);
    case '-':
      if (c1 == '-') {
        // `--` is reserved in Rhai, but `- -x` and `a - -1` are fine; only `--` glued is refused.
        fail(t.pos, "`--` is not an operator in Rhai; write `-= 1` (or `- -x` for a double negation)");
      }
      return c1 == '=' ? op(Tok::MinusEq, 2) : op(Tok::Minus, 1);
    case '*':
      if (c1 == '*') return c2 == '=' ? op(Tok::StarStarEq, 3) : op(Tok::StarStar, 2);
      return c1 == '=' ? op(Tok::StarEq, 2) : op(Tok::Star, 1);
    case '/': return c1 == '=' ? op(Tok::SlashEq, 2) : op(Tok::Slash, 1);
    case '%': return c1 == '=' ? op(Tok::PercentEq, 2) : op(Tok::Percent, 1);
    case '^': return c1 == '=' ? op(Tok::CaretEq, 2) : op(Tok::Caret, 1);
    case '&':
      if (c1 == '&') return op(Tok::AmpAmp, 2);
      return c1 == '=' ? op(Tok::AmpEq, 2) : op(Tok::Amp, 1);
    case '|':
      if (c1 == '|') return op(Tok::PipePipe, 2);
      if (c1 == '=') return op(Tok::PipeEq, 2);
      return op(Tok::Pipe, 1);
    case '!':
      return c1 == '=' ? op(Tok::NotEq, 2) : op(Tok::Bang, 1);
    case '=':
      if (c1 == '=') return op(Tok::EqEq, 2);
      if (c1 == '>') fail(t.pos, "`=>` (switch arms) is not supported by frep's Rhai reader");
      return op(Tok::Assign, 1);
    case '<':
      if (c1 == '<') return c2 == '=' ? op(Tok::ShlEq, 3) : op(Tok::Shl, 2);
      return c1 == '=' ? op(Tok::Le, 2) : op(Tok::Lt, 1);
    case '>':
      if (c1 == '>') return c2 == '=' ? op(Tok::ShrEq, 3) : op(Tok::Shr, 2);
      return c1 == '=' ? op(Tok::Ge, 2) : op(Tok::Gt, 1);
    case '?':
      fail(t.pos, "`?.` and `??` are not supported by frep's Rhai reader");
    default: break;
  }
  fail(t.pos, "unexpected character " + printable(c));
}

Token Lexer::number(std::uint32_t start) {
  const std::uint32_t n = static_cast<std::uint32_t>(text_.size());
  Token t;
  t.pos = start;
  scratch_.clear();
  std::uint32_t p = start;
  // 0x, 0o, 0b integers: parsed as unsigned 64 bits, then reinterpreted as signed (as Rhai).
  if (text_[p] == '0' && p + 1 < n && (text_[p + 1] == 'x' || text_[p + 1] == 'X' || text_[p + 1] == 'o' ||
                                        text_[p + 1] == 'O' || text_[p + 1] == 'b' || text_[p + 1] == 'B')) {
    const char r = static_cast<char>(text_[p + 1] | 0x20);
    const int base = r == 'x' ? 16 : (r == 'o' ? 8 : 2);
    p += 2;
    while (p < n) {
      const char d = text_[p];
      const bool ok = base == 16 ? (is_digit(d) || ((d | 0x20) >= 'a' && (d | 0x20) <= 'f'))
                                 : (d >= '0' && d < static_cast<char>('0' + base));
      if (d == '_') {
        ++p;
      } else if (ok) {
        scratch_ += d;
        ++p;
      } else {
        break;
      }
    }
    std::uint64_t u = 0;
    const auto r2 = std::from_chars(scratch_.data(), scratch_.data() + scratch_.size(), u, base);
    if (scratch_.empty() || r2.ec != std::errc() || r2.ptr != scratch_.data() + scratch_.size())
      fail(start, "malformed number `" + std::string(text_.substr(start, p - start)) + "`");
    if (p < n && is_ident_char(text_[p])) fail(p, "malformed number: unexpected " + printable(text_[p]));
    p_ = p;
    t.kind = Tok::Int;
    t.i = static_cast<std::int64_t>(u);
    return t;
  }
  bool has_period = false, has_e = false;
  while (p < n) {
    const char d = text_[p];
    if (d == '_') {
      ++p;
    } else if (is_digit(d)) {
      scratch_ += d;
      ++p;
    } else if (d == '.' && !has_period) {
      const char after = p + 1 < n ? text_[p + 1] : '\0';
      if (is_digit(after)) {
        scratch_ += '.';
        has_period = true;
        ++p;
      } else if (after == '_' || after == '.' || is_ident_start(after)) {
        break;  // `1..2` is a range, `1.abs()` a method call
      } else {
        scratch_ += ".0";  // `1.` is a float
        has_period = true;
        ++p;
      }
    } else if ((d == 'e' || d == 'E') && !has_e) {
      const char after = p + 1 < n ? text_[p + 1] : '\0';
      if (is_digit(after)) {
        scratch_ += 'e';
        ++p;
      } else if ((after == '+' || after == '-') && p + 2 < n && is_digit(text_[p + 2])) {
        scratch_ += 'e';
        scratch_ += after;
        p += 2;
      } else {
        break;
      }
      has_e = has_period = true;
    } else {
      break;
    }
  }
  if (p < n && is_ident_char(text_[p]))
    fail(p, "malformed number `" + std::string(text_.substr(start, p + 1 - start)) + "`");
  p_ = p;
  if (!has_period) {
    std::int64_t v = 0;
    const auto r = std::from_chars(scratch_.data(), scratch_.data() + scratch_.size(), v);
    if (r.ec == std::errc() && r.ptr == scratch_.data() + scratch_.size()) {
      t.kind = Tok::Int;
      t.i = v;
      return t;
    }
    // Too large for i64: Rhai reads it as a float.
  }
  double f = 0;
  if (!parse_real(scratch_, f)) fail(start, "malformed number `" + std::string(text_.substr(start, p - start)) + "`");
  t.kind = Tok::Float;
  t.f = f;
  return t;
}

std::uint32_t Lexer::escape(std::string& out, std::uint32_t p, char quote) {
  // text_[p] is the character after the backslash.
  const std::uint32_t n = static_cast<std::uint32_t>(text_.size());
  const std::uint32_t at = p - 1;
  if (p >= n) fail(at, "unterminated string");
  const char e = text_[p];
  auto put_utf8 = [&](std::uint32_t cp) {
    if (cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) fail(at, "malformed escape sequence: not a character");
    if (cp < 0x80) {
      out += static_cast<char>(cp);
    } else if (cp < 0x800) {
      out += static_cast<char>(0xC0 | (cp >> 6));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    } else if (cp < 0x10000) {
      out += static_cast<char>(0xE0 | (cp >> 12));
      out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    } else {
      out += static_cast<char>(0xF0 | (cp >> 18));
      out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
      out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    }
  };
  switch (e) {
    case 'n': out += '\n'; return p + 1;
    case 't': out += '\t'; return p + 1;
    case 'r': out += '\r'; return p + 1;
    case '\\': out += '\\'; return p + 1;
    case 'x':
    case 'u':
    case 'U': {
      const int len = e == 'x' ? 2 : (e == 'u' ? 4 : 8);
      std::uint32_t cp = 0;
      for (int k = 1; k <= len; ++k) {
        if (p + k >= n) fail(at, "malformed escape sequence");
        const char h = text_[p + k];
        int v;
        if (is_digit(h)) v = h - '0';
        else if ((h | 0x20) >= 'a' && (h | 0x20) <= 'f') v = (h | 0x20) - 'a' + 10;
        else fail(at, "malformed escape sequence `\\" + std::string(text_.substr(p, k + 1)) + "`");
        cp = cp * 16 + static_cast<std::uint32_t>(v);
      }
      put_utf8(cp);
      return p + 1 + len;
    }
    case '\n':
      if (quote == '"') {  // line continuation: skip the newline and the next line's indentation
        ++p;
        while (p < n && (text_[p] == ' ' || text_[p] == '\t' || text_[p] == '\r')) ++p;
        return p;
      }
      break;
    default:
      if (e == quote) {
        out += quote;
        return p + 1;
      }
  }
  fail(at, "malformed escape sequence `\\" + std::string(1, e) + "`");
}

Token Lexer::string_literal(std::uint32_t start, char quote) {
  const std::uint32_t n = static_cast<std::uint32_t>(text_.size());
  std::string out;
  std::uint32_t p = start + 1;
  for (;;) {
    if (p >= n) fail(start, quote == '\'' ? "unterminated character literal" : "unterminated string");
    const char c = text_[p];
    if (c == quote) {
      ++p;
      break;
    }
    if (quote == '`') {  // verbatim, multi-line; interpolation is not supported
      if (c == '$' && p + 1 < n && text_[p + 1] == '{')
        fail(p, "string interpolation (`${...}`) is not supported by frep's Rhai reader");
      out += c;
      ++p;
      continue;
    }
    if (c == '\n') fail(start, quote == '\'' ? "unterminated character literal" : "unterminated string");
    if (c == '\\') {
      p = escape(out, p + 1, quote);
    } else {
      out += c;
      ++p;
    }
  }
  p_ = p;
  if (quote == '\'') {
    // One character (one UTF-8 sequence); frep treats characters as one-character strings.
    std::size_t chars = 0;
    for (unsigned char ch : out) chars += (ch & 0xC0) != 0x80;
    if (chars != 1) fail(start, "a character literal holds exactly one character");
  }
  Token t;
  t.kind = Tok::String;
  t.pos = start;
  t.str = static_cast<std::uint32_t>(strings_.size());
  strings_.push_back(std::move(out));
  return t;
}

}  // namespace frep::rhai
