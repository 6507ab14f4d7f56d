// Copying an expression from one graph into another, keeping its oracles or replacing them by
// their closed forms (what file writers and exports need: other tools know no oracles).
#pragma once

#include "frep/expr/graph.hpp"
#include "frep/expr/model.hpp"

namespace frep {

enum class OracleCopy {
  Keep,        // the copy shares the same oracle objects
  ClosedForm,  // each oracle becomes its closed form (Oracle::closed_form), built in the copy
};

// Copies the expression `root` of `from` into `to` (node by node, in order; hash-consing shares
// what `to` already has) and returns its id there.
NodeId copy_expression(Graph& to, const Graph& from, NodeId root, OracleCopy oracles = OracleCopy::Keep);

// Whether an oracle is reachable from `root`.
bool has_oracles(const Graph& g, NodeId root);

// `root` of `g` with every oracle replaced by its closed form, in a new graph (`info` kept).
Model expand_oracles(const Graph& g, NodeId root, const FieldInfo& info = {});

}  // namespace frep
