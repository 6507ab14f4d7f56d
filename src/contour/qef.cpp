// QEF accumulation and minimization (truncated pseudo-inverse about the mass point) with a small
// Jacobi eigen-solver for the 3x3 normal matrix.
#include "contour/qef.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace frep {

void Qef::add(const Vec3& p, const Vec3& n) {
  const double d = dot(n, p);
  ata_[0] += n.x * n.x;
  ata_[1] += n.x * n.y;
  ata_[2] += n.x * n.z;
  ata_[3] += n.y * n.y;
  ata_[4] += n.y * n.z;
  ata_[5] += n.z * n.z;
  atb_[0] += n.x * d;
  atb_[1] += n.y * d;
  atb_[2] += n.z * d;
  btb_ += d * d;
  ++planes_;
  add_point(p);
}

void Qef::add_point(const Vec3& p) {
  mass_ += p;
  ++points_;
}

Vec3 Qef::mass_point() const { return points_ ? mass_ / static_cast<double>(points_) : Vec3{}; }

double Qef::error(const Vec3& x) const {
  // x^T A^T A x - 2 x^T A^T b + b^T b
  const double* m = ata_;
  const double xax = m[0] * x.x * x.x + m[3] * x.y * x.y + m[5] * x.z * x.z +
                     2 * (m[1] * x.x * x.y + m[2] * x.x * x.z + m[4] * x.y * x.z);
  return std::max(0.0, xax - 2 * (x.x * atb_[0] + x.y * atb_[1] + x.z * atb_[2]) + btb_);
}

namespace {

// A unit vector perpendicular to v.
Vec3 any_perpendicular(const Vec3& v) {
  const Vec3 c = std::fabs(v.x) < 0.6 ? cross(v, Vec3{1, 0, 0}) : cross(v, Vec3{0, 1, 0});
  return c / length(c);
}

// Unit eigenvector of m for eigenvalue l (well separated from the others): the largest cross
// product of two rows of m - l I, which is orthogonal to both and so to the row space.
Vec3 eigenvector(const double m[6], double l) {
  const Vec3 r0{m[0] - l, m[1], m[2]}, r1{m[1], m[3] - l, m[4]}, r2{m[2], m[4], m[5] - l};
  const Vec3 c[3] = {cross(r0, r1), cross(r0, r2), cross(r1, r2)};
  int best = 0;
  for (int i = 1; i < 3; ++i)
    if (length2(c[i]) > length2(c[best])) best = i;
  const double n = length(c[best]);
  return n > 0 ? c[best] / n : Vec3{1, 0, 0};
}

}  // namespace

