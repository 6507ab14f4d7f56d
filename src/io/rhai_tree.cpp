// Tree-building helpers of the Rhai interpreter: Fidget's value-to-tree conversion, balanced
// unions, substitution of x, y, z (remap) and affine remapping with Fidget's composition.
#include <algorithm>
#include <cmath>
#include <limits>

#include "frep/expr/remap.hpp"
#include "io/rhai_interp.hpp"

namespace frep::rhai {

NodeId Interp::to_expr(const Value& v, std::uint32_t pos, const std::string& what) {
  switch (v.kind()) {
    case Kind::Expr: return v.node();
    case Kind::Int:
    case Kind::Float: return constant(v.number());
    case Kind::Array: {  // Fidget: an array of trees is their union
      charge(v.as<ArrayObj>().items.size());
      std::vector<NodeId> items;
      for (const Value& e : v.as<ArrayObj>().items) items.push_back(to_expr(e, pos, what));
      return reduce(Op::Min, items);
    }
    case Kind::Plane: {
      const PlaneObj& p = v.as<PlaneObj>();
      // Fidget: x * a.x + y * a.y + z * a.z - offset, with its builder's simplifications.
      NodeId t = kNoNode;
      for (int i = 0; i < 3; ++i) {
        if (p.axis[i] == 0) continue;
        const NodeId term = p.axis[i] == 1 ? axes_[i] : binary(Op::Mul, axes_[i], constant(p.axis[i]));
        t = t == kNoNode ? term : binary(Op::Add, t, term);
      }
      if (t == kNoNode) t = constant(0);
      if (p.offset != 0) t = binary(Op::Sub, t, constant(p.offset));
      return t;
    }
    default:
      fail(pos, "expected an expression (a number, x, y, z or a shape) for " + what + ", got " + type_name(v));
  }
}

NodeId Interp::reduce(Op op, std::span<const NodeId> items) {
  charge(items.size() / 2);  // over the recursion: n log n / 2 in all, an upper bound of the work
  if (items.empty())
    return constant(op == Op::Min ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity());
  if (items.size() == 1) return items[0];
  const std::size_t half = items.size() / 2;
  const NodeId a = reduce(op, items.first(half));  // depth log2(n)
  const NodeId b = reduce(op, items.subspan(half));
  return binary(op, a, b);
}

NodeId Interp::remap(NodeId e, NodeId x, NodeId y, NodeId z) {
  return frep::remap(g_, e, x, y, z, [&](std::size_t nodes) {
    charge(nodes);
    // The copy may add as many nodes as it visits: stop before building what the limit refuses.
    check_nodes(nodes);
  });
}

NodeId Interp::linear(const double c[3], double d) {
  // Fidget lowers one row of an affine map as (c0*x + c1*y) + (c2*z + d); its builder drops
  // products with 0, multiplications by 1 and additions of 0.
  auto term = [&](double k, NodeId v) -> NodeId {
    if (k == 0) return kNoNode;
    if (k == 1) return v;
    return binary(Op::Mul, constant(k), v);
  };
  auto sum = [&](NodeId a, NodeId b) -> NodeId {
    if (a == kNoNode) return b;
    if (b == kNoNode) return a;
    return binary(Op::Add, a, b);
  };
  const NodeId ab = sum(term(c[0], axes_[0]), term(c[1], axes_[1]));
  const NodeId cd = sum(term(c[2], axes_[2]), d == 0 ? kNoNode : constant(d));
  const NodeId r = sum(ab, cd);
  return r == kNoNode ? constant(0) : r;
}

NodeId Interp::remap_affine(NodeId e, const Affine& m) {
  NodeId src = e;
  Affine total = m;
  if (auto it = affine_of_.find(e); it != affine_of_.end()) {
    src = it->second.first;
    total = it->second.second * m;  // e(p) = src(N p), so e(M p) = src(N M p)
  }
  NodeId coords[3];
  for (int i = 0; i < 3; ++i) {
    const double c[3] = {total.m[i][0], total.m[i][1], total.m[i][2]};
    coords[i] = linear(c, total.m[i][3]);
  }
  const NodeId r = remap(src, coords[0], coords[1], coords[2]);
  if (r != src) affine_of_[r] = {src, total};
  return r;
}

}  // namespace frep::rhai
