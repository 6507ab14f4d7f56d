// Substituting x, y and z: f(x, y, z) -> f(X, Y, Z), the one implementation behind moving,
// scaling, rotating and every other remap of an expression.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>

#include "frep/expr/graph.hpp"
#include "frep/math/affine.hpp"

namespace frep {

// Copies the nodes reachable from `e` with x, y, z replaced by the nodes X, Y, Z (iterative; the
// copy is hash-consed, so what does not depend on x, y, z is shared, not copied). Oracle leaves
// are composed with the substitution (Oracle::transformed) when X, Y, Z are affine in x, y, z
// (affine_map); otherwise an expression holding an oracle cannot be remapped: InputError.
// `before_copy`, if given, is called with the number of nodes about to be copied, before any is
// (a caller's budget check may throw there).
NodeId remap(Graph& g, NodeId e, NodeId X, NodeId Y, NodeId Z,
             const std::function<void(std::size_t)>& before_copy = {});

// The map p -> (X(p), Y(p), Z(p)) if X, Y and Z are affine in x, y, z: built from x, y, z and
// constants by addition, subtraction, negation, and products and quotients by constants (as
// move, scale and rotate write them). Otherwise nullopt.
std::optional<Affine3> affine_map(const Graph& g, NodeId X, NodeId Y, NodeId Z);

// Row `row` of `a` as an expression, m[row][0] x + m[row][1] y + m[row][2] z + m[row][3], with
// the coefficients rounded to float, in Fidget's lowering: (c0 x + c1 y) + (c2 z + d), dropping
// zero terms, unit factors and a zero constant.
NodeId affine_row(Graph& g, const Affine3& a, int row);

// remap(g, e, rows of a): f(a(p)).
NodeId remap_affine(Graph& g, NodeId e, const Affine3& a);

}  // namespace frep
