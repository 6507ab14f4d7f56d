// UGF operations on converted meshes and on meshed results: offsetting a converted mesh by r
// equals the mesh's exact distance (MeshDistance) minus r; a shell of thickness t measures t
// through the wall, on the field and on its dual contouring mesh; a chamfered box edge meshed
// with DC has the requested width within one cell; every mesh made is closed and manifold
// (validate_mesh, the validator behind frep check).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "frep/contour/mesher.hpp"
#include "frep/convert/convert.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/mesh/mesh_distance.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/validate.hpp"
#include "frep/ugf.hpp"
#include "mesh_test_util.hpp"

namespace frep {
namespace {

TriMesh bracket() { return read_mesh(std::string(FREP_SOURCE_DIR) + "/examples/bracket.obj"); }

Box3 bounds_of(const TriMesh& m) {
  Box3 b;
  for (const Vec3& v : m.vertices) b.add(v);
  return b;
}

TEST(UgfMesh, OffsetOfAConvertedMeshIsItsDistanceMinusR) {
  for (const char* name : {"bracket", "sphere"}) {
    SCOPED_TRACE(name);
    const TriMesh mesh = std::string(name) == "bracket" ? bracket() : test::make_sphere(2, 1.0);
    ConvertResult conv = convert_mesh(mesh);
    const Box3 box = bounds_of(mesh);
    const Vec3 size = box.size();
    const double extent = std::max({size.x, size.y, size.z});
    const MeshDistance oracle(mesh);
    double worst = 0;
    for (double r : {0.05 * extent, -0.02 * extent}) {
      const Expr off = ugf::offset(conv.model.root_expr(), static_cast<float>(r));
      const Tape tape = Tape::compile(*conv.model.graph, off.id());
      PointEvaluator pe;
      std::mt19937_64 rng(7);
      const Box3 region = box.inflated(0.3 * extent);
      std::uniform_real_distribution<double> ux(region.lo.x, region.hi.x), uy(region.lo.y, region.hi.y),
          uz(region.lo.z, region.hi.z);
      for (int i = 0; i < 600; ++i) {
        const Vec3 p{ux(rng), uy(rng), uz(rng)};
        const Vec3f pf(p);
        const double ref = oracle.signed_distance(Vec3(pf), SignMethod::Pseudonormal) - r;
        const double got = pe.eval(tape, pf.x, pf.y, pf.z);
        worst = std::max(worst, std::fabs(got - ref));
      }
    }
    // f32 evaluation of distances up to about the extent: a few ulps of it.
    EXPECT_LT(worst, 4e-6 * extent);
    std::printf("[ugf-error] offset of converted %s (r = 5%% and -2%% of its size): max |F - r - (MeshDistance - r)| = %.2g (%.2g of its size)\n",
                name, worst, worst / extent);
  }
}

// Where along the ray p0 + s d (s in [s0, s1]) the field changes sign, each to 1e-7: up to `n`.
template <class F>
std::vector<double> crossings(F f, Vec3 p0, Vec3 d, double s0, double s1, int steps = 400) {
  std::vector<double> out;
  auto at = [&](double s) { return f(p0 + d * s); };
  double prev = at(s0);
  for (int i = 1; i <= steps; ++i) {
    const double s = s0 + (s1 - s0) * i / steps;
    const double v = at(s);
    if ((prev < 0) != (v < 0)) {
      double lo = s - (s1 - s0) / steps, hi = s;
      const bool lo_neg = prev < 0;
      while (hi - lo > 1e-7) {
        const double m = 0.5 * (lo + hi);
        ((at(m) < 0) == lo_neg ? lo : hi) = m;
      }
      out.push_back(0.5 * (lo + hi));
    }
    prev = v;
  }
  return out;
}

TEST(UgfMesh, AShellMeasuresItsThicknessThroughTheWall) {
  // A converted box [-1, 1]^3, hollowed by t = 0.3 (inward).
  const TriMesh box = test::make_box();
  ConvertResult conv = convert_mesh(box);
  const float t = 0.3f;
  const Expr shell = ugf::shell_inward(conv.model.root_expr(), t);
  const Tape tape = Tape::compile(*conv.model.graph, shell.id());
  PointEvaluator pe;
  MeshOptions mo;
  mo.resolution = 40;
  mo.known_bounds = bounds_of(box);
  MeshStats st;
  const TriMesh meshed = mesh_expression(tape, mo, &st);
  const ValidationReport v = validate_mesh(meshed);
  ASSERT_TRUE(v.is_solid()) << v.summary();
  const MeshDistance result(meshed);

  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  double worst_field = 0, worst_mesh = 0;
  for (int i = 0; i < 20; ++i) {
    // Through each face, along its normal, at a random spot away from the edges.
    const int axis = i % 3;
    const double sign = (i / 3) % 2 ? 1.0 : -1.0;
    Vec3 p0{u(rng), u(rng), u(rng)}, d{0, 0, 0};
    (axis == 0 ? p0.x : axis == 1 ? p0.y : p0.z) = 0;
    (axis == 0 ? d.x : axis == 1 ? d.y : d.z) = sign;
    const auto field = crossings([&](Vec3 p) { return double(pe.eval(tape, float(p.x), float(p.y), float(p.z))); }, p0, d, 0.2, 1.5);
    const auto mesh = crossings([&](Vec3 p) { return result.signed_distance(p); }, p0, d, 0.2, 1.5);
    ASSERT_EQ(field.size(), 2u);
    ASSERT_EQ(mesh.size(), 2u);
    worst_field = std::max(worst_field, std::fabs(field[1] - field[0] - t));
    worst_mesh = std::max(worst_mesh, std::fabs(mesh[1] - mesh[0] - t));
    EXPECT_NEAR(field[1], 1.0, 1e-5);  // the outer surface stays
  }
  EXPECT_LT(worst_field, 1e-5);
  EXPECT_LT(worst_mesh, 0.1 * st.cell_size);
  std::printf("[ugf-error] shell_inward t = 0.3 of a converted box: wall thickness error %.2g on the field, %.2g on its DC mesh (cell %.3g)\n",
              worst_field, worst_mesh, st.cell_size);
}

TEST(UgfMesh, AChamferedBoxEdgeMeshedWithDcHasTheRequestedWidth) {
  const Vec3 n = Vec3{1, 1, 0} * (1 / std::sqrt(2.0));   // the chamfer face's normal
  const Vec3 across = Vec3{1, -1, 0} * (1 / std::sqrt(2.0));
  struct Size {
    ugf::Chamfer c;
    double width;
    const char* name;
  };
  for (const Size& s : {Size{ugf::Chamfer::width(0.4f), 0.4, "width 0.4"}, Size{ugf::Chamfer::setback(0.3f), 0.3 * std::sqrt(2.0), "setback 0.3"},
                        Size{ugf::Chamfer::inset(0.1f), 0.2 /* w = 2 h / tan(phi/2) */, "inset 0.1"}}) {
    SCOPED_TRACE(s.name);
    Graph g;
    const Expr x = g.x(), y = g.y(), z = g.z();
    // The box [-1, 1]^3 with its +x/+y edge chamfered.
    const Expr edge = ugf::chamfer_intersection(x - 1.0f, y - 1.0f, s.c);
    const Expr part = max(max(edge, max(-x - 1.0f, -y - 1.0f)), max(z - 1.0f, -z - 1.0f));
    MeshOptions mo;
    mo.resolution = 37;  // cells that do not line up with the chamfer's edges
    MeshStats st;
    const TriMesh m = mesh_expression(part, mo, &st);
    const ValidationReport v = validate_mesh(m);
    ASSERT_TRUE(v.is_solid()) << v.summary();
    double lo = 1e9, hi = -1e9;
    int faces = 0;
    for (const Triangle& t : m.triangles) {
      const Vec3 a = m.vertices[t[0]], b = m.vertices[t[1]], c = m.vertices[t[2]];
      Vec3 nn = cross(b - a, c - a);
      const double len = std::sqrt(dot(nn, nn));
      if (!(len > 0) || dot(nn, n) / len < 0.999) continue;
      ++faces;
      for (const Vec3& p : {a, b, c}) lo = std::min(lo, dot(p, across)), hi = std::max(hi, dot(p, across));
    }
    ASSERT_GT(faces, 0);
    EXPECT_NEAR(hi - lo, s.width, st.cell_size);
    std::printf("[ugf-error] chamfer (%s) of a box edge, DC mesh at cell %.3g: width %.5f, requested %.5f (error %.2g)\n", s.name,
                st.cell_size, hi - lo, s.width, std::fabs(hi - lo - s.width));
  }
}

// Against a sphere |p - c| - r, the minimum of A + B is exactly A(c) - r (A is 1-Lipschitz and
// equals it at p = c): find_clearance on a converted mesh, whose boxes carry simplified tapes,
// must find it, gap or interference.
TEST(UgfMesh, ClearanceOfAConvertedMeshAndASphere) {
  const TriMesh mesh = bracket();
  const MeshDistance oracle(mesh);
  const Box3 box = bounds_of(mesh);
  double worst = 0;
  for (const Vec3 c : {Vec3{0.1, 0.05, 0.45}, Vec3{0.95, 0.65, 0.3}, Vec3{-0.5, 0.2, 0.1}}) {
    ConvertResult conv = convert_mesh(mesh);
    Graph& g = *conv.model.graph;
    const float r = 0.2f;
    const Expr ball = sqrt(square(g.x() - float(c.x)) + square(g.y() - float(c.y)) + square(g.z() - float(c.z))) - r;
    Box3 region = box;
    region.add(Box3{c - Vec3{r, r, r}, c + Vec3{r, r, r}});
    ugf::ClearanceOptions o;
    o.max_boxes = 5000;
    const ugf::ClearanceResult res =
        ugf::find_clearance(conv.model.root_expr(), ball, {float(region.lo.x), float(region.hi.x)},
                            {float(region.lo.y), float(region.hi.y)}, {float(region.lo.z), float(region.hi.z)}, o);
    const double ref = oracle.signed_distance(Vec3(Vec3f(c)), SignMethod::Pseudonormal) - r;
    EXPECT_NEAR(res.value, ref, 2e-5) << c.x << " " << c.y << " " << c.z;
    EXPECT_LE(res.lower_bound, ref + 1e-6);
    worst = std::max(worst, std::fabs(res.value - ref));
  }
  std::printf("[ugf-error] find_clearance of the converted bracket and spheres (gap and interference): max |value - (MeshDistance(c) - r)| = %.2g\n", worst);
}

}  // namespace
}  // namespace frep
