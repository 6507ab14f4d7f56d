// A graph together with the node that is the shape: what files load into.
#pragma once

#include <memory>

#include "frep/expr/expr.hpp"
#include "frep/expr/graph.hpp"

namespace frep {

struct Model {
  std::unique_ptr<Graph> graph = std::make_unique<Graph>();  // owns the nodes
  NodeId root = kNoNode;                                      // the expression's value

  Expr root_expr() const { return Expr(*graph, root); }
};

}  // namespace frep
