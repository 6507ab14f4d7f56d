// The figures docs/ugf.md gives for find_clearance, asserted as stated: the value found (the
// gap, or minus the interference depth) is the exact one to 3e-7 for two spheres of radius
// below 1 (where the exact answer is known in closed form; A + B is evaluated in floats, whose
// spacing is 1.2e-7 between 1 and 2, so a few roundings are all that is left), with the default
// 20000 boxes, over random pairs apart and interfering; and the proven lower bound, which closes
// in slowly, is never above it, and at most 0.06 below the value in the box of side 6 searched.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "frep/expr/expr.hpp"
#include "frep/ugf/clearance.hpp"

namespace frep {
namespace {

TEST(ClearanceFigures, ValueFoundTo3e7OnSpheres) {
  std::mt19937_64 rng(2024);
  auto u = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  double worst = 0, slowest = 0;
  int interfering = 0;
  for (int rep = 0; rep < 64; ++rep) {
    // Centres and radii as floats: the expressions hold them exactly, so the exact answer below
    // is the expressions' own.
    const float ax = float(u(-1.2, -0.1)), ay = float(u(-1, 1)), az = float(u(-1, 1)), ar = float(u(0.2, 0.9));
    const float bx = float(u(0.1, 1.2)), by = float(u(-1, 1)), bz = float(u(-1, 1)), br = float(u(0.2, 0.9));
    const double d = std::sqrt(double(bx - ax) * (bx - ax) + double(by - ay) * (by - ay) + double(bz - az) * (bz - az));
    const double gap = d - ar - br;  // the minimum of A + B over space
    // Both bodies inside [-3, 3]^3, the region searched.
    Graph g;
    const Expr x = g.x(), y = g.y(), z = g.z();
    const Expr A = sqrt(square(x - ax) + square(y - ay) + square(z - az)) - ar;
    const Expr B = sqrt(square(x - bx) + square(y - by) + square(z - bz)) - br;
    ugf::ClearanceOptions o;
    o.max_boxes = 20000;  // frep clearance's default
    const ugf::ClearanceResult r = ugf::find_clearance(A, B, {-3, 3}, {-3, 3}, {-3, 3}, o);
    const double err = std::fabs(double(r.value) - gap);
    worst = std::max(worst, err);
    interfering += gap < 0;
    EXPECT_LE(err, 3e-7) << "gap " << gap << ", found " << r.value;
    EXPECT_LE(r.lower_bound, r.value);
    EXPECT_LE(double(r.lower_bound), gap + 3e-7);
    EXPECT_LE(r.value - r.lower_bound, 0.06) << "gap " << gap;
    slowest = std::max(slowest, double(r.value - r.lower_bound));
  }
  EXPECT_GE(interfering, 5);  // both kinds of answer are covered
  EXPECT_LE(interfering, 59);
  std::printf("[clearance] two spheres, 64 random pairs (%d interfering): max |value - exact| = %.3g, lower bound up to %.3g below\n",
              interfering, worst, slowest);
}

}  // namespace
}  // namespace frep
