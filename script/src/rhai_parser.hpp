// The Rhai parser: recursive descent with precedence climbing, one top-level item at a time, so
// the driver can run each statement and drop its nodes before parsing the next. Left-nested
// chains (`a + b + c ...`, `a.f().g()`, `a[1][2]`, `else if`) are built by loops, not recursion;
// what does recurse (parentheses, blocks, arguments, unary operators, `**`) stops at kMaxNesting.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "rhai_ast.hpp"
#include "rhai_lexer.hpp"

namespace frep::rhai {

// Deepest nesting of parentheses, blocks, calls, unary operators and `**` that a script may use
// (Rhai's own default limit, which Fidget keeps, is 64).
inline constexpr int kMaxNesting = 200;

class Parser {
 public:
  Parser(Lexer& lexer, Ast& statements, Ast& functions);

  enum class Item { End, Statement, Function };
  // Parses the next top-level item: a statement (its node in the statements' arena goes to
  // `*node`) or a function definition (appended to `fns`, its nodes in the functions' arena).
  Item next(std::uint32_t* node, std::vector<FnDef>& fns);

  // Saving and restoring the position, to look ahead for function definitions.
  struct State {
    std::uint32_t offset;
    Token tok, la;
    bool has_la;
    Tok last;
  };
  State save() const { return {lexer_.offset(), tok_, la_, has_la_, last_}; }
  void restore(const State& s);

 private:
  [[noreturn]] void fail(std::uint32_t pos, std::string msg) const;
  [[noreturn]] void expected(const std::string& what) const;
  void advance();
  const Token& peek();
  bool accept(Tok t);
  void expect(Tok t, const char* context);

  std::uint32_t add(NK kind, std::uint32_t pos, std::uint32_t a = kNone, std::uint32_t b = kNone,
                    std::uint32_t c = kNone, std::uint8_t op = 0, std::uint16_t flags = 0);
  // Moves the top `count` entries of the scratch stack into the arena's list array.
  std::uint32_t commit_list(std::size_t count);

  std::uint32_t statement();
  void end_of_statement();
  std::uint32_t block();
  std::uint32_t expression();
  std::uint32_t binary(int min_prec);
  std::uint32_t unary();
  std::uint32_t postfix(std::uint32_t prefix = kNone);
  std::uint32_t primary();
  std::uint32_t if_chain();
  std::uint32_t for_loop();
  std::uint32_t arguments(NK kind, std::uint32_t sym, std::uint32_t pos, std::size_t already);
  FnDef function();

  struct Depth {
    explicit Depth(Parser& p);
    ~Depth() { --p.depth_; }
    Parser& p;
  };

  Lexer& lexer_;
  Ast& statements_;
  Ast& functions_;
  Ast* ast_;
  Token tok_, la_;
  bool has_la_ = false;
  bool started_ = false;
  Tok last_ = Tok::End;  // kind of the last token consumed
  int depth_ = 0;
  std::vector<std::uint32_t> scratch_;
};

}  // namespace frep::rhai
