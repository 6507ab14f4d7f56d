// Symbolic gradients: d/dx, d/dy, d/dz of an expression, built as expressions in the same graph,
// so that they can be evaluated by every evaluator, pruned, and written to `.vm` like any field.
//
// Conventions where the derivative does not exist are those of GradEvaluator (evaluators.hpp),
// written with frep opcodes only: min/max/and/or take the derivative of the side they return
// (a select built from compare/and/or/not); abs'(0) = +1; sqrt'(0) = 0, so |p - a| has gradient 0
// exactly on the point or edge it measures to; floor/ceil/round/compare/not have derivative 0.
// The formulas mirror the evaluator's operation by operation (same f32 operations in the same
// order), so the symbolic gradient, compiled and evaluated, equals GradEvaluator's result bit for
// bit (up to the sign of zero) wherever the latter is finite at a finite point: the float
// tolerance is zero (tests/expr/derivative_test.cpp). Where an intermediate value or the
// evaluator's gradient is infinite or NaN they may differ: a dropped zero term skips an
// `inf * 0` (the symbolic d/dy of 1/x is 0 at x = 1e-30, the evaluator's NaN), and a NaN
// argument of min/max gives the evaluator NaN but the symbolic select one side's derivative.
// Zero partials times derivatives that may blow up (after recip, div, ln, asin, acos, atan2,
// mod) are guarded as in the evaluator: and(p, p * d).
#pragma once

#include <cstdint>
#include <vector>

#include "frep/expr/expr.hpp"

namespace frep {

// The three partial derivatives of a field.
struct Gradient {
  Expr x, y, z;
};

// Builds gradients and remembers every node's derivatives, so that gradients of expressions that
// share subexpressions cost only their new nodes: a DAG costs O(nodes), never a tree expansion.
// Iterative (no recursion), for graphs of millions of nodes. The graph must outlive this object.
class Differentiator {
 public:
  explicit Differentiator(Graph& g) : g_(&g) {}

  Gradient grad(Expr e);
  Gradient grad(NodeId id) { return grad(Expr(*g_, id)); }

 private:
  struct Entry {
    NodeId d[3] = {kNoNode, kNoNode, kNoNode};
    // The derivative may be infinite or NaN where every value is finite (after recip, div, ln,
    // asin, acos, atan2 or mod): multiplying it by a partial that may be zero needs a guard.
    bool wild = false;
  };
  void compute(NodeId id);

  Graph* g_;
  std::vector<Entry> memo_;  // indexed by node id; d[0] == kNoNode = not computed yet
};

// One-shot: the gradient of `e` (a fresh Differentiator; use one object for many related calls).
Gradient grad(Expr e);

// a.x*b.x + a.y*b.y + a.z*b.z, with zero components dropped: for unit-gradient fields A and B,
// dot(grad(A), grad(B)) is the cosine of the angle between their normals.
Expr dot(const Gradient& a, const Gradient& b);
// The gradient's length, sqrt(dot(g, g)).
Expr length(const Gradient& g);
// dot(grad(a), grad(b)) with one Differentiator shared by both.
Expr grad_dot(Expr a, Expr b);

}  // namespace frep
