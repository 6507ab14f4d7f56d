// Boxes, rounded and chamfered rectangles, spheres: booleans, offsets and shells against
// brute-force exact distances in double precision (closest point on a box by clamping, 2D
// profiles of segments and arcs, radial distances to spheres), and the gradient exactly on faces.
#include <gtest/gtest.h>

#include <map>

#include "frep/ugf.hpp"
#include "ugf/ugf_test_util.hpp"

namespace frep {
namespace {

using namespace ugf_test;
using P3 = std::array<float, 3>;

constexpr double kTol = 5e-6;

// A box with half sizes b, center o and axes (the rows of R), in double.
struct BoxRef {
  std::array<double, 3> b, o;
  std::array<std::array<double, 3>, 3> R;

  std::array<double, 3> local(const P3& p) const {
    std::array<double, 3> l{};
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) l[i] += R[i][k] * (double(p[k]) - o[k]);
    return l;
  }
  double sdf(const P3& p) const {
    const auto l = local(p);
    bool inside = true;
    double out2 = 0, in = 1e300;
    for (int i = 0; i < 3; ++i) {
      const double c = std::clamp(l[i], -b[i], b[i]);
      out2 += (l[i] - c) * (l[i] - c);
      inside = inside && std::fabs(l[i]) <= b[i];
      in = std::min(in, b[i] - std::fabs(l[i]));
    }
    return inside ? -in : std::sqrt(out2);
  }
  // The face plane n.p - d with n = +-R[axis].
  Expr face(Graph& g, int axis, double sign) const {
    double d = b[axis];
    for (int k = 0; k < 3; ++k) d += sign * R[axis][k] * o[k];
    return g.x() * float(sign * R[axis][0]) + g.y() * float(sign * R[axis][1]) + g.z() * float(sign * R[axis][2]) -
           float(d);
  }
  Expr slab(Graph& g, int axis) const { return max(face(g, axis, 1), face(g, axis, -1)); }
};

BoxRef random_box(std::mt19937_64& rng, bool rotated) {
  const Frame3 f = Frame3::random(rng);
  BoxRef box;
  std::uniform_real_distribution<double> u(0.4, 1.5);
  box.b = {u(rng), u(rng), u(rng)};
  box.o = rotated ? f.o : std::array<double, 3>{0, 0, 0};
  if (rotated) box.R = {f.u, f.v, f.e};
  else box.R = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  return box;
}

P3 random_point(std::mt19937_64& rng, double r) {
  std::uniform_real_distribution<double> u(-r, r);
  return {float(u(rng)), float(u(rng)), float(u(rng))};
}

struct Stats {
  ErrorStat exact, bound, unit;
};

// Per-operation statistics of one test, reported and checked when it ends.
class Table {
 public:
  Stats& operator[](const std::string& name) {
    if (!stats_.count(name)) order_.push_back(name);
    return stats_[name];
  }
  ~Table() {
    for (const std::string& name : order_) {
      const Stats& st = stats_[name];
      if (st.exact.points) report(name, st.exact);
      if (st.bound.points) report(name, st.bound, "max bound violation");
      if (st.unit.points) report(name, st.unit, "max ||grad| - 1| (fd)");
      EXPECT_LE(st.exact.max_err, kTol) << name;
      EXPECT_LE(st.bound.max_err, kTol) << name;
      EXPECT_LE(st.unit.max_err, 1e-6) << name;
      EXPECT_GT(st.exact.points, 50) << name;
      EXPECT_GT(st.unit.points, 50) << name;
    }
  }

