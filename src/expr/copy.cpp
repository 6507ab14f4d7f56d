// copy_expression, has_oracles, expand_oracles.
#include "frep/expr/copy.hpp"

#include <vector>

#include "frep/expr/oracle.hpp"

namespace frep {

NodeId copy_expression(Graph& to, const Graph& from, NodeId root, OracleCopy oracles) {
  const std::vector<NodeId> order = reachable_nodes(from, root);
  std::vector<NodeId> id(root + 1, kNoNode);
  for (NodeId n : order) {
    const Node& node = from.node(n);
    if (node.op == Op::Oracle) {
      const auto& o = from.oracles()[oracle_index(node.value)];
      id[n] = oracles == OracleCopy::Keep ? to.oracle(o) : o->closed_form(to);
      continue;
    }
    id[n] = to.make(node.op, node.a == kNoNode ? kNoNode : id[node.a], node.b == kNoNode ? kNoNode : id[node.b],
                    node.value);
  }
  return id[root];
}

bool has_oracles(const Graph& g, NodeId root) {
  if (g.oracles().empty()) return false;
  for (NodeId n : reachable_nodes(g, root))
    if (g.node(n).op == Op::Oracle) return true;
  return false;
}

Model expand_oracles(const Graph& g, NodeId root, const FieldInfo& info) {
  Model m;
  m.root = copy_expression(*m.graph, g, root, OracleCopy::ClosedForm);
  m.info = info;
  return m;
}

}  // namespace frep
