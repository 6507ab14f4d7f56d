// The mesher as a whole: the shared 3D models mesh to valid solids with both methods; the mesh is
// bit-identical for any thread count and any subdivision tiles; bounds are found (or refused for
// unbounded fields); options are checked; progress is reported and a cancel flag stops the run.
#include <gtest/gtest.h>

#include <cstdio>

#include <algorithm>
#include <array>
#include <atomic>
#include <tuple>
#include <cmath>
#include <filesystem>

#include "contour_test_util.hpp"
#include "frep/convert/convert.hpp"
#include "frep/error.hpp"
#include "frep/expr/expr.hpp"
#include "frep/script/load.hpp"
#include "frep/io/vm.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "mesh_test_util.hpp"
#include "test_util.hpp"

namespace frep {
namespace {

using test::mesh_solid;
using test::options;

Tape load(const std::string& name) {
  const Model m = read_vm(test::data_file(name));
  return Tape::compile(*m.graph, m.root);
}

// The same triangles at the same positions, in any order.
std::vector<std::array<double, 9>> triangle_set(const TriMesh& m) {
  std::vector<std::array<double, 9>> out;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    // Rotated so the smallest vertex comes first (orientation kept).
    int first = 0;
    for (int k = 1; k < 3; ++k) {
      const Vec3 a = m.corner(t, k), b = m.corner(t, first);
      if (std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z)) first = k;
    }
    std::array<double, 9> r;
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = m.corner(t, (first + k) % 3);
      r[3 * k] = p.x, r[3 * k + 1] = p.y, r[3 * k + 2] = p.z;
    }
    out.push_back(r);
  }
  std::sort(out.begin(), out.end());
  return out;
}

bool same_mesh(const TriMesh& a, const TriMesh& b) {
  if (a.vertices.size() != b.vertices.size() || a.triangles != b.triangles) return false;
  for (std::size_t i = 0; i < a.vertices.size(); ++i)
    if (!(a.vertices[i] == b.vertices[i])) return false;
  return true;
}

// Every 3D model of the shared data, both methods, bounds found by the search.
TEST(Mesher, SharedModelsAreSolids) {
  for (const char* name : {"bear.vm", "tanglecube.vm"}) {
    if (!test::have_data(name)) GTEST_SKIP() << "shared test data not found: " << test::data_file(name);
    const Tape t = load(name);
    for (auto method : {MeshMethod::DualContouring, MeshMethod::Snap}) {
      MeshOptions o;
      o.resolution = 48;
      o.method = method;
      MeshStats st;
      const TriMesh m = mesh_solid(t, o, name, &st);
      EXPECT_TRUE(st.bounds_found);
      EXPECT_FALSE(st.capped);
      EXPECT_GT(m.triangles.size(), 1000u);
    }
  }
}

// The shared Rhai models (loaded by file type), both methods, at a coarse resolution: the
// gyroid sphere and the sponge are full of thin walls and tiny pieces there.
TEST(Mesher, SharedRhaiModelsAreSolids) {
  const std::string dir = FREP_SOURCE_DIR "/../shared/data/rhai";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << "shared test data not found: " << dir;
  int models = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".rhai") continue;
    const Model model = load_expression(entry.path().string());
    const Tape t = Tape::compile(*model.graph, model.root);
    for (auto method : {MeshMethod::DualContouring, MeshMethod::Snap}) {
      MeshOptions o;
      o.resolution = 32;
      o.method = method;
      const TriMesh m = mesh_solid(t, o, entry.path().filename().string());
      EXPECT_GT(m.triangles.size(), 100u);
    }
    ++models;
  }
  EXPECT_GT(models, 0);
}

// Vertices the repairs cannot untangle depend on where the surface meets the cells: Fidget's
// sponge at 64 cells left 24 (a mesh whose triangles cross, with a warning). The mesher then
// meshes again on shifted grids of the same cell size and keeps the mesh with the fewest.
TEST(Mesher, TangledVerticesAreMeshedAgainOnAShiftedGrid) {
  const std::string path = FREP_SOURCE_DIR "/../shared/data/rhai/sponge.rhai";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared test data not found: " << path;
  const Model model = load_expression(path);
  MeshOptions o;
  o.resolution = 64;
  MeshStats st;
  mesh_solid(Tape::compile(*model.graph, model.root), o, "sponge at 64", &st);  // checks unresolved == 0
  EXPECT_GT(st.unresolved_first, 0u) << "the first grid no longer tangles: pick another resolution for this test";
  EXPECT_TRUE(st.shifted);
}

