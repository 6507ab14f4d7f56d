// A graph together with the node that is the shape: what files load into.
#pragma once

#include <cstdint>
#include <memory>

#include "frep/expr/expr.hpp"
#include "frep/expr/graph.hpp"
#include "frep/math/vec.hpp"

namespace frep {

// How far below-zero-or-small values can reach beyond FieldInfo::bounds: what lets an offset
// or a shell grow the box by its distance instead of forgetting it.
enum class Growth : std::uint8_t {
  Unknown,   // nothing known beyond the box itself
  Box,       // for every t >= 0, every point where f < t lies in bounds.inflated(t)
  Distance,  // moreover f(p) >= the distance from p to the inside at every point outside it
             // (exact signed distances, and their unions, offsets and rigid motions)
};

// What is known about a field beyond its expression. Every expression file keeps it: .frep in
// its header, .vm and .rhai in leading `frep:` comments (which Fidget ignores).
struct FieldInfo {
  // A bound L on |f(p) - f(q)| / |p - q|, or 0 if unknown. 1 for exact distances (what frep
  // convert writes): renderers and meshers then settle boxes from a single value at their centre.
  double lipschitz = 0;
  // A box holding every point where the field is negative (a converted mesh's bounding box), or
  // empty if unknown: the default region to render, mesh and sample.
  Box3 bounds;
  // How the region where f is small grows beyond `bounds` (Unknown when bounds are).
  Growth growth = Growth::Unknown;
};

struct Model {
  std::unique_ptr<Graph> graph = std::make_unique<Graph>();  // owns the nodes
  NodeId root = kNoNode;                                      // the expression's value
  FieldInfo info;                                             // what else is known about it

  Expr root_expr() const { return Expr(*graph, root); }
};

}  // namespace frep
