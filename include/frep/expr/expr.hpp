// A value-type handle to a node of a Graph, with operators so that C++ reads like math:
//   frep::Graph g; auto x = g.x(), y = g.y();
//   auto box = max(abs(x) - 1, abs(y) - 1);
// The handle does not own the graph; the graph must outlive it.
#pragma once

#include <stdexcept>
#include <string>

#include "frep/error.hpp"
#include "frep/expr/graph.hpp"

namespace frep {

class Expr {
 public:
  Expr(Graph& g, NodeId id) : g_(&g), id_(id) {}
  Graph& graph() const { return *g_; }
  NodeId id() const { return id_; }
  const Node& node() const { return g_->node(id_); }

 private:
  Graph* g_;
  NodeId id_;
};

namespace detail {
inline Expr un(Op op, Expr a) { return Expr(a.graph(), a.graph().unary(op, a.id())); }
inline Expr bin(Op op, Expr a, Expr b) {
  if (&a.graph() != &b.graph())
    throw std::invalid_argument(std::string("frep: ") + std::string(op_name(op)) +
                                " of expressions from two different graphs (build both in one frep::Graph)");
  return Expr(a.graph(), a.graph().binary(op, a.id(), b.id()));
}
inline Expr lift(Expr like, float v) { return like.graph().c(v); }
}  // namespace detail

#define FREP_BINARY_OPERATOR(sym, OP)                                                        \
  inline Expr operator sym(Expr a, Expr b) { return detail::bin(Op::OP, a, b); }              \
  inline Expr operator sym(Expr a, float b) { return detail::bin(Op::OP, a, detail::lift(a, b)); } \
  inline Expr operator sym(float a, Expr b) { return detail::bin(Op::OP, detail::lift(b, a), b); }
FREP_BINARY_OPERATOR(+, Add)
FREP_BINARY_OPERATOR(-, Sub)
FREP_BINARY_OPERATOR(*, Mul)
FREP_BINARY_OPERATOR(/, Div)
#undef FREP_BINARY_OPERATOR

inline Expr operator-(Expr a) { return detail::un(Op::Neg, a); }

#define FREP_BINARY_FUNCTION(fn, OP)                                                    \
  inline Expr fn(Expr a, Expr b) { return detail::bin(Op::OP, a, b); }                   \
  inline Expr fn(Expr a, float b) { return detail::bin(Op::OP, a, detail::lift(a, b)); } \
  inline Expr fn(float a, Expr b) { return detail::bin(Op::OP, detail::lift(b, a), b); }
FREP_BINARY_FUNCTION(min, Min)
FREP_BINARY_FUNCTION(max, Max)
FREP_BINARY_FUNCTION(atan2, Atan2)
FREP_BINARY_FUNCTION(compare, Compare)
FREP_BINARY_FUNCTION(mod, Mod)
FREP_BINARY_FUNCTION(logical_and, And)
FREP_BINARY_FUNCTION(logical_or, Or)
#undef FREP_BINARY_FUNCTION

#define FREP_UNARY_FUNCTION(fn, OP) \
  inline Expr fn(Expr a) { return detail::un(Op::OP, a); }
FREP_UNARY_FUNCTION(abs, Abs)
FREP_UNARY_FUNCTION(recip, Recip)
FREP_UNARY_FUNCTION(sqrt, Sqrt)
FREP_UNARY_FUNCTION(square, Square)
FREP_UNARY_FUNCTION(floor, Floor)
FREP_UNARY_FUNCTION(ceil, Ceil)
FREP_UNARY_FUNCTION(round, Round)
FREP_UNARY_FUNCTION(sin, Sin)
FREP_UNARY_FUNCTION(cos, Cos)
FREP_UNARY_FUNCTION(tan, Tan)
FREP_UNARY_FUNCTION(asin, Asin)
FREP_UNARY_FUNCTION(acos, Acos)
FREP_UNARY_FUNCTION(atan, Atan)
FREP_UNARY_FUNCTION(exp, Exp)
FREP_UNARY_FUNCTION(ln, Ln)
FREP_UNARY_FUNCTION(logical_not, Not)
#undef FREP_UNARY_FUNCTION

// if_nonzero_else(c, a, b) = c != 0 ? a : b (NaN counts as non-zero), from and/not and an add:
// exactly one side is non-zero-able, so the sum is the chosen side (a -0 side becomes +0), and the
// gradient is the chosen side's even where that side is exactly 0 (an or-based select would fall
// through to the other side's constant 0 there, with a zero gradient on the surface).
inline Expr if_nonzero_else(Expr c, Expr a, Expr b) { return logical_and(c, a) + logical_and(logical_not(c), b); }

}  // namespace frep