// The bear at 128 over [-1,1]^3 (where its fine details are), dual contouring.
TEST(Mesher, BearAt128IsASolid) {
  FREP_REQUIRE_DATA("bear.vm");
  mesh_solid(load("bear.vm"), options(128), "bear at 128");
}

// A 2D model extruded between given bounds: sharp corners on every letter, flat caps, three
// vertices along one sharp edge in many quads. Written as STL (f32 coordinates) and read back,
// it is still a valid solid.
TEST(Mesher, ExtrudedProsperoThroughStl) {
  FREP_REQUIRE_DATA("prospero.vm");
  const Tape t = load("prospero.vm");
  for (auto method : {MeshMethod::DualContouring, MeshMethod::Snap}) {
    const TriMesh m = mesh_solid(t, options(128, Box3{{-1, -1, -0.05}, {1, 1, 0.05}}, method), "extruded prospero");
    const TriMesh back = read_mesh_from_memory(write_mesh_to_string(m, MeshFormat::Stl), "prospero.stl");
    EXPECT_TRUE(validate_mesh(back).is_solid()) << validate_mesh(back).summary();
  }
}

TEST(Mesher, SameMeshForAnyThreadCountAndTiles) {
  FREP_REQUIRE_DATA("bear.vm");
  const Tape t = load("bear.vm");
  for (auto method : {MeshMethod::DualContouring, MeshMethod::Snap}) {
    MeshOptions o = options(40, Box3{{-1, -1, -1}, {1, 1, 1}}, method);
    o.threads = 1;
    const TriMesh ref = mesh_solid(t, o, "bear at 40");
    ASSERT_GT(ref.triangles.size(), 1000u);
    for (int threads : {2, 3}) {
      o.threads = threads;
      EXPECT_TRUE(same_mesh(mesh_expression(t, o), ref)) << threads << " threads";
    }
    // Leaves of other sizes: the same cells, so the same triangles (numbered in another order).
    const auto ref_set = triangle_set(ref);
    for (std::vector<int> tiles : std::vector<std::vector<int>>{{16, 4}, {32, 8, 2}, {20}}) {
      o.tiles = tiles;
      o.threads = 2;
      EXPECT_TRUE(triangle_set(mesh_expression(t, o)) == ref_set) << "tiles " << ::testing::PrintToString(tiles);
    }
  }
}

// A Lipschitz bound settles more boxes (and, by default, halves the tiles per level) but no cell
// with a sign change: the same triangles, for exact distances (converted meshes).
TEST(Mesher, LipschitzBoundGivesTheSameTriangles) {
  const ConvertResult r = convert_mesh(test::make_sphere(2, 0.8));
  const Tape t = Tape::compile(*r.model.graph, r.model.root);
  for (auto method : {MeshMethod::DualContouring, MeshMethod::Snap}) {
    MeshOptions o = options(36, Box3{{-1, -1, -1}, {1, 1, 1}}, method);
    const TriMesh ref = mesh_solid(t, o, "converted sphere");
    o.lipschitz = 1;
    for (int threads : {1, 2}) {
      o.threads = threads;
      EXPECT_TRUE(triangle_set(mesh_solid(t, o, "converted sphere, Lipschitz")) == triangle_set(ref)) << threads << " threads";
    }
    o.tiles = {16, 4};
    EXPECT_TRUE(triangle_set(mesh_expression(t, o)) == triangle_set(ref)) << "tiles 16, 4";
  }
}

