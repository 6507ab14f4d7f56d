// The Rhai parser (see rhai_parser.hpp). Operator precedences are Rhai's (its book's table).
#include "rhai_parser.hpp"

namespace frep::rhai {

namespace {

struct BinInfo {
  int prec;  // 0 = not a binary operator
  NK kind;
  BinOp op;
  bool right;
};

BinInfo binary_info(Tok t) {
  switch (t) {
    case Tok::PipePipe: return {30, NK::Or, BinOp::Add, false};
    case Tok::Pipe: return {30, NK::Binary, BinOp::BitOr, false};
    case Tok::Caret: return {30, NK::Binary, BinOp::BitXor, false};
    case Tok::AmpAmp: return {60, NK::And, BinOp::Add, false};
    case Tok::Amp: return {60, NK::Binary, BinOp::BitAnd, false};
    case Tok::EqEq: return {90, NK::Binary, BinOp::Eq, false};
    case Tok::NotEq: return {90, NK::Binary, BinOp::Ne, false};
    case Tok::In: return {110, NK::Binary, BinOp::In, false};
    case Tok::Lt: return {130, NK::Binary, BinOp::Lt, false};
    case Tok::Le: return {130, NK::Binary, BinOp::Le, false};
    case Tok::Gt: return {130, NK::Binary, BinOp::Gt, false};
    case Tok::Ge: return {130, NK::Binary, BinOp::Ge, false};
    case Tok::DotDot: return {140, NK::Range, BinOp::Add, false};
    case Tok::DotDotEq: return {140, NK::Range, BinOp::Add, false};
    case Tok::Plus: return {150, NK::Binary, BinOp::Add, false};
    case Tok::Minus: return {150, NK::Binary, BinOp::Sub, false};
    case Tok::Star: return {180, NK::Binary, BinOp::Mul, false};
    case Tok::Slash: return {180, NK::Binary, BinOp::Div, false};
    case Tok::Percent: return {180, NK::Binary, BinOp::Rem, false};
    case Tok::StarStar: return {190, NK::Binary, BinOp::Pow, true};
    case Tok::Shl: return {210, NK::Binary, BinOp::Shl, false};
    case Tok::Shr: return {210, NK::Binary, BinOp::Shr, false};
    default: return {0, NK::Binary, BinOp::Add, false};
  }
}

// Compound assignment operators: 1 + BinOp, 0 for `=`, -1 for not an assignment.
int assign_op(Tok t) {
  switch (t) {
    case Tok::Assign: return 0;
    case Tok::PlusEq: return 1 + static_cast<int>(BinOp::Add);
    case Tok::MinusEq: return 1 + static_cast<int>(BinOp::Sub);
    case Tok::StarEq: return 1 + static_cast<int>(BinOp::Mul);
    case Tok::SlashEq: return 1 + static_cast<int>(BinOp::Div);
    case Tok::PercentEq: return 1 + static_cast<int>(BinOp::Rem);
    case Tok::StarStarEq: return 1 + static_cast<int>(BinOp::Pow);
    case Tok::ShlEq: return 1 + static_cast<int>(BinOp::Shl);
    case Tok::ShrEq: return 1 + static_cast<int>(BinOp::Shr);
    case Tok::AmpEq: return 1 + static_cast<int>(BinOp::BitAnd);
    case Tok::PipeEq: return 1 + static_cast<int>(BinOp::BitOr);
    case Tok::CaretEq: return 1 + static_cast<int>(BinOp::BitXor);
    default: return -1;
  }
}

}  // namespace

Parser::Depth::Depth(Parser& parser) : p(parser) {
  if (++p.depth_ > kMaxNesting) {
    --p.depth_;
    p.fail(p.tok_.pos, "nested more than " + std::to_string(kMaxNesting) +
                           " levels deep (frep's limit on parentheses, blocks, calls and unary operators)");
  }
}

Parser::Parser(Lexer& lexer, Ast& statements, Ast& functions)
    : lexer_(lexer), statements_(statements), functions_(functions), ast_(&statements) {}

void Parser::restore(const State& s) {
  lexer_.seek(s.offset);
  tok_ = s.tok;
  la_ = s.la;
  has_la_ = s.has_la;
  last_ = s.last;
}

void Parser::fail(std::uint32_t pos, std::string msg) const { throw SyntaxError{pos, std::move(msg)}; }

void Parser::expected(const std::string& what) const {
  fail(tok_.pos, "expected " + what + ", found " + tok_text(tok_.kind));
}

void Parser::advance() {
  last_ = tok_.kind;
  if (has_la_) {
    tok_ = la_;
    has_la_ = false;
  } else {
    tok_ = lexer_.next();
  }
}

const Token& Parser::peek() {
  if (!has_la_) {
    la_ = lexer_.next();
    has_la_ = true;
  }
  return la_;
}

bool Parser::accept(Tok t) {
  if (tok_.kind != t) return false;
  advance();
  return true;
}

void Parser::expect(Tok t, const char* context) {
  if (tok_.kind != t) expected(tok_text(t) + " " + context);
  advance();
}

std::uint32_t Parser::add(NK kind, std::uint32_t pos, std::uint32_t a, std::uint32_t b, std::uint32_t c,
                          std::uint8_t op, std::uint16_t flags) {
  AstNode n{kind, op, flags, pos, a, b, c};
  return ast_->add(n);
}

std::uint32_t Parser::commit_list(std::size_t count) {
  const auto start = static_cast<std::uint32_t>(ast_->lists.size());
  ast_->lists.insert(ast_->lists.end(), scratch_.end() - static_cast<std::ptrdiff_t>(count), scratch_.end());
  scratch_.resize(scratch_.size() - count);
  return start;
}

// ---------------------------------------------------------------------------------------------
// Statements

Parser::Item Parser::next(std::uint32_t* node, std::vector<FnDef>& fns) {
  if (!started_) {  // the first token is read here, where syntax errors are caught
    tok_ = lexer_.next();
    started_ = true;
  }
  while (accept(Tok::Semicolon)) {
  }
  if (tok_.kind == Tok::End) return Item::End;
  if (tok_.kind == Tok::Fn) {
    ast_ = &functions_;
    fns.push_back(function());
    ast_ = &statements_;
    accept(Tok::Semicolon);
    return Item::Function;
  }
  *node = statement();
  end_of_statement();
  return Item::Statement;
}

FnDef Parser::function() {
  FnDef f;
  f.pos = tok_.pos;
  advance();  // fn
  if (tok_.kind != Tok::Ident) expected("a function name after `fn`");
  f.name = tok_.sym;
  advance();
  expect(Tok::LParen, "after the function name");
  while (tok_.kind != Tok::RParen) {
    if (tok_.kind != Tok::Ident) expected("a parameter name");
    for (std::uint32_t p : f.params)
      if (p == tok_.sym) fail(tok_.pos, "duplicate parameter name");
    f.params.push_back(tok_.sym);
    advance();
    if (!accept(Tok::Comma)) break;
  }
  expect(Tok::RParen, "after the parameters");
  if (tok_.kind != Tok::LBrace) expected("`{` to start the function body");
  f.body = block();
  return f;
}

void Parser::end_of_statement() {
  if (accept(Tok::Semicolon)) return;
  if (last_ == Tok::RBrace || tok_.kind == Tok::RBrace || tok_.kind == Tok::End) return;
  expected("`;` to end the statement");
}

std::uint32_t Parser::statement() {
  const std::uint32_t pos = tok_.pos;
  switch (tok_.kind) {
    case Tok::Let:
    case Tok::Const: {
      const bool is_const = tok_.kind == Tok::Const;
      advance();
      if (tok_.kind != Tok::Ident) expected(std::string("a variable name after ") + (is_const ? "`const`" : "`let`"));
      const std::uint32_t sym = tok_.sym;
      advance();
      std::uint32_t value = kNone;
      if (accept(Tok::Assign)) value = expression();
      else if (is_const) expected("`=` and a value for the constant");
      return add(NK::Let, pos, sym, value, kNone, 0, is_const ? 1 : 0);
    }
    case Tok::Fn: fail(pos, "functions can only be defined at the top level of the script");
    case Tok::Break:
    case Tok::Return:
    case Tok::Throw: {
      const NK kind = tok_.kind == Tok::Break ? NK::Break : (tok_.kind == Tok::Return ? NK::Return : NK::Throw);
      advance();
      std::uint32_t value = kNone;
      if (tok_.kind != Tok::Semicolon && tok_.kind != Tok::RBrace && tok_.kind != Tok::End) value = expression();
      return add(kind, pos, value);
    }
    case Tok::Continue: advance(); return add(NK::Continue, pos);
    default: break;
  }
  const std::uint32_t e = expression();
  const int aop = assign_op(tok_.kind);
  if (aop < 0) return e;
  const NK target = (*ast_)[e].kind;
  if (target != NK::Var && target != NK::Index && target != NK::Prop)
    fail(tok_.pos, "cannot assign to this: the left side of " + tok_text(tok_.kind) +
                       " must be a variable, an index `a[i]` or a property `a.b`");
  const std::uint32_t op_pos = tok_.pos;
  advance();
  const std::uint32_t value = expression();
  return add(NK::Assign, op_pos, e, value, kNone, static_cast<std::uint8_t>(aop));
}

std::uint32_t Parser::block() {
  Depth d(*this);
  const std::uint32_t pos = tok_.pos;
  expect(Tok::LBrace, "to start a block");
  std::size_t count = 0;
  for (;;) {
    while (accept(Tok::Semicolon)) {
    }
    if (tok_.kind == Tok::RBrace) break;
    if (tok_.kind == Tok::End) fail(pos, "unterminated block: `{` has no matching `}`");
    scratch_.push_back(statement());
    ++count;
    end_of_statement();
  }
  advance();  // }
  const std::uint32_t list = commit_list(count);
  return add(NK::Block, pos, list, static_cast<std::uint32_t>(count));
}

// ---------------------------------------------------------------------------------------------
// Expressions

std::uint32_t Parser::expression() {
  Depth d(*this);
  return binary(1);
}

std::uint32_t Parser::binary(int min_prec) {
  std::uint32_t lhs = unary();
  for (;;) {
    const BinInfo info = binary_info(tok_.kind);
    if (info.prec == 0 || info.prec < min_prec) return lhs;
    const Tok t = tok_.kind;
    const std::uint32_t pos = tok_.pos;
    advance();
    std::uint32_t rhs;
    if (info.right) {
      Depth d(*this);  // right-associative chains recurse
      rhs = binary(info.prec);
    } else {
      rhs = binary(info.prec + 1);
    }
    if (info.kind == NK::Range)
      lhs = add(NK::Range, pos, lhs, rhs, kNone, 0, t == Tok::DotDotEq ? 1 : 0);
    else
      lhs = add(info.kind, pos, lhs, rhs, kNone, static_cast<std::uint8_t>(info.op));
  }
}

std::uint32_t Parser::unary() {
  const std::uint32_t pos = tok_.pos;
  UnOp op;
  switch (tok_.kind) {
    case Tok::Minus: op = UnOp::Neg; break;
    case Tok::Plus: op = UnOp::Plus; break;
    case Tok::Bang: op = UnOp::Not; break;
    default: return postfix();
  }
  Depth d(*this);
  advance();
  // A minus right before a number is part of the literal, as in Rhai's lexer: `-2.abs()` is 2.
  if (op == UnOp::Neg && (tok_.kind == Tok::Int || tok_.kind == Tok::Float)) {
    AstNode n{tok_.kind == Tok::Int ? NK::Int : NK::Float, 0, 0, pos};
    if (tok_.kind == Tok::Float) {
      set_bits64(n, std::bit_cast<std::uint64_t>(-tok_.f));
    } else if (tok_.i == INT64_MIN) {
      fail(pos, "integer literal out of range");
    } else {
      set_bits64(n, static_cast<std::uint64_t>(-tok_.i));
    }
    advance();
    return postfix(ast_->add(n));
  }
  const std::uint32_t operand = unary();
  return add(NK::Unary, pos, operand, kNone, kNone, static_cast<std::uint8_t>(op));
}

std::uint32_t Parser::postfix(std::uint32_t e) {
  if (e == kNone) e = primary();
  for (;;) {
    if (tok_.kind == Tok::Dot) {
      const std::uint32_t pos = tok_.pos;
      advance();
      if (tok_.kind != Tok::Ident) expected("a property or method name after `.`");
      const std::uint32_t sym = tok_.sym;
      advance();
      if (tok_.kind == Tok::LParen) {
        scratch_.push_back(e);
        e = arguments(NK::Method, sym, pos, 1);
      } else {
        e = add(NK::Prop, pos, e, sym);
      }
    } else if (tok_.kind == Tok::LBracket) {
      const std::uint32_t pos = tok_.pos;
      advance();
      const std::uint32_t index = expression();
      expect(Tok::RBracket, "to close the index");
      e = add(NK::Index, pos, e, index);
    } else {
      return e;
    }
  }
}

std::uint32_t Parser::arguments(NK kind, std::uint32_t sym, std::uint32_t pos, std::size_t already) {
  advance();  // (
  std::size_t count = already;
  while (tok_.kind != Tok::RParen) {
    scratch_.push_back(expression());
    ++count;
    if (!accept(Tok::Comma)) break;
  }
  expect(Tok::RParen, "to close the argument list");
  const std::uint32_t list = commit_list(count);
  return add(kind, pos, sym, list, static_cast<std::uint32_t>(count));
}

std::uint32_t Parser::primary() {
  const std::uint32_t pos = tok_.pos;
  switch (tok_.kind) {
    case Tok::Int: {
      AstNode n{NK::Int, 0, 0, pos};
      set_bits64(n, static_cast<std::uint64_t>(tok_.i));
      advance();
      return ast_->add(n);
    }
    case Tok::Float: {
      AstNode n{NK::Float, 0, 0, pos};
      set_bits64(n, std::bit_cast<std::uint64_t>(tok_.f));
      advance();
      return ast_->add(n);
    }
    case Tok::String: {
      const std::uint32_t s = tok_.str;
      advance();
      return add(NK::Str, pos, s);
    }
    case Tok::True: advance(); return add(NK::True, pos);
    case Tok::False: advance(); return add(NK::False, pos);
    case Tok::Ident: {
      const std::uint32_t sym = tok_.sym;
      if (peek().kind == Tok::LParen) {
        advance();
        Depth d(*this);
        return arguments(NK::Call, sym, pos, 0);
      }
      advance();
      return add(NK::Var, pos, sym);
    }
    case Tok::LParen: {
      advance();
      if (accept(Tok::RParen)) return add(NK::Unit, pos);
      const std::uint32_t e = expression();
      expect(Tok::RParen, "to close the parenthesis");
      return e;
    }
    case Tok::LBracket: {
      Depth d(*this);
      advance();
      std::size_t count = 0;
      while (tok_.kind != Tok::RBracket) {
        scratch_.push_back(expression());
        ++count;
        if (!accept(Tok::Comma)) break;
      }
      expect(Tok::RBracket, "to close the array");
      const std::uint32_t list = commit_list(count);
      return add(NK::Array, pos, list, static_cast<std::uint32_t>(count));
    }
    case Tok::MapOpen: {
      Depth d(*this);
      advance();
      std::size_t pairs = 0;
      while (tok_.kind != Tok::RBrace) {
        std::uint32_t key;
        if (tok_.kind == Tok::Ident) {
          key = static_cast<std::uint32_t>(lexer_.strings().size());
          lexer_.strings().emplace_back(lexer_.symbols().name(tok_.sym));
        } else if (tok_.kind == Tok::String) {
          key = tok_.str;
        } else {
          expected("a property name in the object map");
        }
        advance();
        expect(Tok::Colon, "after the property name");
        scratch_.push_back(key);
        scratch_.push_back(expression());
        ++pairs;
        if (!accept(Tok::Comma)) break;
      }
      expect(Tok::RBrace, "to close the object map");
      const std::uint32_t list = commit_list(pairs * 2);
      return add(NK::Map, pos, list, static_cast<std::uint32_t>(pairs));
    }
    case Tok::LBrace: return block();
    case Tok::If: return if_chain();
    case Tok::While: {
      Depth d(*this);
      advance();
      const std::uint32_t cond = expression();
      if (tok_.kind != Tok::LBrace) expected("`{` after the `while` condition");
      const std::uint32_t body = block();
      return add(NK::While, pos, cond, body);
    }
    case Tok::Loop: {
      advance();
      if (tok_.kind != Tok::LBrace) expected("`{` after `loop`");
      return add(NK::Loop, pos, block());
    }
    case Tok::Do: {
      Depth d(*this);
      advance();
      if (tok_.kind != Tok::LBrace) expected("`{` after `do`");
      const std::uint32_t body = block();
      std::uint16_t until = 0;
      if (accept(Tok::Until)) until = 1;
      else expect(Tok::While, "or `until` after the `do` block");
      const std::uint32_t cond = expression();
      return add(NK::DoWhile, pos, body, cond, kNone, 0, until);
    }
    case Tok::For: return for_loop();
    case Tok::Pipe:
    case Tok::PipePipe: fail(pos, "closures (`|x| ...`) are not supported by frep's Rhai reader");
    case Tok::Fn: fail(pos, "functions can only be defined at the top level of the script");
    default: break;
  }
  expected("an expression");
}

std::uint32_t Parser::if_chain() {
  Depth d(*this);
  const std::uint32_t pos = tok_.pos;
  std::size_t pairs = 0;
  std::uint32_t otherwise = kNone;
  for (;;) {
    advance();  // if
    scratch_.push_back(expression());
    if (tok_.kind != Tok::LBrace) expected("`{` after the `if` condition");
    scratch_.push_back(block());
    ++pairs;
    if (!accept(Tok::Else)) break;
    if (tok_.kind == Tok::If) continue;  // `else if`: same chain, no recursion
    if (tok_.kind != Tok::LBrace) expected("`{` or `if` after `else`");
    otherwise = block();
    break;
  }
  const std::uint32_t list = commit_list(pairs * 2);
  return add(NK::If, pos, list, static_cast<std::uint32_t>(pairs), otherwise);
}

std::uint32_t Parser::for_loop() {
  Depth d(*this);
  const std::uint32_t pos = tok_.pos;
  advance();  // for
  std::uint32_t var, index = kNone;
  if (accept(Tok::LParen)) {
    if (tok_.kind != Tok::Ident) expected("a loop variable name");
    var = tok_.sym;
    advance();
    expect(Tok::Comma, "between the loop variable and the index variable");
    if (tok_.kind != Tok::Ident) expected("an index variable name");
    index = tok_.sym;
    advance();
    expect(Tok::RParen, "after the loop variables");
  } else {
    if (tok_.kind != Tok::Ident) expected("a loop variable name after `for`");
    var = tok_.sym;
    advance();
  }
  expect(Tok::In, "after the loop variable");
  const std::uint32_t iterable = expression();
  if (tok_.kind != Tok::LBrace) expected("`{` to start the loop body");
  const std::uint32_t body = block();
  scratch_.push_back(var);
  scratch_.push_back(index);
  const std::uint32_t list = commit_list(2);
  return add(NK::For, pos, iterable, body, list);
}

}  // namespace frep::rhai
