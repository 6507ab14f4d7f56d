// QEF accumulation and minimization (truncated pseudo-inverse about the mass point) with a small
// Jacobi eigen-solver for the 3x3 normal matrix.
#include "frep/contour/qef.hpp"

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

void symmetric_eigen3(const double m[6], double values[3], Vec3 vectors[3]) {
  double a[3][3] = {{m[0], m[1], m[2]}, {m[1], m[3], m[4]}, {m[2], m[4], m[5]}};
  double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int sweep = 0; sweep < 32; ++sweep) {
    const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    const double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
    if (off <= 1e-24 * diag || off == 0) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (a[p][q] == 0) continue;
        // Rotation that zeroes a[p][q] (the smaller angle, for stability).
        const double theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
        const double t = (theta >= 0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1));
        const double c = 1 / std::sqrt(t * t + 1), s = t * c;
        for (int k = 0; k < 3; ++k) {
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) {
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; ++k) {
          const double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
  }
  int order[3] = {0, 1, 2};
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j)
      if (a[order[j]][order[j]] > a[order[i]][order[i]]) std::swap(order[i], order[j]);
  for (int i = 0; i < 3; ++i) {
    const int k = order[i];
    values[i] = a[k][k];
    vectors[i] = {v[0][k], v[1][k], v[2][k]};
  }
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
