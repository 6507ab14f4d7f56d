// The model tape in view coordinates: values equal the model's at the corresponding points
// (with the bounds cut), from named and rotated views, on random expressions, squared distances
// and a converted mesh; under rotation, affine values (planes) and squared distances are bounded
// exactly over view boxes; and chains of affine values as long as the model do not recurse.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "frep/convert/convert.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/expr/expr.hpp"
#include "mesh_test_util.hpp"
#include "render/view_tape.hpp"
#include "test_util.hpp"

namespace frep {
namespace {

Camera camera(const Box3& bounds, double yaw, double pitch) { return make_camera(bounds, yaw, pitch, 32); }

// max(f(p), box(p)) for rotated cameras, f(p) for axis-aligned ones, at p = to_model(u, v, w),
// in double from the model's own f32 value.
double reference(PointEvaluator& pe, const Tape& model, const Camera& cam, const Box3& bounds, double u, double v,
                 double w) {
  const Vec3 p = cam.to_model(u, v, w);
  double f = pe.eval(model, static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z));
  if (cam.axis_aligned) return f;
  double box = -INFINITY;
  for (int a = 0; a < 3; ++a) box = std::max(box, std::fabs(p[a] - cam.center[a]) - bounds.size()[a] / 2);
  return std::max(f, box);
}

// Compares the view tape with the model at random points of the view volume; `tol` is relative
// to the larger of |value| and the bounds' size.
void expect_same_values(const Tape& model, const Box3& bounds, double yaw, double pitch, double tol, const std::string& what) {
  const Camera cam = camera(bounds, yaw, pitch);
  const Tape view = view_tape(model, cam, bounds);
  PointEvaluator pe;
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> unit(-1, 1);
  const double scale = length(bounds.size());
  int failures = 0;
  for (int i = 0; i < 400; ++i) {
    const float u = static_cast<float>(unit(rng) * cam.half_u), v = static_cast<float>(unit(rng) * cam.half_v),
                w = static_cast<float>(unit(rng) * cam.half_w);
    const double got = pe.eval(view, u, v, w);
    const double want = reference(pe, model, cam, bounds, u, v, w);
    if (std::isnan(want) && std::isnan(got)) continue;
    const double bound = tol * std::max(std::fabs(want), scale);
    if (!(std::fabs(got - want) <= bound) && failures++ < 5)
      ADD_FAILURE() << what << " (yaw " << yaw << ", pitch " << pitch << ") at view (" << u << ", " << v << ", " << w
                    << "): " << got << ", model " << want;
  }
}

TEST(ViewTape, ValuesMatchTheModelFromEveryView) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  // Planes, offsets, products and a gated combination, as converted meshes build them.
  const Expr plane = x * 0.36f + y * -0.48f + z * 0.8f - 0.1f;
  const Expr e = max(min(square(plane), square(x - 0.25f) + square(y + 0.5f) + square(z)),
                     (plane + (x - y) * 0.5f) * -3.0f) - 0.2f;
  const Tape t = Tape::compile(g, e.id());
  const Box3 bounds{{-1, -1.5, -1}, {1, 1, 2}};
  for (double yaw : {0.0, 35.0, 90.0, 217.0})
    for (double pitch : {0.0, -30.0, 61.0}) expect_same_values(t, bounds, yaw, pitch, 1e-5, "mixed expression");
}

// Squared distances to points and segments, written as converted meshes write them (offsets
// from a vertex, the clamped position along an edge times the edge's step per axis), scaled.
TEST(ViewTape, SquaredDistancesMatchTheModel) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  const Expr ox = x - 0.3f, oy = y + 0.2f, oz = z - 0.1f;
  const Expr s = ox * 0.5f + oy * -0.25f + oz;  // position along the edge
  const Expr sc = max(min(s, 0.9f), 0.0f);
  const Expr segment = square(ox - sc * 0.5f) + (square(oy + sc * 0.25f) + square(oz - sc));
  const Expr point = (square(ox * 2.0f) + square(oy * -2.0f)) + square(oz * 2.0f);
  const Expr e = min(segment, point * 0.25f) - 0.05f;
  const Tape t = Tape::compile(g, e.id());
  const Box3 bounds{{-1, -1, -1}, {1, 1, 1}};
  for (double yaw : {20.0, 135.0})
    for (double pitch : {-35.0, 10.0}) expect_same_values(t, bounds, yaw, pitch, 1e-5, "squared distances");
}

