#include "predicates.hpp"

#include <cmath>

namespace frep::exact {
namespace {

// A nonoverlapping expansion: the exact value is the sum of its components, which are ordered
// by increasing magnitude, so the sign is the sign of the last one.
struct Expansion {
  static constexpr int kCap = 256;
  double v[kCap];
  int n = 0;
  int sign() const { return n == 0 ? 0 : (v[n - 1] > 0 ? 1 : (v[n - 1] < 0 ? -1 : 0)); }
};

inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a, av = x - bv;
  y = (a - av) + (b - bv);
}

inline void split(double a, double& hi, double& lo) {
  const double c = 134217729.0 * a;  // 2^27 + 1
  hi = c - (c - a);
  lo = a - hi;
}

inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  double ah, al, bh, bl;
  split(a, ah, al);
  split(b, bh, bl);
  y = al * bl - (((x - ah * bh) - al * bh) - ah * bl);
}

// e += b, exactly, dropping zero components.
void grow(Expansion& e, double b) {
  double q = b;
  int m = 0;
  for (int i = 0; i < e.n; ++i) {
    double h;
    two_sum(q, e.v[i], q, h);
    if (h != 0) e.v[m++] = h;
  }
  if (q != 0) e.v[m++] = q;
  e.n = m;
}

Expansion diff(double a, double b) {
  Expansion e;
  double x, y;
  two_sum(a, -b, x, y);
  if (y != 0) e.v[e.n++] = y;
  if (x != 0) e.v[e.n++] = x;
  return e;
}

Expansion mul(const Expansion& a, const Expansion& b) {
  Expansion r;
  for (int i = 0; i < a.n; ++i)
    for (int j = 0; j < b.n; ++j) {
      double x, y;
      two_product(a.v[i], b.v[j], x, y);
      grow(r, y);
      grow(r, x);
    }
  return r;
}

void add(Expansion& r, const Expansion& a, double scale) {
  for (int i = 0; i < a.n; ++i) grow(r, scale * a.v[i]);  // scale is +-1: exact
}

int orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Expansion adx = diff(a.x, d.x), ady = diff(a.y, d.y), adz = diff(a.z, d.z);
  const Expansion bdx = diff(b.x, d.x), bdy = diff(b.y, d.y), bdz = diff(b.z, d.z);
  const Expansion cdx = diff(c.x, d.x), cdy = diff(c.y, d.y), cdz = diff(c.z, d.z);
  Expansion bc;
  add(bc, mul(bdy, cdz), 1);
  add(bc, mul(bdz, cdy), -1);
  Expansion ca;
  add(ca, mul(cdy, adz), 1);
  add(ca, mul(cdz, ady), -1);
  Expansion ab;
  add(ab, mul(ady, bdz), 1);
  add(ab, mul(adz, bdy), -1);
  Expansion det;
  add(det, mul(adx, bc), 1);
  add(det, mul(bdx, ca), 1);
  add(det, mul(cdx, ab), 1);
  return det.sign();
}

}  // namespace

int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  // det[a-d, b-d, c-d] = -det[b-a, c-a, d-a]; the filter bound is Shewchuk's o3derrboundA.
  const double adx = a.x - d.x, ady = a.y - d.y, adz = a.z - d.z;
  const double bdx = b.x - d.x, bdy = b.y - d.y, bdz = b.z - d.z;
  const double cdx = c.x - d.x, cdy = c.y - d.y, cdz = c.z - d.z;
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
  const double permanent = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * std::fabs(adz) +
                           (std::fabs(cdxady) + std::fabs(adxcdy)) * std::fabs(bdz) +
                           (std::fabs(adxbdy) + std::fabs(bdxady)) * std::fabs(cdz);
  const double bound = 7.8e-16 * permanent;
  // Tiny permanents may have lost bits to underflow, where the bound does not hold.
  if (permanent > 1e-280) {
    if (det > bound) return -1;
    if (-det > bound) return 1;
  }
  if (permanent == 0) return 0;
  return -orient3d_exact(a, b, c, d);
}

int orient2d(double ax, double ay, double bx, double by, double cx, double cy) {
  const double l = (bx - ax) * (cy - ay), r = (by - ay) * (cx - ax);
  const double det = l - r;
  const double bound = 3.4e-16 * (std::fabs(l) + std::fabs(r));
  if (std::fabs(l) + std::fabs(r) > 1e-290) {
    if (det > bound) return 1;
    if (-det > bound) return -1;
  }
  Expansion e;
  add(e, mul(diff(bx, ax), diff(cy, ay)), 1);
  add(e, mul(diff(by, ay), diff(cx, ax)), -1);
  return e.sign();
}

}  // namespace frep::exact
