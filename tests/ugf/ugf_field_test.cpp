// Smooth blends (bounds: never larger than the distance to their own zero set), the two-body
// field and clearance, Sampson normalization and the gyroid, and medial-axis tracking, against
// independent references in double precision.
#include <gtest/gtest.h>

#include "frep/ugf.hpp"
#include "ugf/ugf_test_util.hpp"

namespace frep {
namespace {

using namespace ugf_test;
using P3 = std::array<float, 3>;

// ---------------------------------------------------------------------------------------------
// Smooth blends

// The blend of two planes is monotone along any direction m that increases both arguments, so
// its zero set crosses each line q(s) + tau m once: found by bisection, it gives a polyline whose
// distance is the reference.
TEST(UgfBlends, NeverOverestimateTheDistanceToTheirZeroSet) {
  std::mt19937_64 rng(91);
  const ugf::Blend blends[] = {ugf::Blend::Quadratic, ugf::Blend::Cubic, ugf::Blend::Exponential, ugf::Blend::Root};
  const char* names[] = {"quadratic", "cubic", "exponential", "root"};
  for (int bi = 0; bi < 4; ++bi) {
    ErrorStat viol, grad_excess;
    double slack = 0;  // how far below the distance the blend gets: it must be a real blend
    for (double deg : {30.0, 90.0, 150.0}) {
      const Wedge w = Wedge::symmetric(deg * M_PI / 180);
      const Frame3 fr = Frame3::random(rng);
      Graph g;
      const Expr A = fr.plane(g, w.nA, 0), B = fr.plane(g, w.nB, 0);
      const float k = 0.5f;
      // (field, direction increasing it): union and intersection of (A, B), difference A - B.
      const std::vector<std::pair<Expr, V2>> ops = {
          {ugf::smooth_union(A, B, k, blends[bi]), w.nS()},
          {ugf::smooth_intersection(A, B, k, blends[bi]), w.nS()},
          {ugf::smooth_difference(A, B, k, blends[bi]), w.nD()},
      };
      for (const auto& [f, m] : ops) {
        Probe F(f);
        const V2 across{-m.y, m.x};
        std::vector<V2> zero;
        for (int i = 0; i <= 1200; ++i) {
          const V2 base = (-6.0 + 12.0 * i / 1200) * across;
          double lo = -30, hi = 30;
          for (int it = 0; it < 40; ++it) {
            const double mid = 0.5 * (lo + hi);
            (F.exact(fr.point_d(base + mid * m, 0)) > 0 ? hi : lo) = mid;
          }
          zero.push_back(base + (0.5 * (lo + hi)) * m);
        }
        for (int i = 0; i < 300; ++i) {
          const V2 q{std::uniform_real_distribution<double>(-2, 2)(rng), std::uniform_real_distribution<double>(-2, 2)(rng)};
          const auto p = fr.point(q, std::uniform_real_distribution<double>(-2, 2)(rng));
          const V2 ql = fr.local(p);
          double d = 1e300;
          for (std::size_t j = 0; j + 1 < zero.size(); ++j) d = std::min(d, segment_distance(ql, zero[j], zero[j + 1]));
          const double v = F(p);
          viol.add(std::max(0.0, std::fabs(v) - d));
          slack = std::max(slack, d - std::fabs(v));
          // The gradient is a convex combination of unit gradients: at most 1 long.
          grad_excess.add(std::max(0.0, length3(F.grad(p)) - 1));
        }
      }
    }
    report(std::string("smooth blend ") + names[bi], viol, "max |value| - distance");
    report(std::string("smooth blend ") + names[bi], grad_excess, "max |grad| - 1 (f32)");
    // Polyline chords lie off the curve (which only loosens this) and f32 rounding.
    EXPECT_LE(viol.max_err, 2e-6) << names[bi];
    EXPECT_LE(grad_excess.max_err, 2e-6) << names[bi];
    EXPECT_GT(slack, 0.01) << names[bi] << ": the blend never differs from the distance";
  }
}

// Away from the blend (|a - b| >= k) the polynomial blends are exactly min / max.
TEST(UgfBlends, PolynomialBlendsAreMinOutsideTheBlendZone) {
  Graph g;
  auto x = g.x(), y = g.y();
  for (ugf::Blend b : {ugf::Blend::Quadratic, ugf::Blend::Cubic}) {
    Probe U(ugf::smooth_union(x, y, 0.5f, b)), I(ugf::smooth_intersection(x, y, 0.5f, b));
    EXPECT_EQ(U({0.2f, 0.9f, 0}), 0.2f);
    EXPECT_EQ(I({0.2f, 0.9f, 0}), 0.9f);
    EXPECT_LT(U({0.2f, 0.3f, 0}), 0.2f);
    EXPECT_GT(I({0.2f, 0.3f, 0}), 0.3f);
  }
}

// ---------------------------------------------------------------------------------------------
// Two bodies

struct Sphere {
  std::array<double, 3> c;
  double r;
  Expr sdf(Graph& g) const {
    return sqrt(square(g.x() - float(c[0])) + square(g.y() - float(c[1])) + square(g.z() - float(c[2]))) - float(r);
  }
  P3 surface_point(std::mt19937_64& rng) const {
    std::normal_distribution<double> n(0, 1);
    double d[3] = {n(rng), n(rng), n(rng)};
    const double l = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    return {float(c[0] + r * d[0] / l), float(c[1] + r * d[1] / l), float(c[2] + r * d[2] / l)};
  }
};

double distance3(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

TEST(UgfTwoBody, XiIsMinusOneOnAAndPlusOneOnB) {
  std::mt19937_64 rng(92);
  const Sphere sa{{-1.0, 0.2, 0.1}, 0.7}, sb{{1.1, -0.3, 0.4}, 0.5};
  Graph g;
  const Expr A = sa.sdf(g), B = sb.sdf(g);
  Probe Xi(ugf::two_body(A, B)), U(ugf::two_body_parameter(A, B));
  ErrorStat err;
  for (int i = 0; i < 200; ++i) {
    const P3 pa = sa.surface_point(rng), pb = sb.surface_point(rng);
    err.add(std::fabs(Xi(pa) + 1));
    err.add(std::fabs(Xi(pb) - 1));
    err.add(std::fabs(U(pa)));
    err.add(std::fabs(U(pb) - 1));
  }
  report("two_body Xi on the surfaces (-1, +1), parameter (0, 1)", err);
  EXPECT_LE(err.max_err, 1e-5);
  // Xi = t exactly where A / B = (1 + t) / (1 - t), at any point (not only on the segment).
  Probe FA(A), FB(B);
  ErrorStat ratio;
  for (int i = 0; i < 200; ++i) {
    const P3 p{float(std::uniform_real_distribution<double>(-2, 2)(rng)), float(std::uniform_real_distribution<double>(-2, 2)(rng)),
               float(std::uniform_real_distribution<double>(-2, 2)(rng))};
    const double t = Xi.exact(p[0], p[1], p[2]), a = FA.exact(p[0], p[1], p[2]), b = FB.exact(p[0], p[1], p[2]);
    if (std::fabs(1 - t) > 1e-3) ratio.add(std::fabs(a / b - (1 + t) / (1 - t)) / (1 + std::fabs(a / b)));
  }
  EXPECT_LE(ratio.max_err, 1e-9);
}

// between(A, B, t) is zero on the level set Xi = t, with a unit gradient there.
TEST(UgfTwoBody, SurfacesBetweenTheBodies) {
  std::mt19937_64 rng(93);
  const Sphere sa{{-1.0, 0.2, 0.1}, 0.7}, sb{{1.1, -0.3, 0.4}, 0.5};
  Graph g;
  const Expr A = sa.sdf(g), B = sb.sdf(g);
  Probe Xi(ugf::two_body(A, B));
  ErrorStat zero, unit;
  for (float t : {-0.6f, 0.0f, 0.5f}) {
    Probe S(ugf::between(A, B, t));
    for (int i = 0; i < 60; ++i) {
      // Bisection for Xi = t along a segment from A's surface to B's (Xi goes from -1 to +1).
      const P3 pa = sa.surface_point(rng), pb = sb.surface_point(rng);
      auto at = [&](double s) {
        return std::array<double, 3>{pa[0] + s * (pb[0] - pa[0]), pa[1] + s * (pb[1] - pa[1]), pa[2] + s * (pb[2] - pa[2])};
      };
      if (!(Xi.exact(at(0)) < t && Xi.exact(at(1)) > t)) continue;  // the segment dips into a body
      double lo = 0, hi = 1;
      for (int it = 0; it < 50; ++it) (Xi.exact(at(0.5 * (lo + hi))) > t ? hi : lo) = 0.5 * (lo + hi);
      const auto q = at(0.5 * (lo + hi));
      const P3 p{float(q[0]), float(q[1]), float(q[2])};
      zero.add(std::fabs(S(p)));
      unit.add(std::fabs(length3(S.grad(p)) - 1));
    }
  }
  report("between(A, B, t) on Xi = t", zero, "max |value|");
  report("between(A, B, t) on Xi = t", unit, "max ||grad| - 1| (f32)");
  EXPECT_GT(zero.points, 100);
  EXPECT_LE(zero.max_err, 1e-5);
  EXPECT_LE(unit.max_err, 1e-5);
}

// Between two parallel planes, D/2 is the exact distance to the midplane.
TEST(UgfTwoBody, MidsurfaceOfParallelPlanes) {
  std::mt19937_64 rng(94);
  const Frame3 fr = Frame3::random(rng);
  Graph g;
  // Body A: u <= -0.8, body B: u >= 1.2 (outward normals -u and +u); the midplane is u = 0.2.
  const Expr A = fr.plane(g, {1, 0}, -0.8), B = fr.plane(g, {-1, 0}, -1.2);
  Probe M(ugf::midsurface(A, B));
  ErrorStat err;
  for (int i = 0; i < 300; ++i) {
    const auto p = fr.point({std::uniform_real_distribution<double>(-3, 3)(rng), std::uniform_real_distribution<double>(-3, 3)(rng)},
                            std::uniform_real_distribution<double>(-3, 3)(rng));
    err.add(std::fabs(M(p) - (fr.local(p).x - 0.2)));
  }
  report("midsurface of parallel planes", err);
  EXPECT_LE(err.max_err, 2e-6);
}

TEST(UgfTwoBody, ClearanceOfSpheresIsTheGap) {
  std::mt19937_64 rng(95);
  const Interval box{-3, 3};
  ErrorStat err;
  for (int rep = 0; rep < 4; ++rep) {
    auto u = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
    const Sphere sa{{u(-1.5, -0.5), u(-1, 1), u(-1, 1)}, u(0.3, 0.9)};
    const Sphere sb{{u(0.5, 1.5), u(-1, 1), u(-1, 1)}, u(0.3, 0.9)};
    Graph g;
    const Expr A = sa.sdf(g), B = sb.sdf(g);
    const double gap = distance3(sa.c, sb.c) - sa.r - sb.r;  // negative: interference depth
    ugf::ClearanceOptions opt;
    opt.max_boxes = 20000;
    const ugf::ClearanceResult res = ugf::find_clearance(A, B, box, box, box, opt);
    err.add(std::fabs(res.value - gap));
    EXPECT_LE(res.lower_bound, res.value);
    EXPECT_LE(res.lower_bound, gap + 1e-5);
    // The minimum lies on the segment between the centers (inside both spheres' span).
    const std::array<double, 3> p = {res.x, res.y, res.z};
    const double off_line = distance3(p, sa.c) + distance3(p, sb.c) - distance3(sa.c, sb.c);
    EXPECT_LT(off_line, 1e-3);
    // S is constant along the shortest segment.
    Probe S(ugf::clearance_field(A, B));
    for (double s : {0.2, 0.5, 0.8}) {
      const double t = sa.r + s * gap;  // from A's surface towards B
      const double d = distance3(sa.c, sb.c);
      std::array<double, 3> q;
      for (int k = 0; k < 3; ++k) q[k] = sa.c[k] + (sb.c[k] - sa.c[k]) * t / d;
      err.add(std::fabs(S.exact(q) - gap));
    }
    std::printf("[ugf] clearance: gap %.6f, found %.6f (lower bound %.6f, %zu boxes)\n", gap, res.value, res.lower_bound,
                res.boxes);
  }
  report("clearance of two spheres (find_clearance, S on the segment)", err);
  EXPECT_LE(err.max_err, 2e-5);
}

// ---------------------------------------------------------------------------------------------
// Normalization and the gyroid

TEST(UgfNormalize, SampsonNormalizationOfAnImplicitSphere) {
  std::mt19937_64 rng(96);
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  Probe N(ugf::normalize(square(x) + square(y) + square(z) - 1.0f));
  ErrorStat unit, near;
  for (int i = 0; i < 300; ++i) {
    std::normal_distribution<double> n(0, 1);
    double d[3] = {n(rng), n(rng), n(rng)};
    const double l = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const double rho = 1 + std::uniform_real_distribution<double>(-0.2, 0.2)(rng);
    const P3 on{float(d[0] / l), float(d[1] / l), float(d[2] / l)};
    const P3 p{float(rho * d[0] / l), float(rho * d[1] / l), float(rho * d[2] / l)};
    const auto fd = N.fd_grad(on);
    unit.add(std::fabs(length3(fd) - 1));
    unit.add(std::fabs(length3(N.grad(on)) - 1) * 0.1);  // f32 gradient, 10x looser
    // (rho^2 - 1) / (2 rho) against rho - 1: second order in the distance.
    near.add(std::fabs(N(p) - (rho - 1)) / ((rho - 1) * (rho - 1)));
  }
  report("normalize(x^2 + y^2 + z^2 - 1): |grad| on the zero set", unit, "max ||grad| - 1|");
  report("normalize(...) - distance, / distance^2", near, "max ratio");
  EXPECT_LE(unit.max_err, 1e-6);
  EXPECT_LE(near.max_err, 0.63);  // exactly 1 / (2 rho) <= 0.625 in exact arithmetic
}

TEST(UgfGyroid, GradientBoundsAndNormalizations) {
  std::mt19937_64 rng(97);
  const float L = 2.0f;
  const double w = 2 * M_PI / L;
  Graph g;
  Probe G(ugf::gyroid(g, L)), Sn(ugf::gyroid_normalized(g, L, ugf::GyroidScale::Sampson)),
      Bd(ugf::gyroid_normalized(g, L, ugf::GyroidScale::Bound));
  Probe sheet(ugf::gyroid_sheet(g, L, 0.3f)), net(ugf::gyroid_network(g, L, 0.1f));
  double gmin = 1e9, gmax = 0;
  ErrorStat unit, bound_excess, sheet_err;
  int on_surface = 0;
  for (int i = 0; i < 400; ++i) {
    auto u = [&] { return std::uniform_real_distribution<double>(-2, 2)(rng); };
    // A root of g along a random segment.
    const std::array<double, 3> a = {u(), u(), u()}, b = {a[0] + u() * 0.3, a[1] + u() * 0.3, a[2] + u() * 0.3};
    auto at = [&](double s) { return std::array<double, 3>{a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), a[2] + s * (b[2] - a[2])}; };
    const P3 pr{float(a[0]), float(a[1]), float(a[2])};
    bound_excess.add(std::max(0.0, length3(Bd.grad(pr)) - 1));  // 1-Lipschitz everywhere: a safe bound
    if ((G.exact(at(0)) > 0) == (G.exact(at(1)) > 0)) continue;
    double lo = 0, hi = 1;
    const bool rising = G.exact(at(1)) > 0;
    for (int it = 0; it < 50; ++it) ((G.exact(at(0.5 * (lo + hi))) > 0) == rising ? hi : lo) = 0.5 * (lo + hi);
    const auto q = at(0.5 * (lo + hi));
    const P3 p{float(q[0]), float(q[1]), float(q[2])};
    const double gl = length3(G.fd_grad(p, 1e-6)) / w;
    gmin = std::min(gmin, gl);
    gmax = std::max(gmax, gl);
    unit.add(std::fabs(length3(Sn.grad(p)) - 1));
    sheet_err.add(std::fabs(sheet(p) + 0.15f));  // on the gyroid surface the sheet is -t/2
    sheet_err.add(std::fabs(net(p) + 0.1f));     // and the network -bias
    ++on_surface;
  }
  std::printf("[ugf] gyroid: |grad g| / w on g = 0 in [%.6f, %.6f] (sqrt 2 = 1.414214, sqrt 3 = 1.732051)\n", gmin, gmax);
  report("gyroid Sampson: |grad| on the surface", unit, "max ||grad| - 1| (f32)");
  report("gyroid bound g / (sqrt(3) w)", bound_excess, "max |grad| - 1 (f32)");
  report("gyroid sheet / network on the surface", sheet_err);
  EXPECT_GT(on_surface, 50);
  EXPECT_GE(gmin, std::sqrt(2.0) - 1e-4);
  EXPECT_LE(gmax, std::sqrt(3.0) + 1e-4);
  EXPECT_LE(unit.max_err, 2e-5);
  EXPECT_LE(bound_excess.max_err, 1e-5);
  EXPECT_LE(sheet_err.max_err, 2e-5);
}

// ---------------------------------------------------------------------------------------------
// Medial-axis tracking

// A square prism built from four tracked planes: its crease set is the two diagonal planes,
// and M is exactly the distance to them, inside and out.
TEST(UgfMedial, SquareCreaseIsTheDiagonals) {
  std::mt19937_64 rng(98);
  const Frame3 fr = Frame3::random(rng);
  Graph g;
  const double a = 1.0;
  auto face = [&](V2 n) { return ugf::track_plane(fr.plane(g, n, a)); };
  const ugf::Tracked sq = ugf::intersect(ugf::intersect(face({1, 0}), face({-1, 0})),
                                         ugf::intersect(face({0, 1}), face({0, -1})));
  Probe M(sq.m), F(sq.f);
  ErrorStat err;
  for (int i = 0; i < 500; ++i) {
    const auto p = fr.point({std::uniform_real_distribution<double>(-2.5, 2.5)(rng), std::uniform_real_distribution<double>(-2.5, 2.5)(rng)},
                            std::uniform_real_distribution<double>(-2, 2)(rng));
    const V2 q = fr.local(p);
    err.add(std::fabs(std::fabs(M(p)) - std::fabs(std::fabs(q.x) - std::fabs(q.y)) / std::sqrt(2.0)));
    EXPECT_NEAR(F(p), std::max(std::fabs(q.x), std::fabs(q.y)) - a, 1e-5);
  }
  report("medial: square's M vs distance to its diagonals", err);
  EXPECT_LE(err.max_err, 5e-6);
}

// A sphere's crease is its center; offsets keep it; a shell adds the surface.
TEST(UgfMedial, SphereOffsetAndShell) {
  std::mt19937_64 rng(99);
  Graph g;
  const double R = 1.1;
  const ugf::Tracked s = ugf::track_sphere(g, 0.2f, -0.1f, 0.3f, R);
  const ugf::Tracked o = ugf::offset(s, 0.3f), sh = ugf::shell(s, 0.2f), n = ugf::negate(s);
  Probe Ms(s.m), Mo(o.m), Msh(sh.m), Mn(n.m);
  ErrorStat err;
  for (int i = 0; i < 300; ++i) {
    const P3 p = {float(std::uniform_real_distribution<double>(-2, 2)(rng)), float(std::uniform_real_distribution<double>(-2, 2)(rng)),
                  float(std::uniform_real_distribution<double>(-2, 2)(rng))};
    const double rho = std::sqrt(std::pow(p[0] - 0.2, 2) + std::pow(p[1] + 0.1, 2) + std::pow(p[2] - 0.3, 2));
    err.add(std::fabs(Ms(p) - rho));
    err.add(std::fabs(Mo(p) - rho));
    err.add(std::fabs(Mn(p) - rho));
    err.add(std::fabs(std::fabs(Msh(p)) - std::min(rho, std::fabs(rho - R))));
  }
  report("medial: sphere, offset, negation, shell", err);
  EXPECT_LE(err.max_err, 2e-6);
}

// Where two fields' gradients coincide there is no new crease: intersecting a plane with a
// parallel copy of itself keeps M = +inf.
TEST(UgfMedial, ParallelPlanesAddNoCrease) {
  Graph g;
  const ugf::Tracked p1 = ugf::track_plane(g.x() - 1.0f), p2 = ugf::track_plane(g.x() - 2.0f);
  Probe M(ugf::intersect(p1, p2).m), U(ugf::unite(p1, p2).m), D(ugf::subtract(p1, p2).m);
  EXPECT_EQ(M({0.3f, 0.2f, 0.1f}), std::numeric_limits<float>::infinity());
  EXPECT_EQ(U({0.3f, 0.2f, 0.1f}), std::numeric_limits<float>::infinity());
  // max(x - 1, 2 - x): the crease is x = 1.5.
  EXPECT_NEAR(D({0.3f, 0.2f, 0.1f}), -1.2f, 1e-6);
}

}  // namespace
}  // namespace frep
