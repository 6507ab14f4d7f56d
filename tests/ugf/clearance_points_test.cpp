// The points that name a clearance (frep/ugf/clearance.hpp): projections onto a surface, and the
// deepest point of two overlapping spheres, against their closed forms; the tolerance test of a
// result; the region two bodies share.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "frep/eval/evaluators.hpp"
#include "frep/expr/expr.hpp"
#include "frep/ugf/clearance.hpp"

namespace frep {
namespace {

Expr sphere(Graph& g, const Vec3f& c, float r) {
  const Expr x = g.x(), y = g.y(), z = g.z();
  return sqrt(square(x - c.x) + square(y - c.y) + square(z - c.z)) - r;
}

// The distance from q to the line through a and b.
double distance_to_line(const Vec3& q, const Vec3& a, const Vec3& b) {
  return length(cross(q - a, b - a)) / length(b - a);
}

TEST(ClearancePoints, ProjectionLandsOnASphereAlongTheRadius) {
  Graph g;
  const Vec3f c{0.3f, -0.2f, 0.1f};
  const float r = 0.7f;
  const Tape t = Tape::compile(g, sphere(g, c, r).id());
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<float> u(-2, 2);
  for (int i = 0; i < 500; ++i) {
    const Vec3f p{u(rng), u(rng), u(rng)};
    if (length(Vec3(p) - Vec3(c)) < 0.05) continue;  // the gradient turns about the centre
    const Vec3 q = ugf::project_to_surface(t, p);
    EXPECT_NEAR(length(q - Vec3(c)), r, 1e-6) << i;
    EXPECT_LT(distance_to_line(q, Vec3(c), Vec3(p)), 1e-6) << i;
    EXPECT_GT(dot(q - Vec3(c), Vec3(p) - Vec3(c)), 0) << i;  // on the side of p
  }
}

TEST(ClearancePoints, ProjectionOntoAPlaneIsExactAndKeepsPointsWithoutGradient) {
  Graph g;
  const Expr x = g.x(), y = g.y(), z = g.z();
  // The plane 0.6 x + 0.8 z = 0.5, a signed distance.
  const Tape plane = Tape::compile(g, (x * 0.6f + z * 0.8f - 0.5f).id());
  const Vec3 q = ugf::project_to_surface(plane, {2, 1, -1});
  EXPECT_NEAR(0.6 * q.x + 0.8 * q.z, 0.5, 1e-6);
  EXPECT_NEAR(q.y, 1, 1e-12);
  // Moved along the normal only: (2, -1) - (0.6, 0.8) k.
  EXPECT_NEAR((q.x - 2) * 0.8 - (q.z + 1) * 0.6, 0, 1e-6);
  // A constant field has no surface to go to: the point stays.
  const Tape flat = Tape::compile(g, (y * 0.0f + 1.0f).id());
  EXPECT_EQ(ugf::project_to_surface(flat, {0.25f, -3, 7}), Vec3(0.25, -3, 7));
}

// Two overlapping spheres: A + B is r1 + r2 - d below zero all along the segment between the
// centres, and its deepest point, where both depths are half that, is at r1 - depth / 2 from c1.
TEST(ClearancePoints, DeepestPointOfOverlappingSpheres) {
  Graph g;
  const Vec3f c1{-0.2f, 0.1f, 0.0f}, c2{1.0f, 0.4f, -0.3f};
  const float r1 = 0.9f, r2 = 0.6f;
  const Expr A = sphere(g, c1, r1), B = sphere(g, c2, r2);
  const Tape ta = Tape::compile(g, A.id()), tb = Tape::compile(g, B.id());
  const double d = length(Vec3(c2) - Vec3(c1));
  const double depth = r1 + r2 - d;
  ASSERT_GT(depth, 0.2);
  const Vec3 want = Vec3(c1) + (Vec3(c2) - Vec3(c1)) * ((r1 - depth / 2) / d);
  PointEvaluator pe;

  // From the point the search finds: A + B is that close to its minimum there, which allows it
  // about sqrt(1e-6) off the segment.
  const ugf::ClearanceResult r = ugf::find_clearance(A, B, {-2, 2}, {-2, 2}, {-2, 2});
  EXPECT_NEAR(r.value, -depth, 1e-6);
  ugf::DeepestPoint p = ugf::deepest_point(ta, tb, {r.x, r.y, r.z});
  EXPECT_TRUE(p.inside_both);
  EXPECT_LT(length(p.point - want), 2e-3);
  const Vec3f found(p.point);
  EXPECT_NEAR(pe.eval(ta, found.x, found.y, found.z), -depth / 2, 1e-4);
  EXPECT_NEAR(pe.eval(tb, found.x, found.y, found.z), -depth / 2, 1e-4);

  // From anywhere on the segment, even inside A only (near c1) or B only (near c2).
  for (const double s : {0.02, 0.3, 0.5, 0.8, 0.97}) {
    const Vec3f on(Vec3(c1) + (Vec3(c2) - Vec3(c1)) * s);
    p = ugf::deepest_point(ta, tb, on);
    EXPECT_TRUE(p.inside_both) << s;
    EXPECT_LT(distance_to_line(p.point, Vec3(c1), Vec3(c2)), 1e-5) << s;
    EXPECT_LT(length(p.point - want), 1e-5) << s;
    const Vec3f q(p.point);
    EXPECT_NEAR(pe.eval(ta, q.x, q.y, q.z), -depth / 2, 1e-5) << s;
    EXPECT_NEAR(pe.eval(tb, q.x, q.y, q.z), -depth / 2, 1e-5) << s;
  }
}

// Bodies that share no volume have no deepest point: the point given comes back, said not to
// be inside both.
TEST(ClearancePoints, DeepestPointOfDisjointSpheresIsThePointGiven) {
  Graph g;
  const Tape ta = Tape::compile(g, sphere(g, {-1, 0, 0}, 0.5f).id());
  const Tape tb = Tape::compile(g, sphere(g, {1, 0, 0}, 0.5f).id());
  const ugf::DeepestPoint p = ugf::deepest_point(ta, tb, {0, 0.1f, 0});
  EXPECT_FALSE(p.inside_both);
  EXPECT_EQ(p.point, Vec3(Vec3f(0, 0.1f, 0)));
}

TEST(ClearancePoints, WithinToleranceNeedsConvergenceAndAClosedGap) {
  ugf::ClearanceResult r;
  r.value = -0.5f;
  r.lower_bound = -0.5f - 1e-4f;
  r.converged = true;
  EXPECT_TRUE(r.within_tolerance(1e-4));  // as the search compared it, in float
  EXPECT_FALSE(r.within_tolerance(5e-5));
  r.converged = false;
  EXPECT_FALSE(r.within_tolerance(1e-4));
}

TEST(ClearancePoints, SharedRegionIsTheIntersectionPadded) {
  const Box3 s = ugf::shared_region({{-1, -1, -1}, {1, 1, 1}}, {{0, -3, 0.5}, {4, 0, 2}});
  const double pad = 1e-3 * length(Vec3{1, 1, 0.5});
  EXPECT_EQ(s.lo, Vec3(0 - pad, -1 - pad, 0.5 - pad));
  EXPECT_EQ(s.hi, Vec3(1 + pad, 0 + pad, 1 + pad));
}

}  // namespace
}  // namespace frep
