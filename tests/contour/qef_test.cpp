// The QEF and its eigen-solver: eigenpairs of random symmetric matrices satisfy A v = l v with
// orthonormal v; planes through a known corner, edge or face give that corner, the point of the
// edge line or of the plane nearest the mass point; solve_in keeps the result in its box.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "contour/qef.hpp"

namespace frep {
namespace {

TEST(Qef, EigenOfRandomSymmetricMatrices) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 2000; ++trial) {
    double m[6];
    for (double& x : m) x = u(rng) * (trial % 3 == 0 ? 1e-6 : 1.0);
    if (trial % 7 == 0) m[1] = m[2] = m[4] = 0;  // diagonal already
    double val[3];
    Vec3 vec[3];
    symmetric_eigen3(m, val, vec);
    EXPECT_GE(val[0], val[1]);
    EXPECT_GE(val[1], val[2]);
    const double scale = std::max({std::fabs(m[0]), std::fabs(m[1]), std::fabs(m[2]), std::fabs(m[3]), std::fabs(m[4]),
                                   std::fabs(m[5])});
    for (int i = 0; i < 3; ++i) {
      const Vec3 v = vec[i];
      const Vec3 av{m[0] * v.x + m[1] * v.y + m[2] * v.z, m[1] * v.x + m[3] * v.y + m[4] * v.z,
                    m[2] * v.x + m[4] * v.y + m[5] * v.z};
      EXPECT_LT(length(av - v * val[i]), 1e-10 * scale + 1e-300);
      for (int j = 0; j < 3; ++j) EXPECT_NEAR(dot(vec[i], vec[j]), i == j ? 1.0 : 0.0, 1e-12);
    }
  }
}

// Matrices R diag(l) R^T with (nearly) repeated eigenvalues: the values come back, and the
// vectors span the right eigenspaces (A v = l v), orthonormal.
TEST(Qef, EigenWithRepeatedValues) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  const double spectra[][3] = {{1, 1 + 1e-12, 0.3}, {1, 0.5, 0.5}, {2, 2, 2}, {1, 1e-8, 0}, {1, 0, 0}, {3, 1e-13, 0}};
  for (const auto& l : spectra)
    for (int trial = 0; trial < 200; ++trial) {
      // A random rotation from a normalized quaternion.
      double qw = u(rng), qx = u(rng), qy = u(rng), qz = u(rng);
      const double n = std::sqrt(qw * qw + qx * qx + qy * qy + qz * qz);
      qw /= n, qx /= n, qy /= n, qz /= n;
      const double R[3][3] = {{1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)},
                              {2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)},
                              {2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)}};
      double A[3][3] = {};
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          for (int k = 0; k < 3; ++k) A[i][j] += R[i][k] * l[k] * R[j][k];
      const double m[6] = {A[0][0], A[0][1], A[0][2], A[1][1], A[1][2], A[2][2]};
      double val[3];
      Vec3 vec[3];
      symmetric_eigen3(m, val, vec);
      for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(val[i], l[i], 1e-7);  // the closed form loses digits at double roots
        const Vec3 v = vec[i];
        const Vec3 av{A[0][0] * v.x + A[0][1] * v.y + A[0][2] * v.z, A[1][0] * v.x + A[1][1] * v.y + A[1][2] * v.z,
                      A[2][0] * v.x + A[2][1] * v.y + A[2][2] * v.z};
        EXPECT_LT(length(av - v * val[i]), 1e-7);
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(dot(vec[i], vec[j]), i == j ? 1.0 : 0.0, 1e-9);
      }
    }
}