// Under rotation, a squared distance to a point is bounded over a view box by its exact range.
TEST(ViewTape, SquaredDistancesAreBoundedExactlyUnderRotation) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  const Vec3 c{0.4, -0.3, 0.2};
  const Expr d2 = square(x - static_cast<float>(c.x)) + square(y - static_cast<float>(c.y)) + square(z - static_cast<float>(c.z));
  const Box3 bounds{{-1, -1, -1}, {1, 1, 1}};
  const Camera cam = camera(bounds, 35, -30);
  const Tape view = view_tape(Tape::compile(g, d2.id()), cam, bounds);
  IntervalEvaluator ie;
  const Interval r = ie.eval(view, {-0.05f, 0.05f}, {-0.05f, 0.05f}, {-0.05f, 0.05f});
  // The exact range over the view box [-0.05, 0.05]^3: per view axis, the range of (q_j - c'_j)^2.
  const Vec3 d = c - cam.center;
  const double cp[3] = {dot(d, cam.right), dot(d, cam.up), dot(d, cam.toward)};
  double lo = 0, hi = 0;
  for (double cj : cp) {
    const double a = -0.05 - cj, b = 0.05 - cj;
    lo += (a <= 0 && b >= 0) ? 0 : std::min(a * a, b * b);
    hi += std::max(a * a, b * b);
  }
  EXPECT_NEAR(r.lo, lo, 1e-5);
  EXPECT_NEAR(r.hi, hi, 1e-5);
}

TEST(ViewTape, RandomExpressionsMatchTheModel) {
  std::mt19937_64 rng(5);
  for (int e = 0; e < 60; ++e) {
    Graph g;
    test::GenOptions opt;
    opt.max_depth = 3 + e % 4;
    opt.special_const_prob = 0;  // finite, moderate constants: the comparison is of roundings
    opt.const_range = 2.0f;
    test::ExprGen gen(g, rng, opt);
    const Tape t = Tape::compile(g, gen.gen());
    // Random expressions may amplify rounding (divisions by near-zero values): compare where
    // both agree to a loose bound, which still catches a wrong coefficient or a dropped term.
    const Box3 bounds{{-1, -1, -1}, {1, 1, 1}};
    const Camera cam = camera(bounds, 30 + e, -20);
    const Tape view = view_tape(t, cam, bounds);
    PointEvaluator pe;
    int close = 0, total = 0;
    std::uniform_real_distribution<double> unit(-1, 1);
    for (int i = 0; i < 50; ++i) {
      const float u = static_cast<float>(unit(rng) * cam.half_u), v = static_cast<float>(unit(rng) * cam.half_v),
                  w = static_cast<float>(unit(rng) * cam.half_w);
      const double got = pe.eval(view, u, v, w), want = reference(pe, t, cam, bounds, u, v, w);
      if (!std::isfinite(want)) continue;
      ++total;
      close += std::fabs(got - want) <= 1e-3 * std::max(1.0, std::fabs(want));
    }
    EXPECT_GE(close, total * 9 / 10) << "random expression #" << e;
  }
}

TEST(ViewTape, ConvertedMeshMatchesFromARotatedView) {
  const TriMesh mesh = test::make_box({0, 0, 0}, {1, 1, 1});
  const ConvertResult r = convert_mesh(mesh, {});
  const Tape t = Tape::compile(*r.model.graph, r.model.root);
  const Box3 bounds{{-0.2, -0.2, -0.2}, {1.2, 1.2, 1.2}};
  expect_same_values(t, bounds, 40, -25, 1e-5, "converted cube");
}

