// Booleans, chamfers, rounds and pencils of two planes at dihedral angles 30..150 degrees, placed
// at random in 3D, against the exact signed distance of the solid computed independently in
// double precision (2D cross-section profiles of segments and arcs): equal where docs/ugf.md says the
// formula is exact, never larger in magnitude where it is a bound; unit gradient by finite
// differences off the creases; finite gradients everywhere. Also the edge frame identities and
// the fallbacks at degenerate angles.
#include <gtest/gtest.h>

#include <functional>
#include <map>

#include "frep/ugf.hpp"
#include "ugf/ugf_test_util.hpp"

namespace frep {
namespace {

using namespace ugf_test;

constexpr double kExactTol = 5e-6;   // f32 evaluation of fields of magnitude up to ~8
constexpr double kUnitTol = 1e-6;    // |grad| - 1 by double-precision central differences
constexpr double kUnitTolF32 = 2e-5; // |grad| - 1 from the f32 gradient evaluator

struct OpStats {
  ErrorStat exact, bound, unit, unit_f32;
};

// Where a field must equal the reference (otherwise it must bound it).
using ExactWhere = std::function<bool(V2 q, double ref)>;
const ExactWhere kEverywhere = [](V2, double) { return true; };
const ExactWhere kInside = [](V2, double r) { return r <= 0; };
const ExactWhere kOutside = [](V2, double r) { return r >= 0; };

class UgfEdgeOps : public ::testing::Test {
 protected:
  // Samples `f` around the edge of `fr` and compares with `ref`.
  void check(const std::string& name, Expr f, const Frame3& fr, const std::function<double(V2)>& ref,
             const ExactWhere& exact, bool unit_gradient = true, int n = 500) {
    Probe F(f);
    OpStats& st = stats_[name];
    for (int i = 0; i < n; ++i) {
      // The first points sit on the edge itself and on the faces' planes, where distances to the
      // edge are sqrt(0): the gradient must still be finite there.
      V2 q0{uni(-3, 3), uni(-3, 3)};
      if (i < 3) q0 = i == 0 ? V2{0, 0} : uni(-3, 3) * unit_at(i == 1 ? fr_phi_ / 2 + M_PI / 2 : -fr_phi_ / 2 - M_PI / 2);
      const auto p = fr.point(q0, uni(-3, 3));
      const V2 q = fr.local(p);
      const double r = ref(q);
      const double v = F(p);
      char where[96];
      std::snprintf(where, sizeof where, "phi %.0f, q (%.3f, %.3f)", fr_phi_ * 180 / M_PI, q.x, q.y);
      if (exact(q, r)) {
        st.exact.add(std::fabs(v - r), where);
      } else {
        // A bound: same sign, magnitude no larger.
        double viol = std::max(0.0, std::fabs(v) - std::fabs(r));
        if (std::fabs(r) > kExactTol && (v > 0) != (r > 0)) viol = std::max(viol, std::fabs(v - r));
        st.bound.add(viol, where);
      }
      const Grad gr = F.grad(p);
      ASSERT_TRUE(std::isfinite(gr.dx) && std::isfinite(gr.dy) && std::isfinite(gr.dz))
          << name << ": non-finite gradient at local (" << q.x << ", " << q.y << ")";
      if (unit_gradient && i % 2 == 0) {
        const auto fd = F.fd_grad(p);
        if (std::isfinite(fd[0]) && std::isfinite(fd[1]) && std::isfinite(fd[2])) {
          st.unit.add(std::fabs(length3(fd) - 1));
          st.unit_f32.add(std::fabs(length3(gr) - 1));
        }
      }
    }
  }

  void TearDown() override {
    for (const auto& [name, st] : stats_) {
      if (st.exact.points) {
        report(name, st.exact);
        EXPECT_LE(st.exact.max_err, kExactTol) << name;
      }
      if (st.bound.points) {
        report(name, st.bound, "max bound violation");
        EXPECT_LE(st.bound.max_err, kExactTol) << name;
      }
      if (st.unit.points) {
        report(name, st.unit, "max ||grad| - 1| (fd)");
        EXPECT_LE(st.unit.max_err, kUnitTol) << name;
        EXPECT_LE(st.unit_f32.max_err, kUnitTolF32) << name;
        EXPECT_GT(st.unit.points, st.exact.points / 6) << name << ": too few points off the creases";
      }
    }
  }

