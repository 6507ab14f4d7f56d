// remap and affine maps of expressions.
#include "frep/expr/remap.hpp"

#include <algorithm>
#include <array>
#include <unordered_map>
#include <vector>

#include "frep/error.hpp"
#include "frep/expr/oracle.hpp"

namespace frep {

NodeId remap(Graph& g, NodeId e, NodeId X, NodeId Y, NodeId Z, const std::function<void(std::size_t)>& before_copy) {
  if (X == g.var_x() && Y == g.var_y() && Z == g.var_z()) return e;
  // The nodes reachable from e, then rebuilt in increasing id order (arguments first).
  std::unordered_map<NodeId, NodeId> map;
  std::vector<NodeId> order, stack{e};
  map.emplace(e, kNoNode);
  while (!stack.empty()) {
    const NodeId n = stack.back();
    stack.pop_back();
    order.push_back(n);
    const Node& nd = g.node(n);
    const int ar = op_arity(nd.op);
    if (ar > 0 && map.emplace(nd.a, kNoNode).second) stack.push_back(nd.a);
    if (ar > 1 && map.emplace(nd.b, kNoNode).second) stack.push_back(nd.b);
  }
  if (before_copy) before_copy(order.size());
  std::sort(order.begin(), order.end());
  std::optional<std::optional<Affine3>> affine;  // found at the first oracle
  for (NodeId n : order) {
    const Node nd = g.node(n);
    NodeId r;
    switch (nd.op) {
      case Op::VarX: r = X; break;
      case Op::VarY: r = Y; break;
      case Op::VarZ: r = Z; break;
      case Op::Const: r = n; break;
      case Op::Oracle: {
        if (!affine) affine = affine_map(g, X, Y, Z);
        if (!*affine)
          throw InputError("", 0,
                           g.oracle_of(nd).describe() +
                               " can only be remapped by an affine map (moved, scaled, rotated, mirrored): its x, y "
                               "and z must be sums of multiples of x, y, z and constants");
        r = g.oracle(g.oracle_of(nd).transformed(**affine));
        break;
      }
      default:
        r = op_arity(nd.op) == 1 ? g.unary(nd.op, map[nd.a]) : g.binary(nd.op, map[nd.a], map[nd.b]);
    }
    map[n] = r;
  }
  return map[e];
}

std::optional<Affine3> affine_map(const Graph& g, NodeId X, NodeId Y, NodeId Z) {
  // Coefficients of x, y, z and the constant, per node, for the nodes reachable from X, Y, Z.
  using Row = std::array<double, 4>;
  std::unordered_map<NodeId, Row> rows;
  const NodeId roots[3] = {X, Y, Z};
  for (NodeId root : roots) {
    for (NodeId n : reachable_nodes(g, root)) {
      if (rows.count(n)) continue;
      const Node& nd = g.node(n);
      Row r{0, 0, 0, 0};
      const auto arg = [&](NodeId a) -> const Row& { return rows.at(a); };
      const auto constant = [](const Row& v) { return v[0] == 0 && v[1] == 0 && v[2] == 0; };
      switch (nd.op) {
        case Op::VarX: r[0] = 1; break;
        case Op::VarY: r[1] = 1; break;
        case Op::VarZ: r[2] = 1; break;
        case Op::Const: r[3] = nd.value; break;
        case Op::Neg:
          for (int k = 0; k < 4; ++k) r[static_cast<std::size_t>(k)] = -arg(nd.a)[static_cast<std::size_t>(k)];
          break;
        case Op::Add:
        case Op::Sub: {
          const Row &a = arg(nd.a), &b = arg(nd.b);
          const double s = nd.op == Op::Add ? 1 : -1;
          for (std::size_t k = 0; k < 4; ++k) r[k] = a[k] + s * b[k];
          break;
        }
        case Op::Mul: {
          const Row &a = arg(nd.a), &b = arg(nd.b);
          if (constant(a)) {
            for (std::size_t k = 0; k < 4; ++k) r[k] = a[3] * b[k];
          } else if (constant(b)) {
            for (std::size_t k = 0; k < 4; ++k) r[k] = b[3] * a[k];
          } else {
            return std::nullopt;
          }
          break;
        }
        case Op::Div: {
          const Row &a = arg(nd.a), &b = arg(nd.b);
          if (!constant(b) || b[3] == 0) return std::nullopt;
          for (std::size_t k = 0; k < 4; ++k) r[k] = a[k] / b[3];
          break;
        }
        default:
          return std::nullopt;
      }
      for (double v : r)
        if (!std::isfinite(v)) return std::nullopt;
      rows.emplace(n, r);
    }
  }
  Affine3 a;
  for (int i = 0; i < 3; ++i) {
    const Row& r = rows.at(roots[i]);
    for (int k = 0; k < 4; ++k) a.m[i][k] = r[static_cast<std::size_t>(k)];
  }
  return a;
}

NodeId affine_row(Graph& g, const Affine3& a, int row) {
  const NodeId vars[3] = {g.var_x(), g.var_y(), g.var_z()};
  const auto term = [&](int k) -> NodeId {
    const double c = a.m[row][k];
    if (c == 0) return kNoNode;
    if (c == 1) return vars[k];
    return g.binary(Op::Mul, g.constant(static_cast<float>(c)), vars[k]);
  };
  const auto sum = [&](NodeId p, NodeId q) -> NodeId {
    if (p == kNoNode) return q;
    if (q == kNoNode) return p;
    return g.binary(Op::Add, p, q);
  };
  const double d = a.m[row][3];
  const NodeId r = sum(sum(term(0), term(1)), sum(term(2), d == 0 ? kNoNode : g.constant(static_cast<float>(d))));
  return r == kNoNode ? g.constant(0) : r;
}

NodeId remap_affine(Graph& g, NodeId e, const Affine3& a) {
  return remap(g, e, affine_row(g, a, 0), affine_row(g, a, 1), affine_row(g, a, 2));
}

}  // namespace frep