TEST(Qef, CornerEdgeAndFace) {
  const Vec3 c{0.3, 0.6, 0.2};
  // Three planes through c (normals not axis-aligned): the corner, exactly.
  Qef corner;
  const Vec3 n[3] = {Vec3{1, 0.2, 0} / std::sqrt(1.04), Vec3{0, 1, 0.1} / std::sqrt(1.01), Vec3{0.1, 0, 1} / std::sqrt(1.01)};
  const Vec3 off[3] = {{0, 0.3, -0.1}, {0.2, 0, 0.3}, {-0.1, 0.25, 0}};  // points on the planes (off c)
  for (int i = 0; i < 3; ++i) {
    const Vec3 t = off[i] - n[i] * dot(off[i], n[i]);  // tangent offset
    corner.add(c + t, n[i]);
  }
  int rank = 0;
  const Vec3 x = corner.solve(0.02, 3, &rank);
  EXPECT_EQ(rank, 3);
  EXPECT_LT(length(x - c), 1e-12);
  EXPECT_LT(corner.error(x), 1e-12);

  // Two planes: the line through c along d = n0 x n1; the solution is the mass point moved onto it.
  Qef edge;
  const Vec3 p[4] = {c + Vec3{0, 0, 0.3}, c + Vec3{0, 0, -0.2}, c + Vec3{0, 0, 0.1}, c + Vec3{0, 0, 0.2}};
  edge.add(p[0], {1, 0, 0});
  edge.add(p[1], {1, 0, 0});
  edge.add(p[2], {0, 1, 0});
  edge.add(p[3], {0, 1, 0});
  const Vec3 e = edge.solve(0.02, 3, &rank);
  EXPECT_EQ(rank, 2);
  EXPECT_NEAR(e.x, c.x, 1e-12);
  EXPECT_NEAR(e.y, c.y, 1e-12);
  EXPECT_NEAR(e.z, edge.mass_point().z, 1e-12);

  // One plane (nearly: normals within 1e-4 of each other): the mass point projected onto it.
  Qef face;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  Vec3 mass;
  for (int i = 0; i < 6; ++i) {
    const Vec3 q{u(rng), u(rng), 0.5};
    face.add(q, Vec3{1e-4 * (i % 2), 0, 1} / std::sqrt(1 + 1e-8 * (i % 2)));
    mass += q;
  }
  mass = mass / 6.0;
  const Vec3 f = face.solve(0.02, 3, &rank);
  EXPECT_EQ(rank, 1) << f.x << " " << f.y << " " << f.z;
  // (Within the planes' tilt: 1e-4 over a unit distance.)
  EXPECT_NEAR(f.z, 0.5, 1e-4);
  EXPECT_NEAR(f.x, mass.x, 1e-4);
  EXPECT_NEAR(f.y, mass.y, 1e-4);
}

// solve() against the truncated pseudo-inverse written out from symmetric_eigen3, on random
// QEFs from nearly parallel to spread normals (the nearly parallel ones take a fast path).
TEST(Qef, SolveMatchesTheEigenDecomposition) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1), pos(0, 1);
  for (int trial = 0; trial < 3000; ++trial) {
    const double spread = std::pow(10.0, -4 + 4 * pos(rng));  // 1e-4 .. 1
    const Vec3 base{u(rng), u(rng), u(rng)};
    if (length(base) == 0) continue;
    Qef q;
    double ata[6] = {};
    const int k = 2 + trial % 5;
    for (int i = 0; i < k; ++i) {
      Vec3 n = base / length(base) + Vec3{u(rng), u(rng), u(rng)} * spread;
      n = n / length(n);
      q.add({pos(rng), pos(rng), pos(rng)}, n);
      ata[0] += n.x * n.x, ata[1] += n.x * n.y, ata[2] += n.x * n.z, ata[3] += n.y * n.y, ata[4] += n.y * n.z, ata[5] += n.z * n.z;
    }
    double val[3];
    Vec3 vec[3];
    symmetric_eigen3(ata, val, vec);
    const double tau = 0.02;
    // Skip eigenvalues right at the threshold, where the two ways may round differently.
    bool near = false;
    for (int i = 1; i < 3; ++i) near |= std::fabs(val[i] - tau * val[0]) < 1e-3 * val[0];
    if (near) continue;
    const Vec3 m = q.mass_point();
    // Reference: minimize |A x - b|^2 over m + span(kept eigenvectors).
    const Vec3 x = q.solve(tau);
    Vec3 ref = m;
    for (int i = 0; i < 3; ++i) {
      if (val[i] < tau * val[0]) break;
      // d/dt E(m + t v) = 0: t = (v . (A^T b - A^T A m)) / l, with A^T b - A^T A m from the gradient.
      const double e0 = q.error(m), ep = q.error(m + vec[i]), em = q.error(m - vec[i]);
      // E(m + t v) = e0 + t g + t^2 l: g = (ep - em) / 2, l = (ep + em) / 2 - e0.
      ref += vec[i] * (-(ep - em) / 2 / (2 * ((ep + em) / 2 - e0)));
    }
    EXPECT_LT(length(x - ref), 1e-6) << "trial " << trial << " spread " << spread;
  }
}

