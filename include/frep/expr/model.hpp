// A graph together with the node that is the shape: what files load into.
#pragma once

#include <memory>

#include "frep/expr/expr.hpp"
#include "frep/expr/graph.hpp"

namespace frep {

struct Model {
  std::unique_ptr<Graph> graph = std::make_unique<Graph>();  // owns the nodes
  NodeId root = kNoNode;                                      // the expression's value
  // A known bound L on |f(p) - f(q)| / |p - q|, or 0 if unknown. 1 for exact distances (what
  // frep convert writes): renderers and meshers then settle boxes from a single value at their
  // centre. Files keep it (.frep in its flags, .vm and .rhai in a `frep: lipschitz L` comment).
  double lipschitz = 0;

  Expr root_expr() const { return Expr(*graph, root); }
};

}  // namespace frep
