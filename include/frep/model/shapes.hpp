// Primitive shapes as fields, in the forms Fidget's shape library writes them (so a script and
// the same C++ build the same expression), each with its facts (FieldInfo).
#pragma once

#include "frep/math/vec.hpp"
#include "frep/model/field.hpp"

namespace frep {

// |p - center| - radius: the exact signed distance (Lipschitz 1, its box, Growth::Distance).
Field sphere(Graph& g, const Vec3& center, double radius);
// The box [lower, upper] as the max over axes of max(lower - p, p - upper): exact inside and on
// the faces' normal prisms, an underestimate near edges and corners outside (Lipschitz 1,
// Growth::Box: where it is below t is exactly the box grown by t).
Field box(Graph& g, const Vec3& lower, const Vec3& upper);
// sqrt((x - cx)^2 + (y - cy)^2) - radius: a disc in the xy plane, an infinite cylinder along z.
Field circle(Graph& g, double cx, double cy, double radius);
// The rectangle [x0, x1] x [y0, y1] in the xy plane (infinite along z), as box() writes it.
Field rectangle(Graph& g, double x0, double y0, double x1, double y1);
// dot(axis, p) - offset, Fidget's plane shape: negative on the side opposite the axis. With a
// unit axis, the signed distance to the plane.
Field plane(Graph& g, const Vec3& axis, double offset);

}  // namespace frep