// Converted meshes need exact ties: beyond the end of a crease edge, its clamped distance equals
// the end vertex's, and where the vertex has a term of its own, that term must win (the edge's
// sign does not hold there). The view tape rewrites both squared distances; written differently
// (an edge interpolated between two vertex terms used to be left in model coordinates, whose
// rounding far from the origin is coarser than the vertex's shrink), the edge won and whole
// regions came out inside. A bumpy sphere (saddles, so vertex terms) far from the origin.
TEST(ViewTape, ConvertedMeshKeepsItsSignsFarFromTheOrigin) {
  TriMesh mesh = test::make_sphere(2);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> bump(0.7, 1.3);
  for (Vec3& v : mesh.vertices) v = v * bump(rng) + Vec3{1800, 2400, 600};
  const ConvertResult r = convert_mesh(mesh, {});
  const Tape t = Tape::compile(*r.model.graph, r.model.root);
  Box3 bounds = r.model.info.bounds;
  bounds = bounds.inflated(0.5);
  PointEvaluator pe;
  std::uniform_real_distribution<double> unit(-1, 1);
  int wrong = 0, total = 0;
  for (double yaw : {45.0, 120.0})
    for (double pitch : {35.26, -20.0}) {
      const Camera cam = camera(bounds, yaw, pitch);
      const Tape view = view_tape(t, cam, bounds);
      for (int i = 0; i < 1500; ++i) {
        const float u = static_cast<float>(unit(rng) * cam.half_u), v = static_cast<float>(unit(rng) * cam.half_v),
                    w = static_cast<float>(unit(rng) * cam.half_w);
        const double got = pe.eval(view, u, v, w), want = reference(pe, t, cam, bounds, u, v, w);
        if (std::fabs(want) < 1e-4) continue;
        ++total;
        if ((got < 0) != (want < 0) && wrong++ < 5)
          ADD_FAILURE() << "yaw " << yaw << ", pitch " << pitch << " at view (" << u << ", " << v << ", " << w
                        << "): " << got << ", model " << want;
      }
    }
  EXPECT_EQ(wrong, 0) << "of " << total;
}

// Under rotation, a plane through the view's variables is bounded over a view box by its exact
// range (up to rounding), not by the range over the box's axis-aligned hull in model space.
TEST(ViewTape, PlanesAreBoundedExactlyUnderRotation) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  const Vec3 n{0.36, -0.48, 0.8};
  const Expr plane = x * static_cast<float>(n.x) + y * static_cast<float>(n.y) + z * static_cast<float>(n.z);
  const Box3 bounds{{-1, -1, -1}, {1, 1, 1}};
  const Camera cam = camera(bounds, 35, -30);
  ASSERT_FALSE(cam.axis_aligned);
  const Tape view = view_tape(Tape::compile(g, plane.id()), cam, bounds);
  IntervalEvaluator ie;
  const double h = 0.1;  // a small box at the centre, where the bounds cut is far below
  const Interval r = ie.eval(view, {-0.05f, 0.05f}, {-0.05f, 0.05f}, {-0.05f, 0.05f});
  const double exact = h * (std::fabs(dot(n, cam.right)) + std::fabs(dot(n, cam.up)) + std::fabs(dot(n, cam.toward)));
  double hull = 0;  // what x, y, z bounded separately give
  for (int a = 0; a < 3; ++a)
    hull += std::fabs(n[a]) * h * (std::fabs(cam.right[a]) + std::fabs(cam.up[a]) + std::fabs(cam.toward[a]));
  ASSERT_GT(hull, 1.2 * exact) << "the test needs a rotation where the hull is loose";
  EXPECT_LE(static_cast<double>(r.hi) - r.lo, exact * (1 + 1e-5) + 1e-6);
  EXPECT_GE(static_cast<double>(r.hi) - r.lo, exact * (1 - 1e-5) - 1e-6);
}

TEST(ViewTape, LongAffineChainsAreFine) {
  // Scalings of one combination of axes: each is built from the one before, 200,000 deep.
  Graph g;
  Expr e = g.x() + g.y();
  for (int i = 0; i < 200000; ++i) e = i % 3 == 2 ? -e : e * (i % 3 ? 1.5f : 0.6666667f);
  const Tape t = Tape::compile(g, e.id());
  expect_same_values(t, {{-1, -1, -1}, {1, 1, 1}}, 30, 20, 1e-4, "long chain");
}

}  // namespace
}  // namespace frep