 private:
  std::map<std::string, Stats> stats_;
  std::vector<std::string> order_;
};

// Compares f with ref at random points: equal where `exact_at(ref)`, else a bound (same sign, no
// larger magnitude); the gradient is finite everywhere and unit where finite differences say
// the field is smooth.
void compare(Table& table, const std::string& name, Expr f, const std::function<double(const P3&)>& ref,
             const std::function<bool(double)>& exact_at, std::mt19937_64& rng, int n = 1000, double range = 3) {
  Probe F(f);
  Stats& st = table[name];
  for (int i = 0; i < n; ++i) {
    const P3 p = random_point(rng, range);
    const double r = ref(p), v = F(p);
    if (exact_at(r)) st.exact.add(std::fabs(v - r));
    else st.bound.add(std::max(0.0, std::fabs(v) - std::fabs(r)) + ((v > 0) != (r > 0) && std::fabs(r) > kTol ? 1 : 0));
    const Grad gr = F.grad(p);
    ASSERT_TRUE(std::isfinite(gr.dx) && std::isfinite(gr.dy) && std::isfinite(gr.dz)) << name;
    if (i % 3 == 0) {
      const auto fd = F.fd_grad(p);
      if (std::isfinite(fd[0]) && std::isfinite(fd[1]) && std::isfinite(fd[2])) st.unit.add(std::fabs(length3(fd) - 1));
    }
  }
}

const auto kAll = [](double) { return true; };
const auto kIn = [](double r) { return r <= 0; };

TEST(UgfSolids, BoxesFromPlanes) {
  std::mt19937_64 rng(81);
  Table table;
  for (int rep = 0; rep < 6; ++rep) {
    const BoxRef box = random_box(rng, rep % 2 == 1);
    Graph g;
    const Expr sx = box.slab(g, 0), sy = box.slab(g, 1), sz = box.slab(g, 2);
    auto ref = [&](const P3& p) { return box.sdf(p); };
    compare(table, "box: max of 6 planes", max(max(sx, sy), sz), ref, kIn, rng);
    compare(table, "box: nested intersect_exact", ugf::intersect_exact(ugf::intersect_exact(sx, sy), sz), ref, kAll, rng);
    compare(table, "box: nested intersect_right_angle", ugf::intersect_right_angle(ugf::intersect_right_angle(sx, sy), sz),
            ref, kAll, rng);
    // Offsetting the exact box rounds its edges and corners: the exact distance to the box minus r.
    const float r = 0.3f;
    compare(table, "offset(exact box, r)", ugf::offset(ugf::intersect_exact(ugf::intersect_exact(sx, sy), sz), r),
            [&](const P3& p) { return box.sdf(p) - r; }, kAll, rng);
    // Offsetting the max box mitres: exact inside, where it is the bigger box's distance.
    BoxRef bigger = box;
    for (double& h : bigger.b) h += r;
    compare(table, "offset(max box, r)", ugf::offset(max(max(sx, sy), sz), r), [&](const P3& p) { return bigger.sdf(p); },
            kIn, rng);
  }
}

// Exactly on an axis-aligned face (points on the f32 grid, so the face's plane is exactly 0),
// the exact boxes' gradient is the face normal: no constant side of a min/max wins the tie.
TEST(UgfSolids, GradientExactlyOnTheFaces) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  const Expr sx = max(x - 1.0f, -x - 1.0f), sy = max(y - 1.0f, -y - 1.0f), sz = max(z - 1.0f, -z - 1.0f);
  const std::vector<Expr> boxes = {ugf::intersect_exact(ugf::intersect_exact(sx, sy), sz),
                                   ugf::intersect_right_angle(ugf::intersect_right_angle(sx, sy), sz)};
  const std::vector<Expr> unions = {ugf::unite_right_angle(x - 1.0f, y - 1.0f), ugf::unite_exact(x - 1.0f, y - 1.0f)};
  for (int k = 0; k < 4; ++k) {
    Probe F(k < 2 ? boxes[k] : unions[k - 2]);
    for (float a : {-0.5f, 0.0f, 0.25f, 0.5f}) {
      // On the face x = 1 of the box, or of the union's half-space x <= 1 where y > 1.
      const P3 p{1.0f, k < 2 ? a : 2.0f + a, a * 0.5f};
      const Grad gr = F.grad(p);
      EXPECT_EQ(gr.v, 0.0f);
      EXPECT_NEAR(length3(gr), 1.0, 1e-6) << k << " at (1, " << p[1] << ", " << p[2] << ")";
      EXPECT_NEAR(gr.dx, 1.0f, 1e-6) << k << " at (1, " << p[1] << ", " << p[2] << "): (" << gr.dx << ", " << gr.dy << ", " << gr.dz << ")";
    }
  }
}

// Rectangles with rounded or chamfered corners, extruded: the max over the four corners' rounded
// (chamfered) wedges is exact, because each wedge contains the rectangle and shares its boundary
// near its corner.
TEST(UgfSolids, RoundedAndChamferedRectangles) {
  std::mt19937_64 rng(82);
  Table table;
  for (int rep = 0; rep < 4; ++rep) {
    const Frame3 fr = Frame3::random(rng);
    const double a = 1.3, b = 0.8, r = 0.35, s = 0.3;
    Graph g;
    const Expr sides[4] = {fr.plane(g, {1, 0}, a), fr.plane(g, {0, 1}, b), fr.plane(g, {-1, 0}, a),
                           fr.plane(g, {0, -1}, b)};
    Expr rounded = ugf::round_intersection(sides[0], sides[1], r), chamfered = g.c(-1e30f),
         chamfered_exact = g.c(-1e30f);
    for (int i = 0; i < 4; ++i) {
      rounded = max(rounded, ugf::round_intersection(sides[i], sides[(i + 1) % 4], r));
      chamfered = max(chamfered, ugf::chamfer_intersection(sides[i], sides[(i + 1) % 4], ugf::Chamfer::setback(s)));
      chamfered_exact = max(chamfered_exact, ugf::chamfer_intersection(sides[i], sides[(i + 1) % 4],
                                                                       ugf::Chamfer::setback(s).distance_preserving()));
    }
    Profile rr, oct;
    rr.segment({a, -b + r}, {a, b - r});
    rr.arc({a - r, b - r}, r, 0, M_PI / 2);
    rr.segment({a - r, b}, {-a + r, b});
    rr.arc({-a + r, b - r}, r, M_PI / 2, M_PI / 2);
    rr.segment({-a, b - r}, {-a, -b + r});
    rr.arc({-a + r, -b + r}, r, M_PI, M_PI / 2);
    rr.segment({-a + r, -b}, {a - r, -b});
    rr.arc({a - r, -b + r}, r, -M_PI / 2, M_PI / 2);
    oct.polygon({{a, -b + s}, {a, b - s}, {a - s, b}, {-a + s, b}, {-a, b - s}, {-a, -b + s}, {-a + s, -b}, {a - s, -b}});
    compare(table, "rounded rectangle (4 x round_intersection)", rounded, [&](const P3& p) { return rr.sdf(fr.local(p)); },
            kAll, rng);
    compare(table, "chamfered rectangle (4 x chamfer_intersection)", chamfered,
            [&](const P3& p) { return oct.sdf(fr.local(p)); }, kIn, rng);
    compare(table, "chamfered rectangle, distance-preserving", chamfered_exact,
            [&](const P3& p) { return oct.sdf(fr.local(p)); }, kAll, rng);
  }
}

