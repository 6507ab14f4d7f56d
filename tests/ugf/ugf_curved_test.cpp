// Edge operations on curved inputs (two intersecting spheres): every operation's value and
// gradient are finite everywhere the inputs' are, including on the edge circle and at the
// spheres' centers; and the distance-preserving intersection, exact only for planes, is measured
// against the exact distance to the lens (reported, and required to beat max(A, B) near the edge).
#include <gtest/gtest.h>

#include "frep/ugf.hpp"
#include "ugf/ugf_test_util.hpp"

namespace frep {
namespace {

using namespace ugf_test;
using P3 = std::array<float, 3>;
using D3 = std::array<double, 3>;

double dist(const D3& a, const D3& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

// Two balls along the x axis and the exact signed distance to their intersection (a lens).
struct Lens {
  D3 ca{-0.5, 0, 0}, cb{0.6, 0, 0};
  double ra = 1.0, rb = 0.8;

  double sdf(const D3& p) const {
    const double da = dist(p, ca), db = dist(p, cb);
    if (da <= ra && db <= rb) return std::max(da - ra, db - rb);  // convex: exact inside
    // The edge circle: on the plane x = xc, radius rc.
    const double d = cb[0] - ca[0];
    const double xa = (d * d + ra * ra - rb * rb) / (2 * d);
    const double xc = ca[0] + xa, rc = std::sqrt(ra * ra - xa * xa);
    const double rho = std::sqrt(p[1] * p[1] + p[2] * p[2]);
    double best = std::sqrt((p[0] - xc) * (p[0] - xc) + (rho - rc) * (rho - rc));
    // The nearest point of each sphere, if it lies on the lens's part of that sphere.
    auto project = [&](const D3& c, double r, const D3& oc, double orr) {
      const double l = dist(p, c);
      if (l == 0) return;
      const D3 q = {c[0] + r * (p[0] - c[0]) / l, c[1] + r * (p[1] - c[1]) / l, c[2] + r * (p[2] - c[2]) / l};
      if (dist(q, oc) <= orr) best = std::min(best, std::fabs(l - r));
    };
    project(ca, ra, cb, rb);
    project(cb, rb, ca, ra);
    return best;
  }
};

TEST(UgfCurved, EveryOperationStaysFinite) {
  const Lens lens;
  Graph g;
  auto sphere = [&](const D3& c, double r) {
    return sqrt(square(g.x() - float(c[0])) + square(g.y() - float(c[1])) + square(g.z() - float(c[2]))) - float(r);
  };
  const Expr A = sphere(lens.ca, lens.ra), B = sphere(lens.cb, lens.rb);
  const ugf::EdgeFrame f = ugf::edge_frame(A, B);
  const std::vector<std::pair<std::string, Expr>> ops = {
      {"intersect_exact", ugf::intersect_exact(A, B)},
      {"unite_exact", ugf::unite_exact(A, B)},
      {"subtract_exact", ugf::subtract_exact(A, B)},
      {"intersect_right_angle", ugf::intersect_right_angle(A, B)},
      {"unite_right_angle", ugf::unite_right_angle(A, B)},
      {"chamfer_intersection width", ugf::chamfer_intersection(f, ugf::Chamfer::width(0.3f))},
      {"chamfer_intersection setbacks exact",
       ugf::chamfer_intersection(f, ugf::Chamfer::setbacks(0.2f, 0.4f).distance_preserving())},
      {"chamfer_union setback", ugf::chamfer_union(f, ugf::Chamfer::setback(0.3f))},
      {"round_intersection", ugf::round_intersection(f, 0.2f)},
      {"round_union", ugf::round_union(f, 0.2f)},
      {"pencil_chamfer", ugf::pencil_chamfer(f, 0.2f, -0.1f)},
      {"smooth_union", ugf::smooth_union(A, B, 0.3f)},
      {"two_body", ugf::two_body(A, B)},
      {"between", ugf::between(A, B, 0.3f)},
      {"shell_variable", ugf::shell_variable(A, 0.1f + 0.05f * abs(B))},
      {"normalize", ugf::normalize(A * B)},
  };
  // Random points, the spheres' centers, points on the edge circle and on the axis.
  std::mt19937_64 rng(101);
  std::vector<P3> pts;
  for (int i = 0; i < 400; ++i) {
    std::uniform_real_distribution<double> u(-2, 2);
    pts.push_back({float(u(rng)), float(u(rng)), float(u(rng))});
  }
  const double d = lens.cb[0] - lens.ca[0], xa = (d * d + lens.ra * lens.ra - lens.rb * lens.rb) / (2 * d);
  const double rc = std::sqrt(lens.ra * lens.ra - xa * xa);
  for (int i = 0; i < 16; ++i) {
    const double t = 2 * M_PI * i / 16;
    pts.push_back({float(lens.ca[0] + xa), float(rc * std::cos(t)), float(rc * std::sin(t))});
  }
  for (float x : {-0.5f, 0.6f, 0.0f, 1.4f, -1.5f}) pts.push_back({x, 0.0f, 0.0f});
  for (const auto& [name, e] : ops) {
    Probe F(e);
    for (const P3& p : pts) {
      // The two-body field is infinite where A + B = 0 (inside the overlap): skip those.
      if (name == "two_body" && !std::isfinite(F(p))) continue;
      const Grad gr = F.grad(p);
      ASSERT_TRUE(std::isfinite(gr.v) && std::isfinite(gr.dx) && std::isfinite(gr.dy) && std::isfinite(gr.dz))
          << name << " at (" << p[0] << ", " << p[1] << ", " << p[2] << ")";
    }
  }
}

TEST(UgfCurved, ExactIntersectionOfSpheresIsCloserThanMax) {
  const Lens lens;
  Graph g;
  auto sphere = [&](const D3& c, double r) {
    return sqrt(square(g.x() - float(c[0])) + square(g.y() - float(c[1])) + square(g.z() - float(c[2]))) - float(r);
  };
  const Expr A = sphere(lens.ca, lens.ra), B = sphere(lens.cb, lens.rb);
  Probe E(ugf::intersect_exact(A, B)), M(max(A, B));
  std::mt19937_64 rng(102);
  ErrorStat exact_err, max_err, near_exact, near_max;
  for (int i = 0; i < 3000; ++i) {
    std::uniform_real_distribution<double> u(-2, 2);
    const P3 p{float(u(rng)), float(u(rng)), float(u(rng))};
    const double r = lens.sdf({p[0], p[1], p[2]});
    const double e = std::fabs(E(p) - r), m = std::fabs(M(p) - r);
    exact_err.add(e);
    max_err.add(m);
    if (r < 0.1) near_exact.add(e), near_max.add(m);
  }
  report("intersect_exact of two spheres vs the lens (approximate)", exact_err);
  report("max of two spheres vs the lens", max_err);
  report("intersect_exact of spheres, within 0.1 of the lens", near_exact);
  report("max of spheres, within 0.1 of the lens", near_max);
  // First-order exact at the edge: near it the error is far smaller than max's.
  EXPECT_LT(near_exact.max_err, 0.25 * near_max.max_err);
  EXPECT_LT(exact_err.max_err, max_err.max_err);
}

}  // namespace
}  // namespace frep