// Eigenvalues in closed form (the trigonometric solution of the characteristic cubic),
// eigenvectors from cross products; (nearly) repeated eigenvalues get any orthonormal basis of
// their eigenspace. Much cheaper than iterating, and accurate enough for truncation.
void symmetric_eigen3(const double m[6], double values[3], Vec3 vectors[3]) {
  const double scale = std::max({std::fabs(m[0]), std::fabs(m[1]), std::fabs(m[2]), std::fabs(m[3]), std::fabs(m[4]),
                                 std::fabs(m[5])});
  vectors[0] = {1, 0, 0}, vectors[1] = {0, 1, 0}, vectors[2] = {0, 0, 1};
  if (!(scale > 0) || !std::isfinite(scale)) {
    values[0] = values[1] = values[2] = 0;
    if (!std::isfinite(scale)) values[0] = values[1] = values[2] = scale;
    return;
  }
  // Work on m / scale (entries within [-1, 1]).
  double a[6];
  for (int i = 0; i < 6; ++i) a[i] = m[i] / scale;
  const double q = (a[0] + a[3] + a[5]) / 3;
  const double p1 = a[1] * a[1] + a[2] * a[2] + a[4] * a[4];
  const double d0 = a[0] - q, d1 = a[3] - q, d2 = a[5] - q;
  const double p = std::sqrt((d0 * d0 + d1 * d1 + d2 * d2 + 2 * p1) / 6);
  double l[3];
  if (p < 1e-15) {
    l[0] = l[1] = l[2] = q;
  } else {
    // B = (A - q I) / p; det(B) / 2 = cos(3 phi).
    const double b0 = d0 / p, b1 = a[1] / p, b2 = a[2] / p, b3 = d1 / p, b4 = a[4] / p, b5 = d2 / p;
    const double det = b0 * (b3 * b5 - b4 * b4) - b1 * (b1 * b5 - b4 * b2) + b2 * (b1 * b4 - b3 * b2);
    const double r = std::clamp(det / 2, -1.0, 1.0);
    const double phi = std::acos(r) / 3;
    l[0] = q + 2 * p * std::cos(phi);
    l[2] = q + 2 * p * std::cos(phi + 2.0943951023931957);  // + 2 pi / 3
    l[1] = 3 * q - l[0] - l[2];
    if (l[1] > l[0]) std::swap(l[0], l[1]);
    if (l[2] > l[1]) std::swap(l[1], l[2]);
    if (l[1] > l[0]) std::swap(l[0], l[1]);
  }
  // Relative gap below which eigenvalues count as repeated (the closed form is good to about
  // 1e-8 near double roots, where acos loses half the digits).
  const double tol = 1e-7;
  const bool gap01 = l[0] - l[1] > tol, gap12 = l[1] - l[2] > tol;
  if (gap01 && gap12) {
    vectors[0] = eigenvector(a, l[0]);
    vectors[2] = eigenvector(a, l[2]);
    vectors[2] = vectors[2] - vectors[0] * dot(vectors[0], vectors[2]);
    vectors[2] = vectors[2] / length(vectors[2]);
    vectors[1] = cross(vectors[2], vectors[0]);
  } else if (gap01) {
    vectors[0] = eigenvector(a, l[0]);
    vectors[1] = any_perpendicular(vectors[0]);
    vectors[2] = cross(vectors[0], vectors[1]);
  } else if (gap12) {
    vectors[2] = eigenvector(a, l[2]);
    vectors[0] = any_perpendicular(vectors[2]);
    vectors[1] = cross(vectors[2], vectors[0]);
  }
  for (int i = 0; i < 3; ++i) values[i] = l[i] * scale;
}

Vec3 Qef::solve(double threshold, int max_rank, int* rank) const {
  const Vec3 m = mass_point();
  int r = 0;
  Vec3 x = m;
  // Residual of the normal equations at the mass point: A^T b - A^T A m.
  auto residual = [&] {
    return Vec3{atb_[0] - (ata_[0] * m.x + ata_[1] * m.y + ata_[2] * m.z),
                atb_[1] - (ata_[1] * m.x + ata_[3] * m.y + ata_[4] * m.z),
                atb_[2] - (ata_[2] * m.x + ata_[4] * m.y + ata_[5] * m.z)};
  };
  if (planes_ > 0 && max_rank > 0 && threshold > 0) {
    // Fast path for nearly parallel normals (most cells of a smooth surface): the dominant
    // eigenvector by a few power steps; if the rest of the trace is below the threshold, so is
    // every other eigenvalue, and the answer is the rank-1 one.
    const double* a = ata_;
    const double trace = a[0] + a[3] + a[5];
    Vec3 v{a[0], a[1], a[2]};
    if (a[3] > a[0] && a[3] >= a[5]) v = {a[1], a[3], a[4]};
    else if (a[5] > a[0] && a[5] > a[3]) v = {a[2], a[4], a[5]};
    double l1 = 0;
    for (int it = 0; it < 4; ++it) {
      const double n = length(v);
      if (!(n > 0)) break;
      v = v / n;
      const Vec3 w{a[0] * v.x + a[1] * v.y + a[2] * v.z, a[1] * v.x + a[3] * v.y + a[4] * v.z,
                   a[2] * v.x + a[4] * v.y + a[5] * v.z};
      l1 = dot(v, w);
      v = w;
    }
    const double n = length(v);
    if (l1 > 0 && n > 0 && trace - l1 < threshold * l1 * 0.5) {
      v = v / n;
      x = m + v * (dot(v, residual()) / l1);
      if (std::isfinite(x.x) && std::isfinite(x.y) && std::isfinite(x.z)) {
        if (rank) *rank = 1;
        return x;
      }
      x = m;
    }
  }
  if (planes_ > 0 && max_rank > 0) {
    double values[3];
    Vec3 vecs[3];
    symmetric_eigen3(ata_, values, vecs);
    const Vec3 g = residual();
    for (int i = 0; i < 3 && r < max_rank; ++i) {
      if (!(values[i] > 0) || values[i] < threshold * values[0]) break;
      x += vecs[i] * (dot(vecs[i], g) / values[i]);
      ++r;
    }
    if (!std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z)) x = m, r = 0;
  }
  if (rank) *rank = r;
  return x;
}

