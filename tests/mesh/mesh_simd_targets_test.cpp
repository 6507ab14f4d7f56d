// The distance oracle's SIMD kernels (4-wide BVH box tests, triangle packets, dipole sums) on
// every instruction set the library was compiled for, not only the CPU's best: closest
// distances against brute force and winding numbers against the exact sum, per target.
#include <gtest/gtest.h>

#include <random>

#include "frep/mesh/mesh_distance.hpp"
#include "mesh_test_util.hpp"
#include "test_util.hpp"

namespace frep {
namespace {

double brute_unsigned(const TriMesh& m, const Vec3& p) {
  double best = INFINITY;
  auto seg = [&](Vec3 a, Vec3 b) {
    const Vec3 ab = b - a;
    const double t = std::clamp(dot(p - a, ab) / dot(ab, ab), 0.0, 1.0);
    return length(p - (a + ab * t));
  };
  for (std::size_t t = 0; t < m.num_triangles(); ++t) {
    const Vec3 a = m.corner(t, 0), b = m.corner(t, 1), c = m.corner(t, 2), n = cross(b - a, c - a);
    const Vec3 q = p - n * (dot(p - a, n) / dot(n, n));
    if (dot(cross(b - a, q - a), n) >= 0 && dot(cross(c - b, q - b), n) >= 0 && dot(cross(a - c, q - c), n) >= 0)
      best = std::min(best, length(p - q));
    best = std::min({best, seg(a, b), seg(b, c), seg(c, a)});
  }
  return best;
}

TEST(MeshSimdTargets, ClosestPointAndWindingNumberOnEveryTarget) {
  const TriMesh sphere = test::make_sphere(2);
  const TriMesh box = test::make_fine_box(3, {-1, -0.5, 0}, {1, 0.5, 0.25});
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-2, 2);
  std::vector<Vec3> pts(400);
  for (Vec3& p : pts) p = {u(rng), u(rng), u(rng)};
  test::for_each_simd_target([&] {
    for (const TriMesh* m : {&sphere, &box}) {
      const MeshDistance md(*m);
      for (const Vec3& p : pts) {
        ASSERT_NEAR(md.unsigned_distance(p), brute_unsigned(*m, p), 1e-12);
        ASSERT_NEAR(md.winding_number(p), md.winding_number_exact(p), 0.06);  // dipole far field (documented)
        if (std::fabs(md.winding_number_exact(p) - 0.5) > 0.1) {
          ASSERT_EQ(md.signed_distance(p, SignMethod::WindingNumber) < 0, md.winding_number_exact(p) > 0.5);
        }
      }
    }
  });
}

}  // namespace
}  // namespace frep
