// Exact geometric predicates on double coordinates: a floating-point filter first, and exact
// expansion arithmetic (error-free sums and products) when the filter cannot decide. Used
// wherever a wrong sign would give a wrong answer (self-intersections), not for distances.
// The filters are inline: the self-intersection test calls them millions of times per mesh, and
// most calls end there. Public: the mesh checks, repair and the converter decide with them, and a
// program can too.
#pragma once

#include <cmath>

#include "frep/math/vec.hpp"

namespace frep::exact {

// The exact stages (in the library), for what the filters below leave undecided. `permanent` is
// the one orient3d_filter computed.
int orient3d_uncertain(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double permanent);
int orient2d_uncertain(double ax, double ay, double bx, double by, double cx, double cy);

// What orient3d_filter answers where it cannot decide.
inline constexpr int kUndecided = 2;

// orient3d's float filter alone: its sign where the filter decides it, else kUndecided, and
// then orient3d_uncertain(a, b, c, d, permanent) decides (or a caller who knows the answer is 0).
inline int orient3d_filter(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double& permanent) {
  // det[a-d, b-d, c-d] = -det[b-a, c-a, d-a]; the filter bound is Shewchuk's o3derrboundA.
  const double adx = a.x - d.x, ady = a.y - d.y, adz = a.z - d.z;
  const double bdx = b.x - d.x, bdy = b.y - d.y, bdz = b.z - d.z;
  const double cdx = c.x - d.x, cdy = c.y - d.y, cdz = c.z - d.z;
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
  permanent = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * std::fabs(adz) +
              (std::fabs(cdxady) + std::fabs(adxcdy)) * std::fabs(bdz) +
              (std::fabs(adxbdy) + std::fabs(bdxady)) * std::fabs(cdz);
  const double bound = 7.8e-16 * permanent;
  // Tiny permanents may have lost bits to underflow, where the bound does not hold.
  if (permanent > 1e-280) {
    if (det > bound) return -1;
    if (-det > bound) return 1;
  }
  return kUndecided;
}

// Sign (-1, 0, +1) of ((b - a) x (c - a)) . (d - a): positive when d lies on the side that
// triangle abc's right-hand normal points to.
inline int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  double permanent;
  const int s = orient3d_filter(a, b, c, d, permanent);
  return s != kUndecided ? s : orient3d_uncertain(a, b, c, d, permanent);
}

// Sign of (b - a) x (c - a) in the plane: positive for a counter-clockwise turn.
inline int orient2d(double ax, double ay, double bx, double by, double cx, double cy) {
  const double l = (bx - ax) * (cy - ay), r = (by - ay) * (cx - ax);
  const double det = l - r;
  const double bound = 3.4e-16 * (std::fabs(l) + std::fabs(r));
  if (std::fabs(l) + std::fabs(r) > 1e-290) {
    if (det > bound) return 1;
    if (-det > bound) return -1;
  }
  return orient2d_uncertain(ax, ay, bx, by, cx, cy);
}

}  // namespace frep::exact
