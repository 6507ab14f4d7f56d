// Primitive shapes, formula for formula as Fidget's shape library.
#include "frep/model/shapes.hpp"

#include <cmath>

namespace frep {
namespace {

NodeId c(Graph& g, double v) { return g.constant(static_cast<float>(v)); }
NodeId var(Graph& g, int axis) { return axis == 0 ? g.var_x() : axis == 1 ? g.var_y() : g.var_z(); }

// max over `dims` axes of max(lower - p, p - upper).
NodeId slabs(Graph& g, const Vec3& lower, const Vec3& upper, int dims) {
  NodeId r = kNoNode;
  for (int i = 0; i < dims; ++i) {
    const NodeId p = var(g, i);
    const NodeId below = g.binary(Op::Sub, c(g, lower[i]), p);
    const NodeId above = g.binary(Op::Sub, p, c(g, upper[i]));
    const NodeId side = g.binary(Op::Max, below, above);
    r = r == kNoNode ? side : g.binary(Op::Max, r, side);
  }
  return r;
}

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

Field sphere(Graph& g, const Vec3& center, double radius) {
  NodeId d[3];
  for (int i = 0; i < 3; ++i) d[i] = g.unary(Op::Square, g.binary(Op::Sub, var(g, i), c(g, center[i])));
  const NodeId len = g.unary(Op::Sqrt, g.binary(Op::Add, g.binary(Op::Add, d[0], d[1]), d[2]));
  FieldInfo info;
  info.lipschitz = 1;
  if (radius > 0 && finite(center) && std::isfinite(radius)) {
    info.bounds = Box3{center, center}.inflated(radius);
    info.growth = Growth::Distance;
  }
  return Field(g.expr(g.binary(Op::Sub, len, c(g, radius))), info);
}

Field box(Graph& g, const Vec3& lower, const Vec3& upper) {
  FieldInfo info;
  info.lipschitz = 1;
  const Box3 b{lower, upper};
  if (!b.empty() && finite(lower) && finite(upper)) {
    info.bounds = b;
    info.growth = Growth::Box;
  }
  return Field(g.expr(slabs(g, lower, upper, 3)), info);
}

Field circle(Graph& g, double cx, double cy, double radius) {
  const NodeId dx = g.binary(Op::Sub, g.var_x(), c(g, cx));
  const NodeId dy = g.binary(Op::Sub, g.var_y(), c(g, cy));
  const NodeId len = g.unary(Op::Sqrt, g.binary(Op::Add, g.unary(Op::Square, dx), g.unary(Op::Square, dy)));
  FieldInfo info;
  info.lipschitz = 1;
  return Field(g.expr(g.binary(Op::Sub, len, c(g, radius))), info);
}

Field rectangle(Graph& g, double x0, double y0, double x1, double y1) {
  FieldInfo info;
  info.lipschitz = 1;
  return Field(g.expr(slabs(g, {x0, y0, 0}, {x1, y1, 0}, 2)), info);
}

Field plane(Graph& g, const Vec3& axis, double offset) {
  // Fidget: x a.x + y a.y + z a.z - offset, without products by 0 or 1.
  NodeId t = kNoNode;
  for (int i = 0; i < 3; ++i) {
    if (axis[i] == 0) continue;
    const NodeId term = axis[i] == 1 ? var(g, i) : g.binary(Op::Mul, var(g, i), c(g, axis[i]));
    t = t == kNoNode ? term : g.binary(Op::Add, t, term);
  }
  if (t == kNoNode) t = c(g, 0);
  if (offset != 0) t = g.binary(Op::Sub, t, c(g, offset));
  FieldInfo info;
  const double len = std::sqrt(axis.x * axis.x + axis.y * axis.y + axis.z * axis.z);
  if (std::isfinite(len)) info.lipschitz = len * (1 + 1e-6);  // room for the f32 rounding of the axis
  return Field(g.expr(t), info);
}

}  // namespace frep