TEST(Qef, SolveInKeepsTheBox) {
  // A corner at (1.5, 0.5, 0.5), outside the unit box, with x the strongest direction: every
  // solution keeping x is outside, so the result is the mass point (1, 0.5, 0.5).
  Qef q;
  q.add({1.5, 0.5, 0.5}, {1, 0, 0});
  q.add({1.5, 0.5, 0.5}, {1, 0, 0});
  q.add({0.5, 0.5, 0.5}, {0, 1, 0});
  q.add({0.5, 0.5, 0.5}, {0, 0, 1});
  const Box3 box{{0, 0, 0}, {1, 1, 1}};
  EXPECT_LT(length(q.solve(0.02, 3) - Vec3{1.5, 0.5, 0.5}), 1e-12);
  const Vec3 x = q.solve_in(box, 0.02, 0.05);
  EXPECT_LT(length(x - Vec3{1, 0.5, 0.5}), 1e-12);
  // An edge line (x = 1.2, y = 0.5) outside the box: the box's nearest points to it, x = 1 and
  // y = 0.5 (the best the box allows for both planes), z at the mass point.
  Qef e;
  e.add({1.2, 0.3, 0.2}, {1, 0, 0});
  e.add({1.2, 0.3, 0.8}, {1, 0, 0});
  e.add({0.7, 0.5, 0.4}, {0, 1, 0});
  e.add({0.7, 0.5, 0.6}, {0, 1, 0});
  const Vec3 ex = e.solve_in(box, 0.02, 0.05);
  EXPECT_NEAR(ex.x, 1, 1e-12);
  EXPECT_NEAR(ex.y, 0.5, 1e-3);
  EXPECT_NEAR(ex.z, 0.5, 1e-3);
  // Random QEFs: the box minimum is no worse than any point of a grid over the box.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.5, 1.5);
  for (int trial = 0; trial < 200; ++trial) {
    Qef r;
    for (int i = 0; i < 4; ++i) {
      const Vec3 n{u(rng), u(rng), u(rng)};
      if (length(n) > 0) r.add({u(rng), u(rng), u(rng)}, n / length(n));
    }
    const Vec3 y = r.solve_in(box, 0.02, 0.05);
    EXPECT_TRUE(box.contains(y));
    if (box.inflated(0.05).contains(r.solve(0.02))) continue;  // unconstrained answer used
    const double ey = r.error(y);
    for (int i = 0; i <= 10; ++i)
      for (int j = 0; j <= 10; ++j)
        for (int k = 0; k <= 10; ++k) EXPECT_LE(ey, r.error({i / 10.0, j / 10.0, k / 10.0}) * 1.01 + 1e-2 * (1 + ey));
  }
  // Without normals: the mass point.
  Qef m;
  m.add_point({0, 0, 0});
  m.add_point({1, 1, 0});
  EXPECT_EQ(m.solve(0.02), (Vec3{0.5, 0.5, 0}));
  // Non-finite input does not leak out.
  Qef bad;
  bad.add({0.5, 0.5, 0.5}, {1, 0, 0});
  bad.add({0.5, 0.5, 0.5}, {0, 1e-300, 0});
  const Vec3 b = bad.solve_in(box, 0.02, 0.05);
  EXPECT_TRUE(box.contains(b));
  EXPECT_TRUE(std::isfinite(b.x) && std::isfinite(b.y) && std::isfinite(b.z));
}

}  // namespace
}  // namespace frep
