// Tree-building helpers of the Rhai interpreter: Fidget's value-to-tree conversion, and the
// bridge to the modeling library (frep/model/*.hpp): the facts it records for each node built.
#include <algorithm>
#include <cmath>
#include <limits>

#include "frep/model/csg.hpp"
#include "frep/model/shapes.hpp"
#include "frep/model/transform.hpp"
#include "rhai_interp.hpp"

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
      return keep(frep::plane(g_, {p.axis[0], p.axis[1], p.axis[2]}, p.offset));
    }
    default:
      fail(pos, "expected an expression (a number, x, y, z or a shape) for " + what + ", got " + type_name(v));
  }
}

NodeId Interp::reduce(Op op, std::span<const NodeId> items) {
  charge(items.size() / 2);  // over the recursion: n log n / 2 in all, an upper bound of the work
  std::vector<Field> fields;
  fields.reserve(items.size());
  for (NodeId id : items) fields.push_back(field(id));
  return keep(op == Op::Min ? union_of(g_, fields) : intersection_of(g_, fields));
}

NodeId Interp::remap(NodeId e, NodeId x, NodeId y, NodeId z) {
  const Field f = field(e);
  charge_remap(e);
  return keep(frep::remap(f, g_.expr(x), g_.expr(y), g_.expr(z)));
}

void Interp::charge_remap(NodeId copied) {
  // A remap copies at most the nodes reachable from what it remaps.
  const std::size_t nodes = reachable_nodes(g_, copied).size();
  charge(nodes);
  check_nodes(nodes);
}

Field Interp::field(NodeId id) const {
  Field f(g_.expr(id));
  if (auto it = facts_.find(id); it != facts_.end()) {
    f.info = it->second.info;
    f.affine_source = it->second.affine_source;
    f.affine = it->second.affine;
  }
  return f;
}

NodeId Interp::keep(const Field& f) {
  const bool known = f.info.lipschitz > 0 || !f.info.bounds.empty() || f.affine_source != kNoNode;
  // The same node built twice (hash-consing) keeps the facts found first: both are true.
  if (known) facts_.try_emplace(f.id(), Facts{f.info, f.affine_source, f.affine});
  return f.id();
}

}  // namespace frep::rhai
