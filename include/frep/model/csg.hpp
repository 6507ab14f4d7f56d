// Boolean combinations of fields with Fidget's shape library's formulas (min, max, negation,
// the quadratic smooth union), carrying the facts (FieldInfo). For the exact and chamfered
// booleans of unit gradient fields see frep/ugf/boolean.hpp and chamfer.hpp.
#pragma once

#include <span>

#include "frep/model/field.hpp"

namespace frep {

// min(a, b) and max(a, b), and max(a, -b). Both fields must live in the same Graph (copy one
// over with copy_expression, frep/expr/copy.hpp).
Field unite(const Field& a, const Field& b);
Field intersect(const Field& a, const Field& b);
Field subtract(const Field& a, const Field& b);
// -a: the complement.
Field inverse(const Field& a);
// Any number of fields as a balanced tree of min (max): depth log2(n), as Fidget builds them.
// No fields: +inf (-inf), the empty (full) shape.
Field union_of(Graph& g, std::span<const Field> fields);
Field intersection_of(Graph& g, std::span<const Field> fields);
// min(a, b) - max(radius - |a - b|, 0)^2 / (4 radius), Fidget's blend (Quilez's quadratic smooth
// minimum); min(a, b) for radius <= 0. Its gradient is a convex combination of a's and b's.
Field blend(const Field& a, const Field& b, double radius);

}  // namespace frep
