// Exact orientation predicates: a floating-point filter (Shewchuk's error bound), then, when it
// cannot decide, exact expansion arithmetic in fixed-size arrays (Shewchuk's
// scale_expansion_zeroelim and fast_expansion_sum_zeroelim). Meshes made of flat faces make the
// filter fail on every coplanar pair, so the exact stage matters: when the coordinate differences
// are exact (always for float data such as STL) it is the short degree-3 form (24 components at
// most); otherwise the differences' roundoff tails are carried along (192 at most). Coordinates
// outside [2^-200, 2^200] (other than 0), where those products could underflow, take the original
// general expansion code, so that no answer changes there.
#include "frep/math/predicates.hpp"

#include <cmath>

namespace frep::exact {
namespace {

// --- Error-free transformations.

inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a, av = x - bv;
  y = (a - av) + (b - bv);
}

inline void fast_two_sum(double a, double b, double& x, double& y) {  // |a| >= |b| (or a == 0)
  x = a + b;
  y = b - (x - a);
}

inline void two_diff(double a, double b, double& x, double& y) {
  x = a - b;
  const double bv = a - x, av = x + bv;
  y = (a - av) + (bv - b);
}

// (a1 + a0) - b and (a1 + a0) - (b1 + b0) as expansions of three and four components (Shewchuk's
// Two_One_Diff and Two_Two_Diff; zero components kept).
inline void two_one_diff(double a1, double a0, double b, double& x2, double& x1, double& x0) {
  double i;
  two_diff(a0, b, i, x0);
  two_sum(a1, i, x2, x1);
}
inline void two_two_diff(double a1, double a0, double b1, double b0, double* x) {
  double j, z;
  two_one_diff(a1, a0, b0, j, z, x[0]);
  two_one_diff(j, z, b1, x[3], x[2], x[1]);
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

// --- Fixed-size expansions: nonoverlapping components by increasing magnitude. scale() and sum()
// drop zeros (their result for 0 is one zero component), so the sign of what they return is
// the sign of its last component.

// h = e * b; h has room for 2 * n components. Returns h's length.
int scale(const double* e, int n, double b, double* h) {
  double bh, bl;
  split(b, bh, bl);
  const auto product = [&](double a, double& x, double& y) {
    x = a * b;
    double ah, al;
    split(a, ah, al);
    y = al * bl - (((x - ah * bh) - al * bh) - ah * bl);
  };
  double q, hh;
  product(e[0], q, hh);
  int m = 0;
  if (hh != 0) h[m++] = hh;
  for (int i = 1; i < n; ++i) {
    double p1, p0, sum;
    product(e[i], p1, p0);
    two_sum(q, p0, sum, hh);
    if (hh != 0) h[m++] = hh;
    fast_two_sum(p1, sum, q, hh);
    if (hh != 0) h[m++] = hh;
  }
  if (q != 0 || m == 0) h[m++] = q;
  return m;
}

// h = e + f; h has room for ne + nf components. Returns h's length.
int sum(const double* e, int ne, const double* f, int nf, double* h) {
  int i = 0, j = 0, m = 0;
  // Components are taken in order of increasing magnitude from either input.
  const auto next = [&]() {
    if (j >= nf || (i < ne && ((f[j] > e[i]) == (f[j] > -e[i])))) return e[i++];
    return f[j++];
  };
  double q = next(), qn, hh;
  if (i + j < ne + nf) {
    fast_two_sum(next(), q, qn, hh);
    q = qn;
    if (hh != 0) h[m++] = hh;
    while (i + j < ne + nf) {
      two_sum(q, next(), qn, hh);
      q = qn;
      if (hh != 0) h[m++] = hh;
    }
  }
  if (q != 0 || m == 0) h[m++] = q;
  return m;
}

inline int sign_of(const double* e, int n) { return e[n - 1] > 0 ? 1 : (e[n - 1] < 0 ? -1 : 0); }

// a - b as an expansion of one or two components.
inline int difference(double a, double b, double* h) {
  double x, y;
  two_diff(a, b, x, y);
  int m = 0;
  if (y != 0) h[m++] = y;
  if (x != 0 || m == 0) h[m++] = x;
  return m;
}

// h = a * b for expansions of at most two components each (h: room for 8).
int product2(const double* a, int na, const double* b, int nb, double* h) {
  double t0[4], t1[4];
  const int n0 = scale(a, na, b[0], t0);
  if (nb == 1) {
    for (int k = 0; k < n0; ++k) h[k] = t0[k];
    return n0;
  }
  const int n1 = scale(a, na, b[1], t1);
  return sum(t0, n0, t1, n1, h);
}

// h = e * f, f of at most two components (h: room for 4 * ne).
int product_by2(const double* e, int ne, const double* f, int nf, double* h) {
  double t0[64], t1[64];
  const int n0 = scale(e, ne, f[0], t0);
  if (nf == 1) {
    for (int k = 0; k < n0; ++k) h[k] = t0[k];
    return n0;
  }
  const int n1 = scale(e, ne, f[1], t1);
  return sum(t0, n0, t1, n1, h);
}

inline void negate(double* e, int n) {
  for (int k = 0; k < n; ++k) e[k] = -e[k];
}

// Where the fixed-size arithmetic is exact: no product of three coordinate differences (or of
// their roundoff tails) comes near the underflow or overflow thresholds.
inline bool in_range(double x) {
  const double a = std::fabs(x);
  return a == 0 || (a >= 0x1p-200 && a <= 0x1p200);
}

// --- The original general expansion code, kept for coordinates outside in_range (its answers
// there are what they always were).
struct Expansion {
  static constexpr int kCap = 256;
  double v[kCap];
  int n = 0;
  int sign() const { return n == 0 ? 0 : (v[n - 1] > 0 ? 1 : (v[n - 1] < 0 ? -1 : 0)); }
};

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

int orient3d_general(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
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

int orient2d_general(double ax, double ay, double bx, double by, double cx, double cy) {
  Expansion e;
  add(e, mul(diff(bx, ax), diff(cy, ay)), 1);
  add(e, mul(diff(by, ay), diff(cx, ax)), -1);
  return e.sign();
}

// --- Exact stages.

// Sign of det[a - d, b - d, c - d].
int orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  for (const Vec3* p : {&a, &b, &c, &d})
    if (!in_range(p->x) || !in_range(p->y) || !in_range(p->z)) return orient3d_general(a, b, c, d);
  // A repeated point makes the determinant 0; the filter cannot see it (its rounded value is 0
  // against a non-zero bound), and it is common: corners shared by neighbouring triangles.
  if (a == d || b == d || c == d || a == b || b == c || a == c) return 0;
  double dx[3][2], dy[3][2], dz[3][2];  // rows a - d, b - d, c - d
  int nx[3], ny[3], nz[3];
  bool exact_differences = true;
  const Vec3* rows[3] = {&a, &b, &c};
  for (int r = 0; r < 3; ++r) {
    nx[r] = difference(rows[r]->x, d.x, dx[r]);
    ny[r] = difference(rows[r]->y, d.y, dy[r]);
    nz[r] = difference(rows[r]->z, d.z, dz[r]);
    exact_differences = exact_differences && nx[r] == 1 && ny[r] == 1 && nz[r] == 1;
  }
  double fin[192];
  int nfin;
  if (exact_differences) {
    // Shewchuk's orient3dadapt with exact differences: each 2x2 minor is exact in four
    // components, each cofactor term in eight.
    const double adx = dx[0][0], ady = dy[0][0], adz = dz[0][0];
    const double bdx = dx[1][0], bdy = dy[1][0], bdz = dz[1][0];
    const double cdx = dx[2][0], cdy = dy[2][0], cdz = dz[2][0];
    const auto minor = [](double p, double q, double r, double s, double* h) {  // p q - r s
      double x1, x0, y1, y0;
      two_product(p, q, x1, x0);
      two_product(r, s, y1, y0);
      two_two_diff(x1, x0, y1, y0, h);
      return 4;
    };
    double bc[4], ca[4], ab[4], ta[8], tb[8], tc[8], tab[16];
    const int nbc = minor(bdx, cdy, cdx, bdy, bc);
    const int nca = minor(cdx, ady, adx, cdy, ca);
    const int nab = minor(adx, bdy, bdx, ady, ab);
    const int na = scale(bc, nbc, adz, ta);
    const int nb = scale(ca, nca, bdz, tb);
    const int nc = scale(ab, nab, cdz, tc);
    const int nt = sum(ta, na, tb, nb, tab);
    nfin = sum(tab, nt, tc, nc, fin);
  } else {
    // Differences with roundoff tails: products of two-component expansions.
    const auto minor = [](const double* p, int np, const double* q, int nq, const double* r, int nr, const double* s,
                          int ns, double* h) {  // p q - r s, at most 16 components
      double x[8], y[8];
      const int n1 = product2(p, np, q, nq, x);
      const int n2 = product2(r, nr, s, ns, y);
      negate(y, n2);
      return sum(x, n1, y, n2, h);
    };
    double bc[16], ca[16], ab[16], ta[64], tb[64], tc[64], tab[128];
    const int nbc = minor(dx[1], nx[1], dy[2], ny[2], dx[2], nx[2], dy[1], ny[1], bc);
    const int nca = minor(dx[2], nx[2], dy[0], ny[0], dx[0], nx[0], dy[2], ny[2], ca);
    const int nab = minor(dx[0], nx[0], dy[1], ny[1], dx[1], nx[1], dy[0], ny[0], ab);
    const int na = product_by2(bc, nbc, dz[0], nz[0], ta);
    const int nb = product_by2(ca, nca, dz[1], nz[1], tb);
    const int nc = product_by2(ab, nab, dz[2], nz[2], tc);
    const int nt = sum(ta, na, tb, nb, tab);
    nfin = sum(tab, nt, tc, nc, fin);
  }
  return sign_of(fin, nfin);
}

int orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy) {
  for (double v : {ax, ay, bx, by, cx, cy})
    if (!in_range(v)) return orient2d_general(ax, ay, bx, by, cx, cy);
  // Repeated points, or both products with a zero factor (a side along an axis: common).
  if ((ax == bx && ay == by) || (bx == cx && by == cy) || (ax == cx && ay == cy)) return 0;
  if ((bx == ax || cy == ay) && (by == ay || cx == ax)) return 0;
  double u[2], v[2], w[2], z[2];  // (bx - ax) (cy - ay) - (by - ay) (cx - ax)
  const int nu = difference(bx, ax, u), nv = difference(cy, ay, v);
  const int nw = difference(by, ay, w), nz = difference(cx, ax, z);
  double x[8], y[8], h[16];
  const int n1 = product2(u, nu, v, nv, x);
  const int n2 = product2(w, nw, z, nz, y);
  negate(y, n2);
  return sign_of(h, sum(x, n1, y, n2, h));
}

}  // namespace

int orient3d_uncertain(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double permanent) {
  if (permanent == 0) return 0;
  return -orient3d_exact(a, b, c, d);
}

int orient2d_uncertain(double ax, double ay, double bx, double by, double cx, double cy) {
  return orient2d_exact(ax, ay, bx, by, cx, cy);
}

}  // namespace frep::exact