Vec3 Qef::solve_in(const Box3& box, double threshold, double slack) const {
  const Vec3 x = solve(threshold);
  if (box.inflated(slack).contains(x) || planes_ == 0) return max(box.lo, min(box.hi, x));
  // Minimize E(x) = x^T M x - 2 x^T c (+ const) over the box, with M = A^T A + eps I and
  // c = A^T b + eps m (eps: a pull towards the mass point m, for uniqueness). E is convex, so its
  // minimum over the box is where, for some set of coordinates held at a bound, the others solve
  // the reduced system and lie within their bounds: try all 27 sets, keep the lowest E.
  const Vec3 m = mass_point();
  const double trace = ata_[0] + ata_[3] + ata_[5];
  const double eps = 1e-3 * trace;
  const double M[3][3] = {{ata_[0] + eps, ata_[1], ata_[2]}, {ata_[1], ata_[3] + eps, ata_[4]}, {ata_[2], ata_[4], ata_[5] + eps}};
  const double c[3] = {atb_[0] + eps * m.x, atb_[1] + eps * m.y, atb_[2] + eps * m.z};
  auto energy = [&](const double y[3]) {
    double e = 0;
    for (int i = 0; i < 3; ++i) {
      double row = 0;
      for (int j = 0; j < 3; ++j) row += M[i][j] * y[j];
      e += y[i] * row - 2 * y[i] * c[i];
    }
    return e;
  };
  double best_e = INFINITY;
  Vec3 best = max(box.lo, min(box.hi, m));
  for (int pattern = 0; pattern < 27; ++pattern) {
    int state[3];  // 0 free, 1 at lo, 2 at hi
    for (int i = 0, p = pattern; i < 3; ++i, p /= 3) state[i] = p % 3;
    double y[3] = {0, 0, 0};
    int free_idx[3], nf = 0;
    for (int i = 0; i < 3; ++i) {
      if (state[i] == 1) y[i] = box.lo[i];
      else if (state[i] == 2) y[i] = box.hi[i];
      else free_idx[nf++] = i;
    }
    // Reduced system for the free coordinates: M_ff y_f = c_f - M_fb y_b (Gaussian elimination).
    double A[3][4];
    for (int r = 0; r < nf; ++r) {
      const int i = free_idx[r];
      double rhs = c[i];
      for (int j = 0; j < 3; ++j)
        if (state[j] != 0) rhs -= M[i][j] * y[j];
      for (int k = 0; k < nf; ++k) A[r][k] = M[i][free_idx[k]];
      A[r][nf] = rhs;
    }
    bool ok = true;
    for (int col = 0; col < nf && ok; ++col) {
      int piv = col;
      for (int r = col + 1; r < nf; ++r)
        if (std::fabs(A[r][col]) > std::fabs(A[piv][col])) piv = r;
      if (!(std::fabs(A[piv][col]) > 0)) {
        ok = false;
        break;
      }
      for (int k = 0; k <= nf; ++k) std::swap(A[col][k], A[piv][k]);
      for (int r = 0; r < nf; ++r) {
        if (r == col) continue;
        const double f = A[r][col] / A[col][col];
        for (int k = col; k <= nf; ++k) A[r][k] -= f * A[col][k];
      }
    }
    if (!ok) continue;
    for (int r = 0; r < nf && ok; ++r) {
      const int i = free_idx[r];
      y[i] = A[r][nf] / A[r][r];
      ok = std::isfinite(y[i]) && y[i] >= box.lo[i] && y[i] <= box.hi[i];
    }
    if (!ok) continue;
    const double e = energy(y);
    if (e < best_e) {
      best_e = e;
      best = {y[0], y[1], y[2]};
    }
  }
  return best;
}

}  // namespace frep
