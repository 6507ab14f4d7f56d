// Mesh oracles: a mesh's signed distance as a leaf of expressions. Checked against the closed
// form it stands for (values within float rounding, identical signs), against finite differences
// and the closest-point direction (gradients), for interval containment on random boxes, when
// moved, through writers (which write the closed form), and meshed inside mixed expressions.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <sstream>

#include "convert_test_util.hpp"
#include "frep/contour/mesher.hpp"
#include "frep/convert/convert.hpp"
#include "frep/script/load.hpp"
#include "frep/convert/mesh_oracle.hpp"
#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/eval/interval_batch.hpp"
#include "frep/expr/copy.hpp"
#include "frep/expr/derivative.hpp"
#include "frep/expr/expr.hpp"
#include "frep/expr/remap.hpp"
#include "frep/io/vm.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/validate.hpp"
#include "frep/ugf/normalize.hpp"
#include "mesh_test_util.hpp"

namespace frep {
namespace {

std::vector<std::pair<std::string, TriMesh>> test_meshes() {
  std::vector<std::pair<std::string, TriMesh>> v;
  v.emplace_back("box", test::make_box({-1, -0.5, -0.25}, {1, 0.5, 0.25}));
  v.emplace_back("sphere", test::make_sphere(3, 2.0));
  for (const char* name : {"fandisk.obj", "spot.obj", "plate_holes.stl"}) {
    const std::string path = test::shared_mesh_dir() + "/" + name;
    if (std::filesystem::exists(path)) v.emplace_back(name, read_mesh(path));
  }
  return v;
}

// The oracle against the closed form convert_mesh writes: the same field up to the closed form's
// float rounding (docs/convert.md: below 2e-7 of the diagonal), with the same sign wherever the
// value is clearly off the surface. Generated meshes, and shared ones where ../shared is present.
TEST(MeshOracle, ValuesMatchTheClosedForm) {
  for (const auto& [name, mesh] : test_meshes()) {
    SCOPED_TRACE(name);
    const auto oracle = std::make_shared<const MeshOracle>(mesh);
    const ConvertResult closed = convert_mesh(mesh);
    const Tape ct = Tape::compile(*closed.model.graph, closed.model.root);
    const Model om = mesh_model(oracle);
    const Tape ot = Tape::compile(*om.graph, om.root);
    const test::Samples s = test::sample_around(mesh, 2000, 2000, 500);
    const std::size_t n = s.points.size();
    std::vector<float> x(n), y(n), z(n), fc(n), fo(n);
    for (std::size_t i = 0; i < n; ++i)
      x[i] = static_cast<float>(s.points[i].x), y[i] = static_cast<float>(s.points[i].y), z[i] = static_cast<float>(s.points[i].z);
    BatchEvaluator be;
    be.eval(ct, x.data(), y.data(), z.data(), fc.data(), n);
    be.eval(ot, x.data(), y.data(), z.data(), fo.data(), n);
    const double diag = length(bounding_box(mesh).size());
    const double tol = 1e-6 * diag;
    std::size_t worse = 0, signs = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (std::fabs(double(fc[i]) - fo[i]) > tol) ++worse;
      if (std::fabs(fo[i]) > tol && (fc[i] < 0) != (fo[i] < 0)) ++signs;
      if (worse + signs == 1 && (worse || signs))
        ADD_FAILURE() << s.kind[i] << " point (" << x[i] << ", " << y[i] << ", " << z[i] << "): closed form " << fc[i]
                      << ", oracle " << fo[i];
    }
    EXPECT_EQ(worse, 0u) << "values farther apart than " << tol;
    EXPECT_EQ(signs, 0u) << "sign differences off the surface";
  }
}

// Gradients: the unit vector from the closest point (negated inside), which finite differences
// of the exact distance confirm away from the surface and the medial axis.
TEST(MeshOracle, GradientsAreTheClosestPointDirection) {
  const TriMesh mesh = test::make_sphere(3, 2.0);
  const auto oracle = std::make_shared<const MeshOracle>(mesh);
  const MeshDistance& d = oracle->field().distance();
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<float> u(-3, 3);
  std::size_t checked = 0;
  for (int i = 0; i < 3000; ++i) {
    const float p[3] = {u(rng), u(rng), u(rng)};
    Grad g;
    oracle->gradients(&p[0], &p[1], &p[2], &g, 1);
    const Vec3 q{p[0], p[1], p[2]};
    const double f = d.signed_distance(q, SignMethod::Pseudonormal);
    EXPECT_EQ(g.v, static_cast<float>(f));
    EXPECT_NEAR(std::sqrt(double(g.dx) * g.dx + double(g.dy) * g.dy + double(g.dz) * g.dz), 1.0, 1e-6);
    const ClosestPoint c = d.closest_point(q);
    if (c.distance > 1e-3) {
      const Vec3 dir = (q - c.point) / c.distance * (f < 0 ? -1.0 : 1.0);
      if (c.feature != Feature::Face) {
        EXPECT_NEAR(g.dx, dir.x, 1e-5);
        EXPECT_NEAR(g.dy, dir.y, 1e-5);
        EXPECT_NEAR(g.dz, dir.z, 1e-5);
      }
    }
    // Central differences where the distance is smooth (not near the centre: the medial axis).
    if (std::fabs(f) > 0.05 && length(q) > 1.0) {
      const double h = 1e-5;
      double fd[3];
      for (int a = 0; a < 3; ++a) {
        Vec3 qp = q, qm = q;
        qp[a] += h, qm[a] -= h;
        fd[a] = (d.signed_distance(qp, SignMethod::Pseudonormal) - d.signed_distance(qm, SignMethod::Pseudonormal)) / (2 * h);
      }
      EXPECT_NEAR(g.dx, fd[0], 1e-3);
      EXPECT_NEAR(g.dy, fd[1], 1e-3);
      EXPECT_NEAR(g.dz, fd[2], 1e-3);
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000u);
  // On the surface: the face's normal.
  const Vec3 a = mesh.vertices[mesh.triangles[0][0]], b = mesh.vertices[mesh.triangles[0][1]],
             c = mesh.vertices[mesh.triangles[0][2]];
  const Vec3 m = (a + b + c) / 3.0;
  const Vec3 nrm = cross(b - a, c - a) / length(cross(b - a, c - a));
  const float p[3] = {static_cast<float>(m.x), static_cast<float>(m.y), static_cast<float>(m.z)};
  Grad g;
  oracle->gradients(&p[0], &p[1], &p[2], &g, 1);
  EXPECT_NEAR(g.dx, nrm.x, 1e-6);
  EXPECT_NEAR(g.dy, nrm.y, 1e-6);
  EXPECT_NEAR(g.dz, nrm.z, 1e-6);
}

// Intervals of random boxes, small and large, near and far, hold every value inside them, in
// the single-box and the 16-box evaluators; for a moved oracle too.
TEST(MeshOracle, IntervalsContainEveryValueOfTheirBox) {
  const TriMesh mesh = test::make_sphere(2, 1.0);
  const auto oracle = std::make_shared<const MeshOracle>(mesh);
  Affine3 turn;
  turn.m[0][0] = 0.6, turn.m[0][2] = 0.8, turn.m[2][0] = -0.8, turn.m[2][2] = 0.6, turn.m[1][3] = 1e4;
  Graph g;
  const Expr m(g, g.oracle(oracle)), moved(g, g.oracle(oracle->transformed(turn)));
  const Expr y = g.y();
  // (expression, where its surface is along y)
  const std::pair<NodeId, double> cases[] = {
      {m.id(), 0}, {(abs(m) - 0.1f).id(), 0}, {moved.id(), -1e4}, {max(moved, y + 1e4f).id(), -1e4}};
  for (const auto& [root, shift] : cases) {
    const Tape t = Tape::compile(g, root);
    IntervalEvaluator ie;
    IntervalBatchEvaluator ib;
    PointEvaluator pe;
    std::mt19937_64 rng(root);
    for (int round = 0; round < 40; ++round) {
      Interval bx[16], by[16], bz[16];
      for (int k = 0; k < 16; ++k) {
        const double size = std::pow(10.0, std::uniform_real_distribution<double>(-4, 0.5)(rng));
        std::uniform_real_distribution<double> c(-2, 2);
        const double cx = c(rng), cy = c(rng) + shift, cz = c(rng);
        bx[k] = {static_cast<float>(cx - size), static_cast<float>(cx + size)};
        by[k] = {static_cast<float>(cy - size), static_cast<float>(cy + size)};
        bz[k] = {static_cast<float>(cz - size), static_cast<float>(cz + size)};
      }
      ib.eval(t, bx, by, bz, 16);
      for (int k = 0; k < 16; ++k) {
        const Interval one = ie.eval(t, bx[k], by[k], bz[k]);
        EXPECT_EQ(one.lo, ib.result(k).lo);
        EXPECT_EQ(one.hi, ib.result(k).hi);
        std::uniform_real_distribution<float> px(bx[k].lo, bx[k].hi), py(by[k].lo, by[k].hi), pz(bz[k].lo, bz[k].hi);
        for (int i = 0; i < 30; ++i) {
          const float v = pe.eval(t, px(rng), py(rng), pz(rng));
          ASSERT_TRUE(one.contains(v)) << v << " outside [" << one.lo << ", " << one.hi << "]";
        }
        for (float cx : {bx[k].lo, bx[k].hi})
          for (float cy : {by[k].lo, by[k].hi})
            for (float cz : {bz[k].lo, bz[k].hi}) ASSERT_TRUE(one.contains(pe.eval(t, cx, cy, cz)));
      }
    }
  }
}

// A moved oracle is the base at the moved point; moving twice composes; its closed form is the
// base's closed form remapped, which agrees with it.
TEST(MeshOracle, MovedOraclesComposeAndHaveAClosedForm) {
  const TriMesh mesh = test::make_box({-1, -0.5, -0.25}, {1, 0.5, 0.25});
  const auto oracle = std::make_shared<const MeshOracle>(mesh);
  Affine3 a = Affine3::translation({0.5, 0, 0});
  a.m[1][1] = 2;
  const auto moved = oracle->transformed(a);
  const auto twice = moved->transformed(Affine3::translation({0, 0, 1}));
  ASSERT_NE(dynamic_cast<const TransformedOracle*>(twice.get()), nullptr);
  EXPECT_EQ(&dynamic_cast<const TransformedOracle&>(*twice).base(), oracle.get());
  EXPECT_EQ(oracle->transformed(Affine3::identity()), oracle);
  EXPECT_DOUBLE_EQ(moved->lipschitz(), 2 * (1 + 1e-12));
  const Box3 inside = moved->inside_box();  // x in [-1.5, 0.5], y in [-0.25, 0.25]
  EXPECT_NEAR(inside.lo.x, -1.5, 1e-6);
  EXPECT_NEAR(inside.hi.y, 0.25, 1e-6);
  Graph g;
  const NodeId closed = twice->closed_form(g);
  const Tape ct = Tape::compile(g, closed);
  PointEvaluator pe;
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<float> u(-2, 2);
  for (int i = 0; i < 500; ++i) {
    const float p[3] = {u(rng), u(rng), u(rng)};
    float v = 0, b = 0;
    twice->values(&p[0], &p[1], &p[2], &v, 1);
    const float q[3] = {p[0] + 0.5f, 2 * p[1], p[2] + 1};
    oracle->values(&q[0], &q[1], &q[2], &b, 1);
    EXPECT_EQ(v, b);
    EXPECT_NEAR(pe.eval(ct, p[0], p[1], p[2]), v, 1e-5);
  }
}

// remap composes oracles with affine substitutions and refuses others.
TEST(MeshOracle, RemapIsAffineOnly) {
  const auto oracle = std::make_shared<const MeshOracle>(test::make_box());
  Graph g;
  const Expr x = g.x(), y = g.y(), z = g.z();
  const NodeId m = g.oracle(oracle);
  const NodeId moved = remap(g, m, (x - 1.0f).id(), (2.0f * y).id(), (-z).id());
  ASSERT_EQ(g.node(moved).op, Op::Oracle);
  Affine3 map;
  ASSERT_EQ(as_mesh_oracle(g, moved, &map), oracle.get());
  EXPECT_EQ(map.m[0][3], -1);
  EXPECT_EQ(map.m[1][1], 2);
  EXPECT_EQ(map.m[2][2], -1);
  EXPECT_THROW(remap(g, m, (x * x).id(), y.id(), z.id()), InputError);
  EXPECT_EQ(remap(g, m, x.id(), y.id(), z.id()), m);
  EXPECT_EQ(as_mesh_oracle(g, (Expr(g, m) + 1.0f).id()), nullptr);
}

// Writers of expression files write the closed form in place of the oracle.
TEST(MeshOracle, WritersWriteTheClosedForm) {
  const TriMesh mesh = test::make_box();
  const auto oracle = std::make_shared<const MeshOracle>(mesh);
  Graph g;
  const NodeId root = (Expr(g, g.oracle(oracle)) - 0.5f).id();
  std::ostringstream with_oracle, expected;
  write_vm(with_oracle, g, root);
  const ConvertResult closed = convert_mesh(mesh);
  Graph& cg = *closed.model.graph;
  write_vm(expected, cg, (Expr(cg, closed.model.root) - 0.5f).id());
  EXPECT_EQ(with_oracle.str(), expected.str());
  EXPECT_EQ(with_oracle.str().find("oracle"), std::string::npos);
  EXPECT_TRUE(has_oracles(g, root));
  EXPECT_FALSE(has_oracles(g, g.var_x()));
}

// What convert_mesh refuses, a mesh oracle refuses with the same message.
TEST(MeshOracle, RefusesWhatConvertRefuses) {
  TriMesh open = test::make_box();
  open.triangles.pop_back();
  std::string convert_message, oracle_message;
  try {
    convert_mesh(open);
  } catch (const InputError& e) {
    convert_message = e.what();
  }
  try {
    MeshOracle o(open);
  } catch (const InputError& e) {
    oracle_message = e.what();
  }
  EXPECT_NE(convert_message, "");
  EXPECT_EQ(convert_message, oracle_message);
  if (!test::have_shared_meshes()) GTEST_SKIP() << "../shared/data/meshes is absent";
  const std::string teapot = test::shared_mesh_dir() + "/teapot_newell.obj";
  try {
    load_field(teapot);
    ADD_FAILURE() << "an open mesh was loaded";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), teapot);
    EXPECT_NE(std::string(e.what()).find("cannot convert"), std::string::npos) << e.what();
  }
}