// Spheres: offsets and every shell are exact (everything is radial).
TEST(UgfSolids, SphereOffsetsAndShells) {
  std::mt19937_64 rng(83);
  Table table;
  const double R = 1.2, t = 0.4;
  const std::array<double, 3> c = {0.3, -0.2, 0.1};
  Graph g;
  const Expr F = sqrt(square(g.x() - float(c[0])) + square(g.y() - float(c[1])) + square(g.z() - float(c[2]))) - float(R);
  auto radius = [&](const P3& p) {
    return std::sqrt(std::pow(p[0] - c[0], 2) + std::pow(p[1] - c[1], 2) + std::pow(p[2] - c[2], 2));
  };
  // Signed distance to the spherical shell between radii r0 < r1 (a ball if r0 <= 0).
  auto shell_ref = [&](const P3& p, double r0, double r1) {
    const double rho = radius(p);
    const double d1 = std::fabs(rho - r1), d0 = r0 > 0 ? std::fabs(rho - r0) : 1e300;
    const bool inside = rho <= r1 && rho >= r0;
    return inside ? -std::min(d0, d1) : std::min(d0, d1);
  };
  for (float r : {0.5f, -0.4f})
    compare(table, "offset(sphere, r)", ugf::offset(F, r), [&](const P3& p) { return shell_ref(p, 0, R + r); }, kAll, rng);
  compare(table, "shell(sphere, t)", ugf::shell(F, t), [&](const P3& p) { return shell_ref(p, R - t / 2, R + t / 2); }, kAll,
          rng);
  for (float bias : {-1.0f, -0.3f, 0.5f, 1.0f})
    compare(table, "shell_biased(sphere, t, b)", ugf::shell_biased(F, t, bias),
            [&](const P3& p) { return shell_ref(p, R - (1 + bias) * t / 2, R + (1 - bias) * t / 2); }, kAll, rng);
  compare(table, "shell_inward(sphere, t)", ugf::shell_inward(F, t), [&](const P3& p) { return shell_ref(p, R - t, R); }, kAll,
          rng);
  compare(table, "shell_outward(sphere, t)", ugf::shell_outward(F, t), [&](const P3& p) { return shell_ref(p, R, R + t); },
          kAll, rng);
  compare(table, "shell_variable(sphere, constant t)", ugf::shell_variable(F, g.c(t)),
          [&](const P3& p) { return shell_ref(p, R - t / 2, R + t / 2); }, kAll, rng);
}

// A wall whose thickness varies along x: on its surfaces the re-normalized field has a unit
// gradient, and the wall is T(p) thick where T varies slowly.
TEST(UgfSolids, VariableThicknessShell) {
  Graph g;
  auto x = g.x(), z = g.z();
  const Expr F = z;                      // the plane z = 0
  const Expr T = 0.2f + 0.05f * x;       // thickness growing with x
  Probe S(ugf::shell_variable(F, T));
  ErrorStat unit, thick;
  for (float px = -1; px <= 1; px += 0.125f) {
    const float t = 0.2f + 0.05f * px;
    for (float side : {-1.0f, 1.0f}) {
      // The surface: |z| = T/2.
      const P3 p{px, 0.3f, side * t / 2};
      EXPECT_NEAR(S(p), 0.0f, 1e-6);
      unit.add(std::fabs(length3(S.grad(p)) - 1));
      thick.add(std::fabs(S({px, -0.7f, 0.0f}) + t / 2) / t);  // mid-wall: -T/2 to first order
    }
  }
  report("shell_variable: |grad| on the surface", unit, "max ||grad| - 1|");
  report("shell_variable: mid-wall value vs -T/2", thick, "max relative error");
  EXPECT_LE(unit.max_err, 1e-5);
  EXPECT_LE(thick.max_err, 2e-3);
}

}  // namespace
}  // namespace frep
