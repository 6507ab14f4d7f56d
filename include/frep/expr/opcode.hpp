// The one opcode table. Ids are frozen: files and tapes depend on them.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace frep {

// X(Name, id, "text", arity). Arity 0 = leaf.
#define FREP_OPCODES(X)          \
  X(VarX, 0, "var-x", 0)         \
  X(VarY, 1, "var-y", 0)         \
  X(VarZ, 2, "var-z", 0)         \
  X(Const, 3, "const", 0)        \
  X(Neg, 4, "neg", 1)            \
  X(Abs, 5, "abs", 1)            \
  X(Recip, 6, "recip", 1)        \
  X(Sqrt, 7, "sqrt", 1)          \
  X(Square, 8, "square", 1)      \
  X(Floor, 9, "floor", 1)        \
  X(Ceil, 10, "ceil", 1)         \
  X(Round, 11, "round", 1)       \
  X(Sin, 12, "sin", 1)           \
  X(Cos, 13, "cos", 1)           \
  X(Tan, 14, "tan", 1)           \
  X(Asin, 15, "asin", 1)         \
  X(Acos, 16, "acos", 1)         \
  X(Atan, 17, "atan", 1)         \
  X(Exp, 18, "exp", 1)           \
  X(Ln, 19, "ln", 1)             \
  X(Not, 20, "not", 1)           \
  X(Add, 21, "add", 2)           \
  X(Sub, 22, "sub", 2)           \
  X(Mul, 23, "mul", 2)           \
  X(Div, 24, "div", 2)           \
  X(Atan2, 25, "atan2", 2)       \
  X(Min, 26, "min", 2)           \
  X(Max, 27, "max", 2)           \
  X(Compare, 28, "compare", 2)   \
  X(Mod, 29, "mod", 2)           \
  X(And, 30, "and", 2)           \
  X(Or, 31, "or", 2)

// Opcodes of the engine only, never written to a file another tool reads: a leaf whose value
// is computed by code (an oracle, expr/oracle.hpp), such as a mesh's exact signed distance.
#define FREP_ENGINE_OPCODES(X) X(Oracle, 32, "oracle", 0)

// Fidget's opcodes: the ones files hold (ids 0 .. kOpCount - 1).
inline constexpr int kOpCount = 32;
// Every opcode, the engine's own included.
inline constexpr int kEngineOpCount = 33;

enum class Op : std::uint8_t {
#define FREP_X(name, id, text, arity) name = id,
  FREP_OPCODES(FREP_X) FREP_ENGINE_OPCODES(FREP_X)
#undef FREP_X
};


constexpr std::string_view op_name(Op op) {
  switch (op) {
#define FREP_X(name, id, text, arity) \
  case Op::name:                      \
    return text;
    FREP_OPCODES(FREP_X)
    FREP_ENGINE_OPCODES(FREP_X)
#undef FREP_X
  }
  return "?";
}

namespace detail {
inline constexpr std::uint8_t kArity[kEngineOpCount] = {
#define FREP_X(name, id, text, arity) arity,
    FREP_OPCODES(FREP_X) FREP_ENGINE_OPCODES(FREP_X)
#undef FREP_X
};
}  // namespace detail

// A table lookup: this sits on the hot path of tape simplification.
constexpr int op_arity(Op op) { return detail::kArity[static_cast<std::uint8_t>(op)]; }

// Parses the text name of one of Fidget's opcodes (the engine's own have none in files);
// nullopt if unknown. Compares lengths first: it runs once per
// line of every expression file.
constexpr std::optional<Op> op_from_name(std::string_view s) {
#define FREP_X(name, id, text, arity) \
  if (s.size() == sizeof(text) - 1 && s[0] == text[0] && s == text) return Op::name;
  if (s.empty()) return std::nullopt;
  FREP_OPCODES(FREP_X)
#undef FREP_X
  return std::nullopt;
}

// Ops whose interval evaluation may pick one side, which makes them prunable.
constexpr bool op_is_choice(Op op) {
  return op == Op::Min || op == Op::Max || op == Op::And || op == Op::Or;
}

constexpr bool op_is_var(Op op) { return op == Op::VarX || op == Op::VarY || op == Op::VarZ; }

// Leaves other than constants: their values depend on the point.
constexpr bool op_is_input(Op op) { return op_is_var(op) || op == Op::Oracle; }

}  // namespace frep