// Central differences instead of the gradient evaluator for snapping.
TEST(Mesher, SnapWithCentralDifferences) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  const Expr torus = sqrt(square(sqrt(square(x) + square(y)) - 0.5f) + square(z)) - 0.2f;
  MeshOptions o = options(32, Box3{}, MeshMethod::Snap);
  o.snap.gradient = SnapGradient::CentralDifferences;
  MeshStats st;
  const TriMesh m = mesh_solid(torus, o, "torus, central differences", &st);
  for (const Vec3& p : m.vertices) {
    const double d = std::hypot(std::hypot(p.x, p.y) - 0.5, p.z) - 0.2;
    EXPECT_LT(std::fabs(d), 0.1 * st.cell_size);
  }
  EXPECT_EQ(validate_mesh(m).genus, 1);
}

TEST(Mesher, BoundsSearch) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  // An off-centre ball: the box found contains it, and not much more.
  const Expr ball = sqrt(square(x - 0.3f) + square(y + 0.2f) + square(z - 0.1f)) - 0.4f;
  const BoundsResult r = find_bounds(Tape::compile(g, ball.id()));
  EXPECT_FALSE(r.empty);
  const Vec3 c{0.3, -0.2, 0.1};
  for (int a = 0; a < 3; ++a) {
    EXPECT_LE(r.box.lo[a], c[a] - 0.4);
    EXPECT_GE(r.box.hi[a], c[a] + 0.4);
    EXPECT_GT(r.box.lo[a], c[a] - 0.4 - 0.05);
    EXPECT_LT(r.box.hi[a], c[a] + 0.4 + 0.05);
  }
  // Nothing inside: an empty result, and an empty mesh.
  const Expr none = sqrt(square(x) + square(y) + square(z)) + 1.0f;
  EXPECT_TRUE(find_bounds(Tape::compile(g, none.id())).empty);
  EXPECT_TRUE(mesh_expression(none, options(16, Box3{})).triangles.empty());
  // Unbounded: a half-space, a 2D disc (an infinite cylinder), a gyroid lattice.
  const std::vector<Expr> unbounded = {x - 0.5f, sqrt(square(x) + square(y)) - 0.5f,
                                       sin(x * 5) * cos(y * 5) + sin(y * 5) * cos(z * 5) + sin(z * 5) * cos(x * 5)};
  for (const Expr& e : unbounded) {
    try {
      mesh_expression(e, options(16, Box3{}));
      ADD_FAILURE() << "an unbounded field was meshed";
    } catch (const InputError& err) {
      EXPECT_NE(std::string(err.what()).find("--bounds"), std::string::npos) << err.what();
      EXPECT_NE(std::string(err.what()).find("unbounded"), std::string::npos) << err.what();
    }
  }
}

// When intervals cannot bound the inside, the error says why, from samples: NaN everywhere, or
// bounded but unprovable (with the region to give, which must hold the shape).
TEST(Mesher, UnprovenBoundsAreExplained) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  const auto message = [&](const Expr& e) -> std::string {
    try {
      mesh_expression(e, options(16, Box3{}));
    } catch (const InputError& err) {
      return err.what();
    }
    return "(meshed)";
  };
  // sqrt of a negative number everywhere.
  const std::string nan = message(sqrt(-1.0f - square(x)));
  EXPECT_NE(nan.find("NaN"), std::string::npos) << nan;
  // A ball of radius 2 plus square(x) - x * x: exactly 0, but the intervals of the two terms
  // differ wherever x's interval holds 0, so the search never proves the far boxes positive.
  const std::string ball = message(sqrt(square(x) + square(y) + square(z)) - 2.0f - (square(x) - x * x));
  EXPECT_NE(ball.find("could not prove"), std::string::npos) << ball;
  const auto at = ball.find("give --bounds ");
  ASSERT_NE(at, std::string::npos) << ball;
  double b[6];
  ASSERT_EQ(std::sscanf(ball.c_str() + at + 14, "%lf,%lf,%lf,%lf,%lf,%lf", &b[0], &b[1], &b[2], &b[3], &b[4], &b[5]), 6);
  for (int a = 0; a < 3; ++a) {
    EXPECT_LE(b[a], -2.0) << ball;
    EXPECT_GE(b[a + 3], 2.0) << ball;
    EXPECT_LE(b[a + 3], 4.0) << "a useful region, not the search cube: " << ball;
  }
}

