// An independent signed distance to a triangle mesh, to check the library's against: the
// distance to every triangle in turn (inside the triangle's prism, the distance to its plane;
// else to the nearest of its three edges), and the sign from the winding number, the sum of the
// solid angles every triangle subtends at the point over 4 pi (inside where it exceeds 1/2). Off
// a closed surface the winding number is an integer, which the double sum (accurate to about
// 1e-12) rounds to; near an open mesh's hole it is the generalized winding number, as the
// library's `SignMethod::WindingNumber` defines it. Nothing of MeshDistance (no hierarchy, no
// pseudonormals, no far-field approximation) is used: O(triangles) per point, for small meshes.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "frep/mesh/mesh.hpp"

namespace frep::test {

inline double bf_dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 bf_cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline double bf_norm(Vec3 a) { return std::sqrt(bf_dot(a, a)); }

// Squared distance from p to the segment ab.
inline double bf_segment_distance2(Vec3 p, Vec3 a, Vec3 b) {
  const Vec3 ab = b - a, ap = p - a;
  const double len2 = bf_dot(ab, ab);
  const double t = len2 > 0 ? std::clamp(bf_dot(ap, ab) / len2, 0.0, 1.0) : 0.0;
  const Vec3 d = ap - ab * t;
  return bf_dot(d, d);
}

// Squared distance from p to the closed triangle abc (any shape, flat ones included).
inline double bf_triangle_distance2(Vec3 p, Vec3 a, Vec3 b, Vec3 c) {
  const Vec3 n = bf_cross(b - a, c - a);
  const double n2 = bf_dot(n, n);
  if (n2 > 0) {
    // Inside the prism over the triangle: p is on the inner side of the three edge planes.
    const bool inside = bf_dot(bf_cross(b - a, p - a), n) >= 0 && bf_dot(bf_cross(c - b, p - b), n) >= 0 &&
                        bf_dot(bf_cross(a - c, p - c), n) >= 0;
    if (inside) {
      const double h = bf_dot(p - a, n);
      return h * h / n2;
    }
  }
  return std::min({bf_segment_distance2(p, a, b), bf_segment_distance2(p, b, c), bf_segment_distance2(p, c, a)});
}

// The solid angle the triangle abc subtends at p, signed by its orientation as seen from p
// (positive when p is behind it: on the side its normal points away from).
inline double bf_solid_angle(Vec3 p, Vec3 a, Vec3 b, Vec3 c) {
  const Vec3 u = a - p, v = b - p, w = c - p;
  const double lu = bf_norm(u), lv = bf_norm(v), lw = bf_norm(w);
  const double num = bf_dot(u, bf_cross(v, w));
  const double den = lu * lv * lw + bf_dot(u, v) * lw + bf_dot(u, w) * lv + bf_dot(v, w) * lu;
  return 2 * std::atan2(num, den);
}

struct BruteForceSdf {
  const TriMesh& mesh;

  double unsigned_distance(Vec3 p) const {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
      best = std::min(best, bf_triangle_distance2(p, mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2)));
    return std::sqrt(best);
  }
  double winding_number(Vec3 p) const {
    double sum = 0;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
      sum += bf_solid_angle(p, mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2));
    return sum / (4 * M_PI);
  }
  // Negative inside.
  double signed_distance(Vec3 p) const {
    const double d = unsigned_distance(p);
    return winding_number(p) > 0.5 ? -d : d;
  }
};

// Whether a float the library wrote for the exact signed distance at a point is that distance
// rounded to float: within one float ulp of `want` (the reference's own rounding error is far
// below it), or within `slack` of it (an absolute allowance for points on the surface, whose
// sign is either).
inline bool bf_float_matches(float got, double want, double slack) {
  const double ulp = std::nextafter(std::fabs(static_cast<float>(want)), std::numeric_limits<float>::infinity()) -
                     std::fabs(static_cast<float>(want));
  return std::fabs(double(got) - want) <= ulp + slack;
}

}  // namespace frep::test
