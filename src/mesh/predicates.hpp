// Exact geometric predicates on double coordinates: a floating-point filter first, and exact
// expansion arithmetic (error-free sums and products) when the filter cannot decide. Used
// wherever a wrong sign would give a wrong answer (self-intersections), not for distances.
#pragma once

#include "frep/math/vec.hpp"

namespace frep::exact {

// Sign (-1, 0, +1) of ((b - a) x (c - a)) . (d - a): positive when d lies on the side that
// triangle abc's right-hand normal points to.
int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// Sign of (b - a) x (c - a) in the plane: positive for a counter-clockwise turn.
int orient2d(double ax, double ay, double bx, double by, double cx, double cy);

}  // namespace frep::exact
