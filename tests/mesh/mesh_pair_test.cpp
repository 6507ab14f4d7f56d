// compare_meshes (frep/mesh/mesh_pair.hpp) against brute force over every triangle pair: contact
// counts from the exact triangle-pair classification, the distance and closest triangles from
// triangle_distance2, nesting from the exact winding number; on generated meshes placed at random
// (apart, crossing, nested), on touching and face-to-face boxes, on moved copies, for any thread
// count. triangle_distance2 itself against a convex minimization that shares none of its cases.
// Also the depth search the clearance command runs on two mesh leaves (find_clearance with a
// Lipschitz bound), against its interval form. Real meshes from ../shared where present.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include "frep/convert/mesh_oracle.hpp"
#include "frep/error.hpp"
#include "frep/expr/copy.hpp"
#include "frep/mesh/mesh_distance.hpp"
#include "frep/mesh/mesh_field.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/mesh_pair.hpp"
#include "frep/mesh/topology.hpp"
#include "frep/mesh/tri_tri.hpp"
#include "frep/ugf/clearance.hpp"
#include "mesh_test_util.hpp"

namespace frep {
namespace {

// --- References.

// Minimum of a convex function on [lo, hi] by ternary search (to below 1e-15 of the interval).
template <class F>
double convex_min(F f, double lo, double hi) {
  for (int i = 0; i < 90 && hi > lo; ++i) {
    const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
    if (f(m1) <= f(m2)) hi = m2;
    else lo = m1;
  }
  return f(0.5 * (lo + hi));
}

// Distance between two segments: the distance to segment q is convex along segment p.
double ref_segments(Vec3 p0, Vec3 p1, Vec3 q0, Vec3 q1) {
  return convex_min(
      [&](double s) {
        const Vec3 p = p0 + (p1 - p0) * s;
        return convex_min([&](double t) { return length(p - (q0 + (q1 - q0) * t)); }, 0, 1);
      },
      0, 1);
}

// Distance from a point to a triangle, over the barycentric domain u, v >= 0, u + v <= 1.
double ref_point_triangle(Vec3 p, const Vec3 q[3]) {
  return convex_min(
      [&](double u) {
        return convex_min([&](double v) { return length(p - (q[0] + (q[1] - q[0]) * u + (q[2] - q[0]) * v)); }, 0,
                          1 - u);
      },
      0, 1);
}

double ref_triangles(const Vec3 p[3], const Vec3 q[3]) {
  double best = INFINITY;
  for (int i = 0; i < 3; ++i) {
    best = std::min({best, ref_point_triangle(p[i], q), ref_point_triangle(q[i], p)});
    for (int k = 0; k < 3; ++k) best = std::min(best, ref_segments(p[i], p[(i + 1) % 3], q[k], q[(k + 1) % 3]));
  }
  return best;
}

// Every pair of the two placed meshes: contacts classified as compare_meshes does, the smallest
// (squared distance, a, b) when no pair meets, and nesting from the exact winding number.
struct Brute {
  std::size_t cross = 0, overlap = 0, touch = 0;
  double d2 = INFINITY;
  std::uint32_t a = 0, b = 0;
  std::size_t a_in_b = 0, b_in_a = 0;
};

std::vector<Vec3> placed(const MeshField& f, const Affine3& place) {
  std::vector<Vec3> v = f.welded().vertices;
  if (!place.is_identity())
    for (Vec3& p : v) p = place.apply(p);
  return v;
}

Brute brute(const MeshField& fa, const Affine3& pa, const MeshField& fb, const Affine3& pb) {
  const std::vector<Vec3> va = placed(fa, pa), vb = placed(fb, pb);
  const TriMesh &A = fa.welded(), &B = fb.welded();
  Brute r;
  for (std::uint32_t i = 0; i < A.num_triangles(); ++i)
    for (std::uint32_t j = 0; j < B.num_triangles(); ++j) {
      const Vec3 p[3] = {va[A.triangles[i][0]], va[A.triangles[i][1]], va[A.triangles[i][2]]};
      const Vec3 q[3] = {vb[B.triangles[j][0]], vb[B.triangles[j][1]], vb[B.triangles[j][2]]};
      const unsigned pi[3] = {0, 1, 2}, qi[3] = {3, 4, 5};
      const Contact c = classify_triangle_pair(p, pi, q, qi);
      r.cross += c == Contact::Cross;
      r.overlap += c == Contact::Overlap;
      r.touch += c == Contact::Touch;
      Vec3 x, y;
      const double d2 = triangle_distance2(p, q, x, y);
      if (d2 < r.d2) r.d2 = d2, r.a = i, r.b = j;  // increasing (i, j): the first of equals stays
    }
  // A shell is inside the other solid if its first face's first corner is (surfaces apart).
  const auto inside = [](const MeshField& from, const std::vector<Vec3>& v, const MeshField& to,
                         const std::vector<Vec3>& tv) {
    TriMesh other = to.welded();
    other.vertices = tv;
    const MeshDistance d(other);
    std::size_t n = 0;
    for (std::uint32_t s = 0; s < from.topology().num_shells(); ++s)
      n += d.winding_number_exact(v[from.welded().triangles[from.topology().shell_faces(s)[0]][0]]) > 0.5;
    return n;
  };
  if (r.cross + r.overlap + r.touch == 0) {
    r.a_in_b = inside(fa, va, fb, vb);
    r.b_in_a = inside(fb, vb, fa, va);
  }
  return r;
}

void expect_matches_brute(const MeshPairResult& r, const Brute& b, const std::string& what) {
  SCOPED_TRACE(what);
  EXPECT_EQ(r.crossing, b.cross);
  EXPECT_EQ(r.overlapping, b.overlap);
  EXPECT_EQ(r.touching, b.touch);
  if (b.cross + b.overlap + b.touch == 0) {
    // The same function on the same coordinates (up to a power of two): the same bits.
    EXPECT_EQ(r.distance, std::sqrt(b.d2));
    EXPECT_EQ(r.triangle_a, b.a);
    EXPECT_EQ(r.triangle_b, b.b);
    EXPECT_NEAR(length(r.point_a - r.point_b), r.distance, 1e-12 * (1 + r.distance));
    EXPECT_EQ(r.a_shells_inside_b, b.a_in_b);
    EXPECT_EQ(r.b_shells_inside_a, b.b_in_a);
  } else {
    EXPECT_EQ(r.distance, 0);
    EXPECT_FALSE(r.apart());
  }
}

Affine3 rigid(std::mt19937& rng, double reach) {
  std::normal_distribution<double> n(0, 1);
  std::uniform_real_distribution<double> u(-reach, reach);
  double q[4];
  double l = 0;
  for (double& c : q) c = n(rng), l += c * c;
  l = std::sqrt(l);
  for (double& c : q) c /= l;
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  Affine3 a;
  const double m[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                          {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                          {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) a.m[i][j] = m[i][j];
    a.m[i][3] = u(rng);
  }
  return a;
}

TriMesh moved(TriMesh m, const Vec3& t) {
  for (Vec3& v : m.vertices) v += t;
  return m;
}

// How far a mesh reaches from the origin along the axes: the largest |coordinate|.
double reach(const TriMesh& m) {
  double r = 0;
  for (const Vec3& v : m.vertices) r = std::max({r, std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
  return r;
}

TriMesh joined(TriMesh a, const TriMesh& b) {
  const auto base = static_cast<std::uint32_t>(a.vertices.size());
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  a.origins.clear();  // no provenance for a mesh made in code
  for (std::size_t t = 0; t < b.num_triangles(); ++t)
    a.add_triangle(b.triangles[t][0] + base, b.triangles[t][1] + base, b.triangles[t][2] + base);
  return a;
}

// --- triangle_distance2.

TEST(MeshPair, TriangleDistanceMatchesConvexMinimization) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  int disjoint = 0;
  double worst = 0;
  for (int trial = 0; trial < 240; ++trial) {
    Vec3 p[3], q[3];
    const Vec3 shift{u(rng), u(rng), u(rng)};
    for (int k = 0; k < 3; ++k) {
      p[k] = {u(rng), u(rng), u(rng)};
      q[k] = Vec3{u(rng), u(rng), u(rng)} + shift;
    }
    if (trial % 4 == 1) q[1] = q[0] + (p[1] - p[0]) * 0.7 + Vec3{0, 0, 1e-3};  // nearly parallel edges
    if (trial % 4 == 2) {
      // Parallel planes: face-to-face.
      for (int k = 0; k < 3; ++k) q[k] = p[k] * 0.8 + Vec3{0.05, 0.02, 0} + cross(p[1] - p[0], p[2] - p[0]) * 0.1;
    }
    const unsigned pi[3] = {0, 1, 2}, qi[3] = {3, 4, 5};
    if (classify_triangle_pair(p, pi, q, qi) != Contact::None) continue;  // meeting: 0, not measured here
    ++disjoint;
    Vec3 a, b;
    const double d = std::sqrt(triangle_distance2(p, q, a, b));
    const double ref = ref_triangles(p, q);
    worst = std::max(worst, std::fabs(d - ref));
    EXPECT_NEAR(d, ref, 1e-12) << "trial " << trial;
    // The points are on the triangles, and as far apart as said.
    EXPECT_LT(ref_point_triangle(a, p), 1e-12);
    EXPECT_LT(ref_point_triangle(b, q), 1e-12);
    EXPECT_DOUBLE_EQ(length(a - b), d);
  }
  EXPECT_GT(disjoint, 150);
  std::printf("[mesh-pair] triangle_distance2 vs convex minimization, %d disjoint pairs: max |error| %.2g\n", disjoint,
              worst);
}

TEST(MeshPair, TriangleDistanceOfDegenerateTriangles) {
  // A triangle collapsed to a segment and one collapsed to a point.
  const Vec3 p[3] = {{0, 0, 0}, {2, 0, 0}, {1, 0, 0}};
  const Vec3 q[3] = {{1, 1, 0.5}, {1, 1, 0.5}, {1, 1, 0.5}};
  Vec3 a, b;
  EXPECT_DOUBLE_EQ(std::sqrt(triangle_distance2(p, q, a, b)), std::sqrt(1.25));
  EXPECT_DOUBLE_EQ(a.x, 1);
}

// --- compare_meshes against brute force.

TEST(MeshPair, RandomPlacementsMatchBruteForce) {
  std::mt19937 rng(11);
  const MeshField box(test::make_fine_box(3));
  const MeshField ball(test::make_sphere(2, 0.6));
  const MeshField small(test::make_sphere(1, 0.25));
  int apart = 0, crossing = 0, nested = 0;
  for (int trial = 0; trial < 24; ++trial) {
    const MeshField& fa = trial % 2 ? box : ball;
    const MeshField& fb = trial % 3 ? small : ball;
    // Every fifth placement stays near the origin, where the small ball nests.
    const Affine3 pa = trial % 4 ? Affine3{} : rigid(rng, 0.2), pb = rigid(rng, trial % 5 ? 1.8 : 0.2);
    const MeshPairResult r = compare_meshes({fa, pa}, {fb, pb});
    expect_matches_brute(r, brute(fa, pa, fb, pb), "trial " + std::to_string(trial));
    apart += r.apart();
    crossing += r.crossing > 0;
    nested += r.a_shells_inside_b + r.b_shells_inside_a > 0;
  }
  // The placements cover the three cases.
  EXPECT_GT(apart, 2);
  EXPECT_GT(crossing, 2);
  EXPECT_GT(nested, 0);
}

TEST(MeshPair, TouchingAndFaceToFaceBoxes) {
  const MeshField a(test::make_fine_box(2));
  // Face to face: the box [1, 3] x [-1, 1]^2 shares the plane x = 1 (coplanar pairs overlap).
  const MeshField face(test::make_fine_box(2, {1, -1, -1}, {3, 1, 1}));
  MeshPairResult r = compare_meshes(a, face);
  expect_matches_brute(r, brute(a, {}, face, {}), "face to face");
  EXPECT_GT(r.overlapping, 0u);
  EXPECT_EQ(r.crossing, 0u);
  EXPECT_TRUE(r.surfaces_meet());
  EXPECT_FALSE(r.interfere());
  EXPECT_EQ(r.point_a.x, 1);
  // Corner to corner: [1, 3]^3 meets the box only at (1, 1, 1).
  const MeshField corner(test::make_fine_box(2, {1, 1, 1}, {3, 3, 3}));
  r = compare_meshes(a, corner);
  expect_matches_brute(r, brute(a, {}, corner, {}), "corner");
  EXPECT_GT(r.touching, 0u);
  EXPECT_EQ(r.crossing + r.overlapping, 0u);
  ASSERT_FALSE(r.examples.empty());
  EXPECT_EQ(r.examples.front().kind, PairContact::Touch);
  EXPECT_LT(length(r.examples.front().point - Vec3{1, 1, 1}), 1e-15);
  // A hair apart: [1 + 2^-40, 3]: no contact, the gap exact.
  const double e = std::ldexp(1.0, -40);
  const MeshField near(test::make_fine_box(2, {1 + e, -1, -1}, {3, 1, 1}));
  r = compare_meshes(a, near);
  expect_matches_brute(r, brute(a, {}, near, {}), "a hair apart");
  EXPECT_TRUE(r.apart());
  EXPECT_EQ(r.distance, e);
  // Crossing: moved by half a width.
  const MeshField half(test::make_fine_box(2, {0, -0.5, -0.5}, {2, 1.5, 1.5}));
  r = compare_meshes(a, half);
  expect_matches_brute(r, brute(a, {}, half, {}), "crossing");
  EXPECT_GT(r.crossing, 0u);
  EXPECT_TRUE(r.interfere());
  ASSERT_FALSE(r.examples.empty());
  EXPECT_EQ(r.examples.front().kind, PairContact::Cross);
  // The example point is on both triangles.
  const MeshPairContactExample& ex = r.examples.front();
  const Vec3 p[3] = {a.welded().corner(ex.a, 0), a.welded().corner(ex.a, 1), a.welded().corner(ex.a, 2)};
  const Vec3 q[3] = {half.welded().corner(ex.b, 0), half.welded().corner(ex.b, 1), half.welded().corner(ex.b, 2)};
  EXPECT_LT(ref_point_triangle(ex.point, p), 1e-12);
  EXPECT_LT(ref_point_triangle(ex.point, q), 1e-12);
  // Examples: crossing first, each kind in increasing (a, b), at most max_examples.
  MeshPairOptions o;
  o.max_examples = 3;
  const MeshPairResult few = compare_meshes(a, half, o);
  ASSERT_EQ(few.examples.size(), 3u);
  for (std::size_t i = 1; i < few.examples.size(); ++i)
    EXPECT_TRUE(std::make_pair(few.examples[i - 1].a, few.examples[i - 1].b) <
                std::make_pair(few.examples[i].a, few.examples[i].b));
}

TEST(MeshPair, NestedSolidsAndShells) {
  const MeshField big(test::make_fine_box(3, {-2, -2, -2}, {2, 2, 2}));
  const MeshField ball(test::make_sphere(2, 0.5));
  MeshPairResult r = compare_meshes(big, ball);
  expect_matches_brute(r, brute(big, {}, ball, {}), "ball in box");
  EXPECT_TRUE(r.b_inside_a());
  EXPECT_FALSE(r.a_inside_b());
  EXPECT_TRUE(r.interfere());
  EXPECT_FALSE(r.apart());
  // The ball is convex and the wall flat: the nearest is the ball's farthest vertex along an axis.
  EXPECT_NEAR(r.distance, 2 - reach(ball.welded()), 1e-12);
  // Swapped.
  r = compare_meshes(ball, big);
  EXPECT_TRUE(r.a_inside_b());
  EXPECT_EQ(r.a_shells, 1u);
  // Two shells, one inside the box and one outside.
  const MeshField two(joined(test::make_sphere(1, 0.5), moved(test::make_sphere(1, 0.5), {5, 0, 0})));
  r = compare_meshes(big, two);
  expect_matches_brute(r, brute(big, {}, two, {}), "two shells");
  EXPECT_EQ(r.b_shells, 2u);
  EXPECT_EQ(r.b_shells_inside_a, 1u);
  EXPECT_FALSE(r.b_inside_a());
  EXPECT_TRUE(r.interfere());
  // Nearly concentric spheres: every pair of facing triangles is nearly as close as the closest,
  // which boxes cannot tell apart (the projection bounds must, and must lose nothing).
  const MeshField outer(test::make_sphere(3, 1.0));
  const MeshField inner(moved(test::make_sphere(3, 0.5), {0.01, 0.003, 0}));
  r = compare_meshes(outer, inner);
  expect_matches_brute(r, brute(outer, {}, inner, {}), "nearly concentric spheres");
  EXPECT_TRUE(r.b_inside_a());
  // A ball in a hollow: the box with a cavity, the ball in the cavity, is apart from it.
  TriMesh cavity = test::make_fine_box(2, {-1, -1, -1}, {1, 1, 1});
  for (Triangle& t : cavity.triangles) std::swap(t[1], t[2]);  // inward: the wall of a void
  const MeshField hollow(joined(test::make_fine_box(3, {-2, -2, -2}, {2, 2, 2}), cavity));
  r = compare_meshes(hollow, ball);
  expect_matches_brute(r, brute(hollow, {}, ball, {}), "ball in a cavity");
  EXPECT_TRUE(r.apart());
  EXPECT_NEAR(r.distance, 1 - reach(ball.welded()), 1e-12);
}

TEST(MeshPair, MovedCopiesMatchCopiesMovedByHand) {
  const TriMesh m = test::make_sphere(3, 1.0);
  const MeshField f(m);
  const Vec3 t{2.3, 0.1, -0.2};
  const MeshField by_hand(moved(m, t));
  const MeshPairResult placed_copy = compare_meshes(f, {f, Affine3::translation(t)});
  const MeshPairResult hand = compare_meshes(f, by_hand);
  EXPECT_TRUE(hand.apart());
  EXPECT_EQ(placed_copy.distance, hand.distance);  // a translation places as v + t: the same coordinates
  EXPECT_EQ(placed_copy.triangle_a, hand.triangle_a);
  EXPECT_EQ(placed_copy.triangle_b, hand.triangle_b);
  EXPECT_NEAR(hand.distance, length(t) - 2, 2e-2);  // two faceted unit spheres
  // As a moved mesh leaf holds it: the field is evaluated at p - t, so the placement is its inverse.
  const MeshPairResult leaf = compare_meshes(f, PlacedMesh::moved_field(f, Affine3::translation(-t)));
  EXPECT_EQ(leaf.distance, hand.distance);
  // The whole pair turned about the z axis: the same distance, up to rounding.
  Affine3 rot;
  const double c = std::cos(0.3), s = std::sin(0.3);
  rot.m[0][0] = c, rot.m[0][1] = -s, rot.m[1][0] = s, rot.m[1][1] = c;
  const MeshPairResult turned = compare_meshes({f, rot}, {f, rot * Affine3::translation(t)});
  EXPECT_NEAR(turned.distance, hand.distance, 1e-12);
  // Placements must be invertible and finite.
  Affine3 flat;
  flat.m[2][2] = 0;
  EXPECT_THROW(compare_meshes(f, {f, flat}), InputError);
  EXPECT_THROW(PlacedMesh::moved_field(f, flat), InputError);
  Affine3 inf = Affine3::translation({INFINITY, 0, 0});
  EXPECT_THROW(compare_meshes(f, {f, inf}), InputError);
}

TEST(MeshPair, ResultDoesNotDependOnThreads) {
  const MeshField a(test::make_sphere(4, 1.0));
  const MeshField b(test::make_fine_box(12, {-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5}));
  for (const Affine3& place : {Affine3::translation({2.5, 0.3, 0.2}), Affine3::translation({0.9, 0.1, 0})}) {
    MeshPairOptions o;
    o.threads = 1;
    const MeshPairResult one = compare_meshes(a, {b, place}, o);
    for (int threads : {2, 3, 8}) {
      o.threads = threads;
      const MeshPairResult r = compare_meshes(a, {b, place}, o);
      EXPECT_EQ(r.distance, one.distance);
      EXPECT_EQ(r.triangle_a, one.triangle_a);
      EXPECT_EQ(r.triangle_b, one.triangle_b);
      EXPECT_EQ(r.point_a, one.point_a);
      EXPECT_EQ(r.point_b, one.point_b);
      EXPECT_EQ(r.crossing, one.crossing);
      EXPECT_EQ(r.touching, one.touching);
      ASSERT_EQ(r.examples.size(), one.examples.size());
      for (std::size_t i = 0; i < r.examples.size(); ++i) {
        EXPECT_EQ(r.examples[i].a, one.examples[i].a);
        EXPECT_EQ(r.examples[i].b, one.examples[i].b);
      }
    }
  }
}

TEST(MeshPair, DistanceCanBeSkipped) {
  const MeshField a(test::make_sphere(1, 1.0));
  MeshPairOptions o;
  o.distance = false;
  const MeshPairResult r = compare_meshes(a, {a, Affine3::translation({3, 0, 0})}, o);
  EXPECT_TRUE(r.apart());
  EXPECT_TRUE(std::isnan(r.distance));
}

// --- The depth search of two mesh leaves: a Lipschitz bound from one evaluation per box.

TEST(MeshPair, LipschitzDepthSearchAgreesWithIntervals) {
  const auto a = std::make_shared<const MeshOracle>(test::make_sphere(3, 1.0));
  const auto b = std::make_shared<const MeshOracle>(moved(test::make_fine_box(3, {-0.4, -0.4, -0.4}, {0.4, 0.4, 0.4}), {1.1, 0.2, 0}));
  Model ma = mesh_model(a);
  const Model mb = mesh_model(b);
  const NodeId broot = copy_expression(*ma.graph, *mb.graph, mb.root);
  const Interval x{0.5f, 1.6f}, y{-0.3f, 0.7f}, z{-0.5f, 0.5f};
  ugf::ClearanceOptions o;
  o.max_boxes = 4000;
  const ugf::ClearanceResult iv = ugf::find_clearance(ma.root_expr(), Expr(*ma.graph, broot), x, y, z, o);
  o.lipschitz = 2;
  std::size_t calls = 0;
  o.progress = [&](const ugf::ClearanceProgress& p) {
    EXPECT_LE(p.lower_bound, p.value);
    return ++calls < 1000000;
  };
  const ugf::ClearanceResult lip = ugf::find_clearance(ma.root_expr(), Expr(*ma.graph, broot), x, y, z, o);
  EXPECT_GT(calls, 0u);
  EXPECT_LT(lip.value, 0);
  // Each proven bound is below the value the other attained.
  EXPECT_LE(lip.lower_bound, iv.value);
  EXPECT_LE(iv.lower_bound, lip.value);
  EXPECT_NEAR(lip.value, iv.value, 2e-3);
  // The value is A + B where it says.
  const MeshField& fa = a->field();
  const MeshField& fb = b->field();
  const Vec3 p{lip.x, lip.y, lip.z};
  EXPECT_NEAR(lip.value, fa.signed_distance(p) + fb.signed_distance(p), 1e-6);
  // A progress callback that says stop stops the search.
  o.progress = [](const ugf::ClearanceProgress&) { return false; };
  const ugf::ClearanceResult stopped = ugf::find_clearance(ma.root_expr(), Expr(*ma.graph, broot), x, y, z, o);
  EXPECT_TRUE(stopped.stopped);
  EXPECT_LE(stopped.boxes, 20u);  // the first call, after 16 boxes
  EXPECT_LE(stopped.lower_bound, stopped.value);
}

// --- Real meshes: a part against copies of itself moved along x.

TEST(MeshPair, RealMeshAndMovedCopies) {
  FREP_REQUIRE_SHARED_MESHES();
  for (const char* name : {"fandisk.obj", "armadillo_libigl.obj"}) {
    const TriMesh m = read_mesh(test::shared_mesh_dir() + "/" + name);
    const MeshField f(m);
    const double w = f.box().size().x;
    // 1.3 widths along x: apart by 0.3 widths at least (the extreme faces of these parts face
    // each other, so exactly that for fandisk).
    const auto t0 = std::chrono::steady_clock::now();
    const MeshPairResult gap = compare_meshes(f, {f, Affine3::translation({1.3 * w, 0, 0})});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_TRUE(gap.apart()) << name;
    EXPECT_GE(gap.distance, 0.3 * w * (1 - 1e-12)) << name;
    if (std::string(name) == "fandisk.obj") {
      EXPECT_NEAR(gap.distance, 0.3 * w, 1e-12 * w);
    }
    // A third of a width: the surfaces cross.
    const MeshPairResult third = compare_meshes(f, {f, Affine3::translation({w / 3, 0, 0})});
    EXPECT_GT(third.crossing, 0u) << name;
    EXPECT_TRUE(third.interfere());
    std::printf("[mesh-pair] %s (%zu triangles) and a copy 1.3 widths along x: gap %.9g in %.3f s; a third of a "
                "width: %zu crossing pairs in %.3f s\n",
                name, m.num_triangles(), gap.distance, seconds, third.crossing, third.seconds);
  }
}

}  // namespace
}  // namespace frep
