// Transforms as substitutions of x, y, z, composed where affine.
#include "frep/model/transform.hpp"

#include <algorithm>
#include <cmath>

#include "frep/expr/remap.hpp"
#include "frep/model/shapes.hpp"

namespace frep {
namespace {

// Rodrigues' matrix of a rotation by `radians` about the unit `axis` (right-handed), computed as
// nalgebra's Rotation3 from a scaled axis does, so that scripts match Fidget bit for bit.
Affine3 rotation(const Vec3& axis, double radians) {
  const Vec3 v{radians * axis.x, radians * axis.y, radians * axis.z};
  const double norm = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
  Affine3 r;
  if (!(norm > 0)) return r;
  const double ux = v.x / norm, uy = v.y / norm, uz = v.z / norm;
  const double s = std::sin(norm), c = std::cos(norm), t = 1 - c;
  r.m[0][0] = ux * ux + (1 - ux * ux) * c;
  r.m[0][1] = ux * uy * t - uz * s;
  r.m[0][2] = ux * uz * t + uy * s;
  r.m[1][0] = ux * uy * t + uz * s;
  r.m[1][1] = uy * uy + (1 - uy * uy) * c;
  r.m[1][2] = uy * uz * t - ux * s;
  r.m[2][0] = ux * uz * t - uy * s;
  r.m[2][1] = uy * uz * t + ux * s;
  r.m[2][2] = uz * uz + (1 - uz * uz) * c;
  return r;
}

}  // namespace

Field transform(const Field& f, const Affine3& m) {
  Graph& g = f.graph();
  NodeId src = f.id();
  Affine3 total = m;
  if (f.affine_source != kNoNode) {
    src = f.affine_source;
    total = f.affine * m;  // f(p) = src(N p), so f(m p) = src(N m p)
  }
  const NodeId r = remap_affine(g, src, total);
  Field out(g.expr(r), affine_info(f.info, m));
  if (r != src) {
    out.affine_source = src;
    out.affine = total;
  }
  return out;
}

Field move(const Field& f, const Vec3& offset) { return transform(f, Affine3::translation(-offset)); }

Field scale(const Field& f, const Vec3& s) {
  Affine3 m;
  for (int i = 0; i < 3; ++i) m.m[i][i] = 1.0 / s[i];
  return transform(f, m);
}

Field rotate(const Field& f, const Vec3& axis, double degrees, const Vec3& center) {
  // Moved by -center, rotated by -angle, moved back: three remaps, composed (Fidget's order).
  const Field moved = transform(f, Affine3::translation(center));
  const Field turned = transform(moved, rotation(axis, -(degrees * (3.14159265358979323846 / 180.0))));
  return transform(turned, Affine3::translation(-center));
}

Field reflect(const Field& f, const Vec3& axis, double offset) {
  // The shape at p - 2 d a, d = dot(a, p) - offset (Fidget's plane shape, then the mirror).
  Graph& g = f.graph();
  const Expr d = plane(g, axis, offset).expr;
  const Expr twice = 2.0f * d;
  Expr p[3] = {g.x(), g.y(), g.z()};
  for (int i = 0; i < 3; ++i)
    if (axis[i] != 0) p[i] = p[i] - (axis[i] == 1 ? twice : twice * static_cast<float>(axis[i]));
  return remap(f, p[0], p[1], p[2]);
}

Field revolve_y(const Field& f, double offset) {
  Graph& g = f.graph();
  const Field moved = transform(f, Affine3::translation({-offset, 0, 0}));
  const Expr x = g.x(), y = g.y();
  const Field revolved = remap(moved, sqrt(square(x) + square(y)), y, g.z());
  return transform(revolved, Affine3::translation({offset, 0, 0}));
}

namespace {
// The z = 0 section of f, cut to lower <= z <= upper.
Expr section(const Field& f) {
  Graph& g = f.graph();
  return g.expr(frep::remap(g, f.id(), g.var_x(), g.var_y(), g.constant(0)));
}
Expr slab_z(Graph& g, double lower, double upper) {
  const Expr z = g.z();
  return max(static_cast<float>(lower) - z, z - static_cast<float>(upper));
}
}  // namespace

// max(section, slab): the larger bound (the slab's is 1); the box's xy extent between lower and
// upper, growing as the section's does.
FieldInfo extruded_info(const FieldInfo& a, const FieldInfo& b, double lower, double upper) {
  FieldInfo r;
  r.lipschitz = a.lipschitz > 0 && b.lipschitz > 0 ? std::max({a.lipschitz, b.lipschitz, 1.0}) : 0.0;
  if (a.bounds.empty() || b.bounds.empty() || !(lower <= upper) || !std::isfinite(upper - lower)) return r;
  r.bounds = a.bounds;
  r.bounds.add(b.bounds);
  r.bounds.lo.z = lower;
  r.bounds.hi.z = upper;
  r.growth = std::min({a.growth, b.growth, Growth::Box});
  return r;
}

Field extrude_z(const Field& f, double lower, double upper) {
  Graph& g = f.graph();
  const Expr t = section(f);
  return Field(max(t, slab_z(g, lower, upper)), extruded_info(f.info, f.info, lower, upper));
}

Field loft_z(const Field& a, const Field& b, double lower, double upper) {
  Graph& g = a.graph();
  const Expr ta = section(a), tb = section(b);
  const Expr z = g.z();
  const Expr t = ((z - static_cast<float>(lower)) * tb + (static_cast<float>(upper) - z) * ta) /
                 g.c(static_cast<float>(upper - lower));
  // Between the two sections at every z (a convex combination), but its Lipschitz bound also
  // grows with |a - b| / (upper - lower): unknown.
  FieldInfo info = extruded_info(a.info, b.info, lower, upper);
  info.lipschitz = 0;
  return Field(max(t, slab_z(g, lower, upper)), info);
}

Field remap(const Field& f, Expr X, Expr Y, Expr Z) {
  Graph& g = f.graph();
  if (const auto m = affine_map(g, X.id(), Y.id(), Z.id())) {
    // As transform() would, but keeping the caller's X, Y, Z nodes (their rounding).
    return Field(g.expr(frep::remap(g, f.id(), X.id(), Y.id(), Z.id())), affine_info(f.info, *m));
  }
  return Field(g.expr(frep::remap(g, f.id(), X.id(), Y.id(), Z.id())));
}

}  // namespace frep