// Symbolic gradients of a mesh leaf are oracles of its gradient components, so operations built
// on gradients apply to meshes: Sampson normalization leaves an exact distance unchanged.
TEST(MeshOracle, GradientsOfMeshLeavesAreOraclesToo) {
  const auto oracle = std::make_shared<const MeshOracle>(test::make_sphere(2, 1.0));
  Graph g;
  const Expr m(g, g.oracle(oracle));
  Differentiator d(g);
  const Gradient gr = d.grad(m);
  const Tape tx = Tape::compile(g, gr.x.id()), tn = Tape::compile(g, ugf::normalize(m).id());
  PointEvaluator pe;
  IntervalEvaluator ie;
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<float> u(-2, 2);
  for (int i = 0; i < 300; ++i) {
    const float p[3] = {u(rng), u(rng), u(rng)};
    Grad expect;
    oracle->gradients(&p[0], &p[1], &p[2], &expect, 1);
    EXPECT_EQ(pe.eval(tx, p[0], p[1], p[2]), expect.dx);
    float v = 0;
    oracle->values(&p[0], &p[1], &p[2], &v, 1);
    EXPECT_NEAR(pe.eval(tn, p[0], p[1], p[2]), v, 1e-6);
    const Interval b = ie.eval(tx, {p[0] - 0.1f, p[0] + 0.1f}, {p[1], p[1]}, {p[2], p[2]});
    EXPECT_TRUE(b.lo >= -1.001f && b.hi <= 1.001f && b.contains(expect.dx));
  }
  EXPECT_NE(dynamic_cast<const GradientOracle*>(&g.oracle_of(g.node(gr.y.id()))), nullptr);
}

// A mesh oracle minus a sphere meshes into a closed solid of the right volume.
TEST(MeshOracle, MixedExpressionsMeshIntoSolids) {
  const auto oracle = std::make_shared<const MeshOracle>(test::make_box());
  Graph g;
  const Expr x = g.x(), y = g.y(), z = g.z();
  const Expr cut = max(Expr(g, g.oracle(oracle)), -(sqrt(x * x + y * y + (z - 1.0f) * (z - 1.0f)) - 0.75f));
  MeshOptions mo;
  mo.resolution = 64;
  mo.lipschitz = 1;
  mo.known_bounds = Box3{{-1, -1, -1}, {1, 1, 1}};
  const TriMesh out = mesh_expression(Tape::compile(g, cut.id()), mo);
  const ValidationReport r = validate_mesh(out);
  EXPECT_TRUE(r.is_solid()) << r.summary();
  // The cube of side 2 minus the part of the ball inside it (a hemisphere of radius 0.75).
  const double expected = 8.0 - 2.0 / 3.0 * M_PI * 0.75 * 0.75 * 0.75;
  EXPECT_NEAR(r.volume, expected, 0.01 * expected);
}

}  // namespace
}  // namespace frep
