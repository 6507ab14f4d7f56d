// The Rhai syntax tree: 20-byte nodes in an arena (child links are indices, lists live in one
// shared index array), so a statement costs a handful of small records and the arena of
// top-level statements can be cut back after each statement has run.
#pragma once

#include <bit>
#include <cstdint>
#include <vector>

namespace frep::rhai {

inline constexpr std::uint32_t kNone = 0xFFFFFFFFu;

enum class NK : std::uint8_t {
  // expressions
  Unit, True, False, Int, Float, Str, Var, Array, Map, Index, Prop, Call, Method, Unary, Binary, And, Or, Range,
  If, Block, While, Loop, DoWhile, For,
  // statements
  Let, Assign, Break, Continue, Return, Throw,
};

enum class BinOp : std::uint8_t { Add, Sub, Mul, Div, Rem, Pow, Shl, Shr, BitAnd, BitOr, BitXor, Eq, Ne, Lt, Le, Gt, Ge, In };
enum class UnOp : std::uint8_t { Neg, Plus, Not };

// Field use by kind:
//   Int/Float: a, b = the 64 bits          Str: a = string pool index       Var: a = symbol
//   Array: a = list, b = count             Map: a = list of (string index, value) pairs, b = pairs
//   Index: a = base, b = index             Prop: a = base, b = symbol
//   Call: a = symbol, b = list, c = count  Method: same, the receiver first in the list
//   Unary: op, a    Binary: op, a, b    And/Or: a, b    Range: a, b, flags 1 = inclusive
//   If: a = list of (condition, block) pairs, b = pairs, c = else block or kNone
//   Block: a = list, b = count    While: a = condition, b = body    Loop: a = body
//   DoWhile: a = body, b = condition, flags 1 = `until`
//   For: a = iterable, b = body, c = list of (variable, index variable or kNone)
//   Let: a = symbol, b = value or kNone, flags 1 = const
//   Assign: op = 0 for `=`, else 1 + BinOp; a = target, b = value
//   Break/Return/Throw: a = value or kNone
struct AstNode {
  NK kind;
  std::uint8_t op = 0;
  std::uint16_t flags = 0;
  std::uint32_t pos = 0;  // byte offset in the script, for error messages
  std::uint32_t a = kNone, b = kNone, c = kNone;
};
static_assert(sizeof(AstNode) == 20);

struct Ast {
  std::vector<AstNode> nodes;
  std::vector<std::uint32_t> lists;

  std::uint32_t add(const AstNode& n) {
    nodes.push_back(n);
    return static_cast<std::uint32_t>(nodes.size() - 1);
  }
  const AstNode& operator[](std::uint32_t i) const { return nodes[i]; }
  // Everything added after a mark can be dropped again.
  struct Mark {
    std::size_t nodes, lists;
  };
  Mark mark() const { return {nodes.size(), lists.size()}; }
  void truncate(Mark m) {
    nodes.resize(m.nodes);
    lists.resize(m.lists);
  }
};

inline void set_bits64(AstNode& n, std::uint64_t bits) {
  n.a = static_cast<std::uint32_t>(bits);
  n.b = static_cast<std::uint32_t>(bits >> 32);
}
inline std::uint64_t bits64(const AstNode& n) { return static_cast<std::uint64_t>(n.b) << 32 | n.a; }
inline std::int64_t int_of(const AstNode& n) { return static_cast<std::int64_t>(bits64(n)); }
inline double float_of(const AstNode& n) { return std::bit_cast<double>(bits64(n)); }

// A script function: `fn name(params) { body }`, its nodes in the functions' arena.
struct FnDef {
  std::uint32_t name;
  std::vector<std::uint32_t> params;
  std::uint32_t body;
  std::uint32_t pos;
};

}  // namespace frep::rhai