  double uni(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng_); }

  static std::vector<double> angles() {
    std::vector<double> v;
    for (int deg = 30; deg <= 150; deg += 10) v.push_back(deg * M_PI / 180);
    return v;
  }

  std::mt19937_64 rng_{71};
  double fr_phi_ = 0;  // the angle being tested, for messages
  std::map<std::string, OpStats> stats_;
};

TEST_F(UgfEdgeOps, Booleans) {
  for (double phi : angles()) {
    fr_phi_ = phi;
    const Wedge w = Wedge::symmetric(phi), wu = w.flipped();
    const Frame3 fr = Frame3::random(rng_);
    Graph g;
    const Expr A = fr.plane(g, w.nA, 0), B = fr.plane(g, w.nB, 0);
    const Profile inter = wedge_profile(w), uni_c = wedge_profile(wu);
    auto ref_i = [&](V2 q) { return inter.sdf(q); };
    auto ref_u = [&](V2 q) { return -uni_c.sdf(q); };  // the union is the complement of wu
    // The plain forms are exact except in the edge's normal cone (outside for the intersection,
    // inside for the union), where they are bounds.
    check("intersect", ugf::intersect(A, B), fr, ref_i, [&](V2 q, double) { return !w.in_edge_cone(q); });
    check("unite", ugf::unite(A, B), fr, ref_u, [&](V2 q, double) { return !wu.in_edge_cone(q); });
    check("intersect_exact", ugf::intersect_exact(A, B), fr, ref_i, kEverywhere);
    check("unite_exact", ugf::unite_exact(A, B), fr, ref_u, kEverywhere);
    // A minus B: the wedge of nA and -nB, whose angle is 180 degrees - phi.
    const Wedge wd = Wedge::from_normals(w.nA, -1.0 * w.nB);
    const Profile diff = wedge_profile(wd);
    auto ref_d = [&](V2 q) { return diff.sdf(q); };
    check("subtract", ugf::subtract(A, B), fr, ref_d, [&](V2 q, double) { return !wd.in_edge_cone(q); });
    check("subtract_exact", ugf::subtract_exact(A, B), fr, ref_d, kEverywhere);
  }
}

TEST_F(UgfEdgeOps, RightAngleForms) {
  for (int rep = 0; rep < 4; ++rep) {
    fr_phi_ = M_PI / 2;
    const Wedge w = Wedge::symmetric(M_PI / 2), wu = w.flipped();
    const Frame3 fr = Frame3::random(rng_);
    Graph g;
    const Expr A = fr.plane(g, w.nA, 0), B = fr.plane(g, w.nB, 0);
    const Profile inter = wedge_profile(w), uni_c = wedge_profile(wu);
    auto ref_i = [&](V2 q) { return inter.sdf(q); };
    auto ref_u = [&](V2 q) { return -uni_c.sdf(q); };
    check("intersect_right_angle", ugf::intersect_right_angle(A, B), fr, ref_i, kEverywhere);
    check("unite_right_angle", ugf::unite_right_angle(A, B), fr, ref_u, kEverywhere);
    const Wedge wd = Wedge::from_normals(w.nA, -1.0 * w.nB);
    const Profile diff = wedge_profile(wd);
    check("subtract_right_angle", ugf::subtract_right_angle(A, B), fr, [&](V2 q) { return diff.sdf(q); },
          kEverywhere);
    // The classic 45-degree chamfers with setback r.
    const double r = 0.7;
    const Profile ci = chamfered_profile(w, r, r), cu = chamfered_profile(wu, r, r);
    check("chamfer_intersection_right_angle", ugf::chamfer_intersection_right_angle(A, B, r), fr,
          [&](V2 q) { return ci.sdf(q); }, kInside);
    check("chamfer_union_right_angle", ugf::chamfer_union_right_angle(A, B, r), fr,
          [&](V2 q) { return -cu.sdf(q); }, kOutside);
  }
}

TEST_F(UgfEdgeOps, Chamfers) {
  for (double phi : angles()) {
    fr_phi_ = phi;
    const Wedge w = Wedge::symmetric(phi), wu = w.flipped();
    const Frame3 fr = Frame3::random(rng_);
    Graph g;
    const Expr A = fr.plane(g, w.nA, 0), B = fr.plane(g, w.nB, 0);
    const ugf::EdgeFrame f = ugf::edge_frame(A, B);
    // Each size, with its solid built geometrically: the cut at inset h along the bisector, the
    // setback points, the symmetric setback points |dA - dB| s = w apart, and asymmetric ones.
    const double h = 0.3, s = 0.8, width = 1.0, sA = 0.5, sB = 1.1;
    struct Case {
      std::string name;
      ugf::Chamfer size;
      Profile inter, uni;
    };
    std::vector<Case> cases = {
        {"inset", ugf::Chamfer::inset(h), cut_profile(w, w.nS(), -h), cut_profile(wu, -1.0 * w.nS(), -h)},
        {"setback", ugf::Chamfer::setback(s), chamfered_profile(w, s, s), chamfered_profile(wu, s, s)},
        {"width", ugf::Chamfer::width(width), chamfered_profile(w, width / norm(w.dA - w.dB), width / norm(w.dA - w.dB)),
         chamfered_profile(wu, width / norm(w.dA - w.dB), width / norm(w.dA - w.dB))},
        {"setbacks", ugf::Chamfer::setbacks(sA, sB), chamfered_profile(w, sA, sB), chamfered_profile(wu, sA, sB)},
    };
    for (const Case& c : cases) {
      auto ref_i = [&](V2 q) { return c.inter.sdf(q); };
      auto ref_u = [&](V2 q) { return -c.uni.sdf(q); };
      check("chamfer_intersection " + c.name, ugf::chamfer_intersection(f, c.size), fr, ref_i, kInside);
      check("chamfer_intersection " + c.name + " exact", ugf::chamfer_intersection(f, c.size.distance_preserving()),
            fr, ref_i, kEverywhere);
      check("chamfer_union " + c.name, ugf::chamfer_union(f, c.size), fr, ref_u, kOutside);
      check("chamfer_union " + c.name + " exact", ugf::chamfer_union(f, c.size.distance_preserving()), fr, ref_u,
            kEverywhere);
    }
  }
}

TEST_F(UgfEdgeOps, Rounds) {
  for (double phi : angles()) {
    fr_phi_ = phi;
    const Wedge w = Wedge::symmetric(phi), wu = w.flipped();
    const Frame3 fr = Frame3::random(rng_);
    Graph g;
    const Expr A = fr.plane(g, w.nA, 0), B = fr.plane(g, w.nB, 0);
    for (double r : {0.25, 0.6}) {
      const Profile ri = rounded_profile(w, r), ru = rounded_profile(wu, r);
      check("round_intersection", ugf::round_intersection(A, B, r), fr, [&](V2 q) { return ri.sdf(q); }, kEverywhere);
      check("round_union", ugf::round_union(A, B, r), fr, [&](V2 q) { return -ru.sdf(q); }, kEverywhere);
    }
  }
}

TEST_F(UgfEdgeOps, PencilsAndTheEdgeFrame) {
  for (double phi : angles()) {
    fr_phi_ = phi;
    const Wedge w = Wedge::symmetric(phi);
    const Frame3 fr = Frame3::random(rng_);
    Graph g;
    const Expr A = fr.plane(g, w.nA, 0), B = fr.plane(g, w.nB, 0);
    const ugf::EdgeFrame f = ugf::edge_frame(A, B);
    // Sn and Dn are the plane distances along the bisector's normal and across it; pencils are
    // planes through the edge; A and B are the pencil's ends.
    auto plane_ref = [](V2 m, double d) { return [=](V2 q) { return dot(m, q) - d; }; };
    check("edge frame Sn", f.Sn, fr, plane_ref(w.nS(), 0), kEverywhere);
    check("edge frame Dn", f.Dn, fr, plane_ref(w.nD(), 0), kEverywhere);
    check("A = Sn cos(phi/2) + Dn sin(phi/2)", f.Sn * std::cos(phi / 2) + f.Dn * std::sin(phi / 2), fr,
          plane_ref(w.nA, 0), kEverywhere);
    check("B = Sn cos(phi/2) - Dn sin(phi/2)", f.Sn * std::cos(phi / 2) - f.Dn * std::sin(phi / 2), fr,
          plane_ref(w.nB, 0), kEverywhere);
    check("pencil(+phi/2) = A", ugf::pencil(f, phi / 2), fr, plane_ref(w.nA, 0), kEverywhere);
    check("pencil(-phi/2) = B", ugf::pencil(f, -phi / 2), fr, plane_ref(w.nB, 0), kEverywhere);
    for (double frac : {-0.6, 0.0, 0.45, 2.0}) {  // 2.0: beyond the faces, any plane of the pencil
      const double theta = frac * phi / 2, d = -0.4;
      const V2 m = std::cos(theta) * w.nS() + std::sin(theta) * w.nD();
      check("pencil_face", ugf::pencil_face(f, theta, d), fr, plane_ref(m, d), kEverywhere);
      if (std::fabs(frac) < 1) {
        const Profile cut = cut_profile(w, m, d);
        check("pencil_chamfer", ugf::pencil_chamfer(f, theta, d), fr, [&](V2 q) { return cut.sdf(q); }, kInside);
      }
    }
    // c, cos(phi/2), sin(phi/2) are constants for planes (folded).
    EXPECT_NEAR(f.c.node().value, std::cos(phi), 1e-6);
    EXPECT_TRUE(f.A.graph().is_const(f.cos_half.id()) && f.A.graph().is_const(f.sin_half.id()));
  }
}

// Near phi = 0 and phi = 180 degrees the edge operations fall back to max / min, stay finite, and
// the frame reports itself invalid.
TEST(UgfEdgeFrame, DegenerateAnglesFallBackToMaxAndMin) {
  std::mt19937_64 rng(72);
  for (double deg : {0.0, 0.5, 179.5, 180.0}) {
    const double phi = deg * M_PI / 180;
    const Frame3 fr = Frame3::random(rng);
    Graph g;
    // Offset B a little so that the two planes are distinct even when parallel.
    const Expr A = fr.plane(g, unit_at(phi / 2), 0), B = fr.plane(g, unit_at(-phi / 2), -0.3);
    const ugf::EdgeFrame f = ugf::edge_frame(A, B);
    EXPECT_EQ(f.valid.node().value, 0.0f) << deg;
    const Expr mx = max(A, B), mn = min(A, B);
    const std::vector<std::pair<Expr, Expr>> pairs = {
        {ugf::intersect_exact(A, B), mx},
        {ugf::unite_exact(A, B), mn},
        {ugf::chamfer_intersection(f, ugf::Chamfer::setback(0.5f)), mx},
        {ugf::chamfer_intersection(f, ugf::Chamfer::setbacks(0.5f, 0.2f).distance_preserving()), mx},
        {ugf::chamfer_union(f, ugf::Chamfer::width(0.5f)), mn},
        {ugf::round_intersection(f, 0.5f), mx},
        {ugf::round_union(f, 0.5f), mn},
        {ugf::pencil_chamfer(f, 0.1f, -0.2f), mx},
    };
    for (const auto& [op, fallback] : pairs) {
      Probe F(op), M(fallback);
      for (int i = 0; i < 50; ++i) {
        std::uniform_real_distribution<double> u(-3, 3);
        const auto p = fr.point({u(rng), u(rng)}, u(rng));
        EXPECT_EQ(F(p), M(p)) << deg;
        const Grad gr = F.grad(p), gm = M.grad(p);
        EXPECT_EQ(gr.dx, gm.dx);
        EXPECT_EQ(gr.dy, gm.dy);
        EXPECT_EQ(gr.dz, gm.dz);
      }
    }
  }
}

}  // namespace
}  // namespace frep