// Known bounds replace the search (for fields taking their value from the nearest feature, like
// converted meshes, intervals cannot bound the inside far away), with a margin cell.
TEST(Mesher, KnownBounds) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  const Expr a = sqrt(square(x - 0.3f) + square(y) + square(z)) - 0.25f;
  const Expr b = sqrt(square(x + 0.3f) + square(y) + square(z)) - 0.25f;
  // The value of the nearer ball (by absolute value): a union of the two, for intervals a puzzle.
  const Expr nearer = if_nonzero_else(compare(abs(a), abs(b)) + 1, b, a);
  MeshOptions o = options(24, Box3{});
  o.known_bounds = Box3{{-0.55, -0.25, -0.25}, {0.55, 0.25, 0.25}};
  MeshStats st;
  const TriMesh m = mesh_solid(nearer, o, "two balls, known bounds", &st);
  EXPECT_TRUE(st.bounds_known);
  EXPECT_FALSE(st.bounds_found);
  EXPECT_EQ(validate_mesh(m).components, 2u);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_LT(st.bounds.lo[axis], o.known_bounds.lo[axis]);  // a margin cell beyond the box
    EXPECT_GT(st.bounds.hi[axis], o.known_bounds.hi[axis]);
  }
  o.known_bounds = Box3{{0, 0, 0}, {1, NAN, 1}};
  EXPECT_THROW(Mesher bad(o), InputError);
}

TEST(Mesher, OptionsAreChecked) {
  auto bad = [](auto change) {
    MeshOptions o;
    change(o);
    EXPECT_THROW(Mesher m(o), InputError);
  };
  bad([](MeshOptions& o) { o.resolution = 0; });
  bad([](MeshOptions& o) { o.resolution = kMaxMeshResolution + 1; });
  bad([](MeshOptions& o) { o.cell_size = std::nan(""); });
  bad([](MeshOptions& o) { o.cell_size = -1; });
  bad([](MeshOptions& o) { o.bounds = Box3{{0, 0, 0}, {1, 0, 1}}; });
  bad([](MeshOptions& o) { o.bounds = Box3{{0, 0, 0}, {1, INFINITY, 1}}; });
  bad([](MeshOptions& o) { o.bounds = Box3{{0, 0, std::nan("")}, {1, 1, 1}}; });
  bad([](MeshOptions& o) { o.tiles = {16, 6}; });
  bad([](MeshOptions& o) { o.tiles = {64}; });
  bad([](MeshOptions& o) { o.edge_tolerance = 0; });
  // A cell size that needs more cells than allowed along an axis.
  Graph g;
  const Expr ball = sqrt(square(g.x()) + square(g.y()) + square(g.z())) - 0.5f;
  MeshOptions o = options(16);
  o.cell_size = 1e-4;
  EXPECT_THROW(mesh_expression(ball, o), InputError);
  // Cells finer than f32 coordinates resolve.
  o = options(64, Box3{{1e6, 1e6, 1e6}, {1e6 + 1, 1e6 + 1, 1e6 + 1}});
  EXPECT_THROW(mesh_expression(ball, o), InputError);
}

TEST(Mesher, ProgressAndCancel) {
  Graph g;
  const Expr ball = sqrt(square(g.x()) + square(g.y()) + square(g.z())) - 0.5f;
  MeshOptions o = options(48);
  std::vector<double> cells;
  bool bounds_phase = false;
  o.bounds = Box3{};
  o.progress = [&](const MeshProgress& p) {
    if (std::string(p.phase) == "bounds") bounds_phase = true;
    if (std::string(p.phase) == "cells") cells.push_back(p.fraction);
  };
  const TriMesh m = mesh_solid(ball, o, "ball with progress");
  EXPECT_FALSE(m.triangles.empty());
  EXPECT_TRUE(bounds_phase);
  ASSERT_FALSE(cells.empty());
  EXPECT_EQ(cells.back(), 1.0);
  for (std::size_t i = 1; i < cells.size(); ++i) EXPECT_LE(cells[i - 1], cells[i]);
  std::atomic<bool> stop{true};
  o.cancel = &stop;
  EXPECT_THROW(mesh_expression(ball, o), MeshCancelled);
}

}  // namespace
}  // namespace frep
