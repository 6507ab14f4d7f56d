// Flat regions merged (frep/mesh/merge_flat.hpp) on the mesher's output: the result is a solid
// (checked by frep's validator and by CGAL), its vertices are input vertices at their exact
// positions, and its surface and the input's lie within the tolerance of each other (an
// independent distance oracle, both ways), on CAD-like shapes and on curved ones.
#include "frep/mesh/merge_flat.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "cgal_test_util.hpp"
#include "contour_test_util.hpp"
#include "frep/contour/mesher.hpp"
#include "frep/mesh/mesh_distance.hpp"
#include "frep/mesh/validate.hpp"
#include "frep/script/load.hpp"

namespace frep {
namespace {

struct Shape {
  std::string name;
  Tape e;
  bool flat;  // all faces flat: most triangles must go
};

// Largest distance from points of `a` (its vertices and random points of each triangle) to `b`.
double one_way_distance(const TriMesh& a, const TriMesh& b, int per_triangle) {
  const MeshDistance d(b);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  double worst = 0;
  for (const Vec3& v : a.vertices) worst = std::max(worst, d.closest_point(v).distance);
  for (const Triangle& t : a.triangles)
    for (int k = 0; k < per_triangle; ++k) {
      double s = u(rng), r = u(rng);
      if (s + r > 1) s = 1 - s, r = 1 - r;
      const Vec3 p = a.vertices[t[0]] + (a.vertices[t[1]] - a.vertices[t[0]]) * s + (a.vertices[t[2]] - a.vertices[t[0]]) * r;
      worst = std::max(worst, d.closest_point(p).distance);
    }
  return worst;
}

std::vector<Shape> shapes() {
  std::vector<Shape> out;
  auto box = [](const Expr& x, const Expr& y, const Expr& z, double a, double b, double c) {
    return max(max(abs(x) - float(a), abs(y) - float(b)), abs(z) - float(c));
  };
  struct Xyz {
    Graph g;
    Expr x = g.x(), y = g.y(), z = g.z();
  };
  auto add = [&](const std::string& name, const Expr& e, bool flat) { out.push_back({name, Tape::compile(e.graph(), e.id()), flat}); };
  {
    Xyz s;
    add("box", box(s.x - 0.03f, s.y + 0.02f, s.z, 0.7, 0.5, 0.3), true);
  }
  {
    Xyz s;  // turned about two axes: no face or crease along the grid
    const double a = 0.5, b = 0.35;
    auto u = s.x * float(std::cos(a)) + s.y * float(std::sin(a));
    auto v0 = -s.x * float(std::sin(a)) + s.y * float(std::cos(a));
    auto v = v0 * float(std::cos(b)) + s.z * float(std::sin(b));
    auto w = -v0 * float(std::sin(b)) + s.z * float(std::cos(b));
    add("rotated box", box(u, v, w, 0.5, 0.35, 0.25), true);
  }
  {
    Xyz s;  // an L: a concave crease
    add("L", min(box(s.x, s.y, s.z, 0.7, 0.2, 0.3), box(s.x + 0.5f, s.y - 0.3f, s.z, 0.2, 0.5, 0.3)), true);
  }
  {
    Xyz s;  // a frame: a square hole through it (genus 1), and a cavity inside (a second shell)
    const Expr frame = max(box(s.x, s.y, s.z, 0.7, 0.7, 0.25), -box(s.x, s.y, s.z, 0.3, 0.3, 0.5));
    add("frame with a cavity", max(frame, -box(s.x - 0.5f, s.y, s.z, 0.1, 0.3, 0.1)), true);
  }
  {
    Xyz s;  // a plate with a round hole: flat faces around a curved one
    const Expr plate = box(s.x, s.y, s.z, 0.7, 0.5, 0.15);
    add("plate with a round hole", max(plate, 0.3f - sqrt(square(s.x) + square(s.y))), false);
  }
  {
    Xyz s;
    add("ball", sqrt(square(s.x) + square(s.y) + square(s.z)) - 0.7f, false);
  }
  return out;
}

TEST(MergeFlat, SolidsKeepTheirSurfaceAndLoseTheGrid) {
  for (const Shape& sh : shapes()) {
    SCOPED_TRACE(sh.name);
    MeshOptions o = test::options(48);
    o.merge_flat = false;
    MeshStats st;
    const TriMesh uniform = test::mesh_solid(sh.e, o, sh.name, &st);
    const double tol = kFlatTolerance * st.cell_size;
    MergeFlatReport rep;
    const TriMesh merged = merge_flat_regions(uniform, tol, &rep);
    const ValidationReport v = validate_mesh(merged);
    EXPECT_TRUE(v.is_solid());
    EXPECT_FALSE(test::cgal_self_intersects(merged));
    EXPECT_EQ(rep.refused, 0u);
    // Vertices removed, none moved.
    std::set<std::array<double, 3>> before;
    for (const Vec3& p : uniform.vertices) before.insert({p.x, p.y, p.z});
    for (const Vec3& p : merged.vertices) EXPECT_TRUE(before.count({p.x, p.y, p.z})) << p.x << " " << p.y << " " << p.z;
    EXPECT_EQ(merged.vertices.size() + rep.removed, uniform.vertices.size());
    // The same surface both ways, to the tolerance (a crease straightened moves it by at most that).
    EXPECT_LE(one_way_distance(merged, uniform, 8), 2 * tol);
    EXPECT_LE(one_way_distance(uniform, merged, 1), 2 * tol);
    EXPECT_NEAR(v.volume, validate_mesh(uniform).volume, 1e-6);
    if (sh.flat) {
      // (The turned box keeps more: where its edges cross cells badly the grid's vertices sit up
      // to 0.08 cells off its faces, and the triangles there are in no face's plane.)
      EXPECT_LT(merged.triangles.size() * 5, uniform.triangles.size()) << merged.triangles.size();
    } else {
      EXPECT_LE(merged.triangles.size(), uniform.triangles.size());
    }
    if (sh.name == "ball") {
      EXPECT_EQ(merged.triangles.size(), uniform.triangles.size()) << "nothing flat on a ball";
    }
    // The mesher does the same by default, and says so.
    MeshOptions d = test::options(48);
    MeshStats ds;
    const TriMesh by_default = test::mesh_solid(sh.e, d, sh.name, &ds);
    EXPECT_EQ(by_default.triangles, merged.triangles);
    EXPECT_EQ(by_default.vertices, merged.vertices);
    EXPECT_EQ(ds.flat_regions, rep.regions);
  }
}

// A slab 1.2 cells thick: its two large faces, a cell apart and facing away from each other,
// never join one region, whatever the tolerance.
TEST(MergeFlat, ThinSlabsStaySolid) {
  Graph g;
  const Expr x = g.x(), y = g.y(), z = g.z();
  const Expr slab = max(max(abs(x) - 0.6f, abs(y) - 0.6f), abs(z) - 0.03f);
  MeshOptions o = test::options(40);
  o.merge_flat = false;
  MeshStats st;
  const TriMesh uniform = test::mesh_solid(slab, o, "slab", &st);
  for (double tol : {1e-4 * st.cell_size, 0.01 * st.cell_size}) {
    const TriMesh merged = merge_flat_regions(uniform, tol);
    EXPECT_TRUE(validate_mesh(merged).is_solid()) << tol;
    EXPECT_FALSE(test::cgal_self_intersects(merged)) << tol;
    EXPECT_LE(merged.triangles.size(), 40u) << tol;
  }
}

// The demo's job: the bracket (a plate with a 48-sided hole), converted to its exact distance and
// meshed at 128 cells with the default options: a few times its own 416 triangles, not 58,120.
TEST(MergeFlat, BracketAtTheDemoResolutionByDefault) {
  const Model m = load_field(FREP_SOURCE_DIR "/examples/bracket.obj");
  const Tape tape = Tape::compile(*m.graph, m.root);
  const MeshOptions o = test::model_options(m, 128);
  MeshStats st;
  const TriMesh merged = test::mesh_solid(tape, o, "bracket", &st);
  EXPECT_EQ(st.triangles_before_simplify, 58120u);
  EXPECT_LT(merged.triangles.size(), 2000u);
  EXPECT_FALSE(test::cgal_self_intersects(merged));
}

// A closed pillow thinner than the tolerance: its top and bottom are each flat to it, and each
// alone would be re-triangulated into the other's triangle turned over (a shell of no volume).
// Both are left as they were.
TEST(MergeFlat, ThinnerThanTheToleranceIsLeftAlone) {
  const double h = 1e-4;
  TriMesh m;
  for (const Vec3& p : std::vector<Vec3>{{0, 0, 0}, {0.5, 0, 0}, {1, 0, 0}, {0.5, 0.5, 0}, {0, 1, 0}, {0, 0.5, 0}})
    m.vertices.push_back(p);
  m.vertices.push_back({0.3, 0.3, h});
  m.vertices.push_back({0.3, 0.3, -h});
  for (unsigned i = 0; i < 6; ++i) {
    const unsigned j = (i + 1) % 6;
    m.add_triangle(i, j, 6);
    m.add_triangle(j, i, 7);
  }
  ASSERT_TRUE(validate_mesh(m).is_solid());
  MergeFlatReport rep;
  const TriMesh out = merge_flat_regions(m, 1e-3, &rep);
  EXPECT_TRUE(validate_mesh(out).is_solid());
  EXPECT_EQ(out.triangles.size(), m.triangles.size());
}

// Random unions and differences of boxes (some turned), balls, cylinders and half-spaces, merged
// with the mesher's tolerance and with far larger ones (up to a cell, where regions take in
// slivers and lips at an angle): every output a solid, no crossings (CGAL), the same volume to
// what the tolerance allows.
TEST(MergeFlat, RandomSolidsStaySolidAtAnyTolerance) {
  int merged_some = 0;
  std::vector<int> seeds(40);
  std::iota(seeds.begin(), seeds.end(), 0);
  seeds.push_back(1393);  // at a cell, a lip at an angle taken into a region turned its hole over
  for (int seed : seeds) {
    std::mt19937 rng(static_cast<unsigned>(seed));
    std::uniform_real_distribution<double> U(-1, 1);
    Graph g;
    const Expr x = g.x(), y = g.y(), z = g.z();
    auto box = [&](bool turned) {
      const double cx = 0.4 * U(rng), cy = 0.4 * U(rng), cz = 0.4 * U(rng);
      const double a = 0.15 + 0.35 * std::fabs(U(rng)), b = 0.15 + 0.35 * std::fabs(U(rng)), c = 0.15 + 0.35 * std::fabs(U(rng));
      Expr X = x - float(cx), Y = y - float(cy), Z = z - float(cz);
      if (turned) {
        const double t1 = 3 * U(rng), t2 = 3 * U(rng);
        const Expr u = X * float(std::cos(t1)) + Y * float(std::sin(t1));
        const Expr v0 = -X * float(std::sin(t1)) + Y * float(std::cos(t1));
        const Expr v = v0 * float(std::cos(t2)) + Z * float(std::sin(t2));
        const Expr w = -v0 * float(std::sin(t2)) + Z * float(std::cos(t2));
        X = u, Y = v, Z = w;
      }
      return max(max(abs(X) - float(a), abs(Y) - float(b)), abs(Z) - float(c));
    };
    auto shape = [&]() -> Expr {
      switch (rng() % 4) {
        case 0: {
          const double cx = 0.4 * U(rng), cy = 0.4 * U(rng), cz = 0.4 * U(rng), r = 0.2 + 0.4 * std::fabs(U(rng));
          return sqrt(square(x - float(cx)) + square(y - float(cy)) + square(z - float(cz))) - float(r);
        }
        case 1: {
          const double cx = 0.4 * U(rng), cy = 0.4 * U(rng), r = 0.2 + 0.4 * std::fabs(U(rng)), h = 0.2 + 0.5 * std::fabs(U(rng));
          return max(sqrt(square(x - float(cx)) + square(y - float(cy))) - float(r), abs(z) - float(h));
        }
        case 2: {
          const double a = U(rng), b = U(rng), c = U(rng), d = 0.3 * U(rng), l = std::sqrt(a * a + b * b + c * c) + 1e-9;
          return x * float(a / l) + y * float(b / l) + z * float(c / l) - float(d);
        }
        default:
          return box(rng() % 2 == 0);
      }
    };
    Expr e = box(rng() % 3 == 0);
    for (int i = 1, k = 2 + static_cast<int>(rng() % 4); i < k; ++i) e = rng() % 3 == 0 ? max(e, -shape()) : min(e, shape());
    MeshOptions o = test::options(12 + static_cast<int>(rng() % 30));
    o.merge_flat = false;
    MeshStats st;
    const TriMesh m = mesh_expression(e, o, &st);
    if (m.triangles.empty() || st.unresolved > 0) continue;
    const double volume = validate_mesh(m).volume;
    for (double cells : {kFlatTolerance, 0.01, 0.5, 1.0}) {
      SCOPED_TRACE("seed " + std::to_string(seed) + ", tolerance " + std::to_string(cells) + " cells");
      const double tol = cells * st.cell_size;
      MergeFlatReport rep;
      const TriMesh out = merge_flat_regions(m, tol, &rep);
      const ValidationReport v = validate_mesh(out);
      EXPECT_TRUE(v.is_solid()) << v.summary();
      EXPECT_FALSE(test::cgal_self_intersects(out));
      EXPECT_NEAR(v.volume, volume, 4 * tol * v.area + 1e-9);
      merged_some += rep.regions > 0;
    }
  }
  EXPECT_GT(merged_some, 40);
}

// The text of `--max-error` (and Python's max_error): flat, 0, a bound in units or cells.
TEST(MeshOptionsText, MaxError) {
  MeshOptions o;
  ASSERT_TRUE(set_max_error(o, "0"));
  EXPECT_EQ(o.max_error, 0);
  EXPECT_FALSE(o.merge_flat);
  ASSERT_TRUE(set_max_error(o, "flat"));
  EXPECT_EQ(o.max_error, 0);
  EXPECT_TRUE(o.merge_flat);
  ASSERT_TRUE(set_max_error(o, "0.05c"));
  EXPECT_EQ(o.max_error, 0.05);
  EXPECT_TRUE(o.max_error_in_cells);
  EXPECT_TRUE(o.merge_flat);
  ASSERT_TRUE(set_max_error(o, "0.01"));
  EXPECT_EQ(o.max_error, 0.01);
  EXPECT_FALSE(o.max_error_in_cells);
  for (const char* bad : {"", "c", "-1", "-0.5c", "abc", "1e999", "nan", "inf", "0.05cc", "flat0", "0.1 "}) {
    MeshOptions b;
    b.max_error = 7;
    EXPECT_FALSE(set_max_error(b, bad)) << bad;
    EXPECT_EQ(b.max_error, 7) << bad << ": untouched";
  }
}

}  // namespace
}  // namespace frep
