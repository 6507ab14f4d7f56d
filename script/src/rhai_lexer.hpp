// The Rhai lexer: turns script text into tokens on demand (no token array, so a script of
// millions of statements costs no memory here), interning identifiers as small integers.
// Number syntax follows Rhai's tokenizer: `_` separators, 0x/0o/0b integers, `1.` and `1e5`
// floats, `1..2` a range and `1.abs()` a method call; integers too large for i64 read as floats.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace frep::rhai {

enum class Tok : std::uint8_t {
  End, Ident, Int, Float, String,
  // keywords
  Let, Const, Fn, If, Else, While, Loop, Do, Until, For, In, Break, Continue, Return, Throw, True, False,
  // punctuation
  LParen, RParen, LBracket, RBracket, LBrace, RBrace, MapOpen, Comma, Semicolon, Colon, Dot, DotDot, DotDotEq,
  // operators
  Plus, Minus, Star, Slash, Percent, StarStar, Shl, Shr, Amp, Pipe, Caret, AmpAmp, PipePipe, Bang,
  Assign, EqEq, NotEq, Lt, Le, Gt, Ge,
  PlusEq, MinusEq, StarEq, SlashEq, PercentEq, StarStarEq, ShlEq, ShrEq, AmpEq, PipeEq, CaretEq,
};

// How a token is named in error messages ("`;`", "a number", "the end of the script").
std::string tok_text(Tok t);

struct Token {
  Tok kind = Tok::End;
  std::uint32_t pos = 0;  // byte offset of the first character
  union {
    std::int64_t i;
    double f;
    std::uint32_t sym;  // Ident: symbol id
    std::uint32_t str;  // String: index into the string pool
  };
  Token() : i(0) {}
};

// Identifier interning: names are views into the script text (or static strings), ids are dense.
class Symbols {
 public:
  Symbols();
  std::uint32_t intern(std::string_view name);
  // kNone if the name was never interned.
  std::uint32_t find(std::string_view name) const;
  std::string_view name(std::uint32_t id) const { return names_[id]; }
  std::uint32_t size() const { return static_cast<std::uint32_t>(names_.size()); }
  static constexpr std::uint32_t kNone = 0xFFFFFFFFu;

 private:
  static std::uint64_t hash(std::string_view s);
  void grow();
  std::vector<std::string_view> names_;
  // Open addressing: (32 bits of the hash << 32 | id), all ones = empty. The stored hash bits
  // let a probe skip other names without touching their text.
  std::vector<std::uint64_t> slots_;
};

// Line and 1-based column (in characters) of a byte offset; computed only for error messages.
struct LineCol {
  std::uint64_t line;
  std::uint64_t column;
};
LineCol line_col(std::string_view text, std::uint32_t pos);

// Thrown by the lexer and parser; the driver turns it into InputError with line and column.
struct SyntaxError {
  std::uint32_t pos;
  std::string message;
};

class Lexer {
 public:
  Lexer(std::string_view text, Symbols& symbols, std::vector<std::string>& strings);
  Token next();
  std::uint32_t offset() const { return p_; }
  void seek(std::uint32_t offset) { p_ = offset; }
  std::string_view text() const { return text_; }
  Symbols& symbols() { return symbols_; }
  std::vector<std::string>& strings() { return strings_; }

 private:
  [[noreturn]] void fail(std::uint32_t pos, std::string msg) const;
  void skip_space_and_comments();
  Token number(std::uint32_t start);
  Token string_literal(std::uint32_t start, char quote);
  std::uint32_t escape(std::string& out, std::uint32_t start, char quote);

  std::string_view text_;
  std::uint32_t p_ = 0;
  Symbols& symbols_;
  std::vector<std::string>& strings_;
  std::string scratch_;
};

}  // namespace frep::rhai
