// A graph together with the node that is the shape: what files load into.
#pragma once

#include <memory>

#include "frep/expr/expr.hpp"
#include "frep/expr/graph.hpp"
#include "frep/math/vec.hpp"

namespace frep {

// What is known about a field beyond its expression. Every expression file keeps it: .frep in
// its header, .vm and .rhai in leading `frep:` comments (which Fidget ignores).
struct FieldInfo {
  // A bound L on |f(p) - f(q)| / |p - q|, or 0 if unknown. 1 for exact distances (what frep
  // convert writes): renderers and meshers then settle boxes from a single value at their centre.
  double lipschitz = 0;
  // A box holding every point where the field is negative (a converted mesh's bounding box), or
  // empty if unknown: the default region to render, mesh and sample.
  Box3 bounds;
};

struct Model {
  std::unique_ptr<Graph> graph = std::make_unique<Graph>();  // owns the nodes
  NodeId root = kNoNode;                                      // the expression's value
  FieldInfo info;                                             // what else is known about it

  Expr root_expr() const { return Expr(*graph, root); }
};

}  // namespace frep
