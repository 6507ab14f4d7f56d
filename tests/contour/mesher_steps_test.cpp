// The mesher's driver steps one at a time: the options check, the default tiles, the region (given,
// known or searched), the cell edge, the cut box and its Lipschitz bound, the tiles and the reuse
// of the subdivider, the leaves (against a brute-force count of the cells with sign changes), one
// pass over a grid, and, with stand-in passes, the rerun off corners on the surface and the
// reruns while vertices stay tangled.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "contour/assemble.hpp"
#include "contour/mesher_steps.hpp"
#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/expr/expr.hpp"
#include "frep/contour/mesher.hpp"
#include "frep/util/memory_budget.hpp"

namespace frep::contour {
namespace {

bool is_f32(double d) {
  volatile float f = static_cast<float>(d);
  return static_cast<double>(f) == d;
}

const Box3 kCube{{-1, -1, -1}, {1, 1, 1}};

struct Ball {
  Graph g;
  Expr e = sqrt(square(g.x() - 0.1f) + square(g.y()) + square(g.z() + 0.05f)) - 0.6f;
  Tape tape = Tape::compile(g, e.id());
};

TEST(MesherSteps, CheckOptionsAcceptsGoodOptionsAndRejectsEachBadOne) {
  EXPECT_NO_THROW(check_options(MeshOptions{}));
  for (std::vector<int> tiles : std::vector<std::vector<int>>{{16, 4}, {32, 8, 2}, {20}, {32}}) {
    MeshOptions o;
    o.tiles = tiles;
    EXPECT_NO_THROW(check_options(o)) << ::testing::PrintToString(tiles);
  }
  const std::vector<std::function<void(MeshOptions&)>> bad = {
      [](MeshOptions& o) { o.method = static_cast<MeshMethod>(7); },
      [](MeshOptions& o) { o.resolution = 0; },
      [](MeshOptions& o) { o.resolution = kMaxMeshResolution + 1; },
      [](MeshOptions& o) { o.cell_size = -1; },
      [](MeshOptions& o) { o.cell_size = INFINITY; },
      [](MeshOptions& o) { o.bounds = Box3{{0, 0, 0}, {1, 1, 0}}; },
      [](MeshOptions& o) { o.bounds = Box3{{0, 0, 0}, {1, INFINITY, 1}}; },
      [](MeshOptions& o) { o.known_bounds = Box3{{0, 0, -INFINITY}, {1, 1, 1}}; },
      [](MeshOptions& o) { o.edge_tolerance = 1; },
      [](MeshOptions& o) { o.edge_iterations = 65; },
      [](MeshOptions& o) { o.qef_threshold = -0.1; },
      [](MeshOptions& o) { o.snap.iterations = 101; },
      [](MeshOptions& o) { o.snap.difference_step = 0.6; },
      [](MeshOptions& o) { o.tiles = {0}; },
      [](MeshOptions& o) { o.tiles = {16, 6}; },
      [](MeshOptions& o) { o.tiles = {64}; },
  };
  for (std::size_t i = 0; i < bad.size(); ++i) {
    MeshOptions o;
    bad[i](o);
    EXPECT_THROW(check_options(o), InputError) << "bad option " << i;
  }
  // A cell size makes the resolution irrelevant.
  MeshOptions o;
  o.cell_size = 0.1;
  o.resolution = 0;
  EXPECT_NO_THROW(check_options(o));
}

TEST(MesherSteps, DefaultTilesSplitTheGridIntoAFewBoxesOfLeavesOf8) {
  for (int growth : {2, 4})
    for (int cells : {1, 8, 9, 16, 33, 100, 129, 1000, kMaxMeshResolution}) {
      const std::vector<int> t = default_tiles(cells, growth);
      SCOPED_TRACE(::testing::PrintToString(t) + " for " + std::to_string(cells) + " cells");
      EXPECT_EQ(t.back(), 8);
      for (std::size_t i = 1; i < t.size(); ++i) EXPECT_EQ(t[i - 1], t[i] * growth);
      EXPECT_GE(t.front() * growth, cells) << "the top level has at most `growth` boxes per axis";
      if (t.size() > 1) {
        EXPECT_LT(t.front(), cells) << "and more than one";
      }
      MeshOptions o;
      o.tiles = t;
      EXPECT_NO_THROW(check_options(o));
    }
}

TEST(MesherSteps, RegionIsGivenKnownOrSearched) {
  Ball b;
  // Given: as is, no margin, no search.
  {
    MeshOptions o;
    o.bounds = kCube;
    MeshControl control(o);
    MeshStats st;
    const MeshRegion r = find_region(b.tape, o, control, st);
    EXPECT_FALSE(r.empty);
    EXPECT_FALSE(r.found());
    EXPECT_EQ(r.margin, 0);
    EXPECT_EQ(r.box.lo, kCube.lo);
    EXPECT_EQ(r.box.hi, kCube.hi);
    EXPECT_FALSE(st.bounds_found || st.bounds_known);
  }
  // Known: as is, with a margin.
  {
    MeshOptions o;
    o.known_bounds = Box3{{-0.5, -0.6, -0.7}, {0.7, 0.6, 0.5}};
    MeshControl control(o);
    MeshStats st;
    const MeshRegion r = find_region(b.tape, o, control, st);
    EXPECT_TRUE(r.found());
    EXPECT_EQ(r.box.lo, o.known_bounds.lo);
    EXPECT_EQ(st.found.hi, o.known_bounds.hi);
    EXPECT_TRUE(st.bounds_known);
    EXPECT_FALSE(st.bounds_found);
  }
  // Searched: around the ball, reported as the "bounds" phase.
  {
    MeshOptions o;
    std::vector<std::string> phases;
    o.progress = [&](const MeshProgress& p) { phases.push_back(p.phase); };
    MeshControl control(o);
    MeshStats st;
    const MeshRegion r = find_region(b.tape, o, control, st);
    ASSERT_FALSE(r.empty);
    EXPECT_TRUE(r.found());
    EXPECT_TRUE(st.bounds_found);
    EXPECT_GT(st.search_rounds, 0);
    const Vec3 c{0.1, 0, -0.05};
    for (int a = 0; a < 3; ++a) {
      EXPECT_LE(r.box.lo[a], c[a] - 0.6);
      EXPECT_GE(r.box.hi[a], c[a] + 0.6);
    }
    EXPECT_EQ(st.found.lo, r.box.lo);
    EXPECT_EQ(phases, std::vector<std::string>{"bounds"});
  }
  // Nothing inside.
  {
    Graph g;
    const Expr none = sqrt(square(g.x()) + square(g.y()) + square(g.z())) + 1.0f;
    MeshOptions o;
    MeshControl control(o);
    MeshStats st;
    EXPECT_TRUE(find_region(Tape::compile(g, none.id()), o, control, st).empty);
  }
}

TEST(MesherSteps, CellEdgeFromResolutionOrCellSize) {
  MeshOptions o;
  o.resolution = 40;
  const Box3 region{{0, 0, 0}, {2, 4, 1}};
  EXPECT_DOUBLE_EQ(cell_edge(region, o), 4.0 / 40);
  o.cell_size = 0.3;
  EXPECT_DOUBLE_EQ(cell_edge(region, o), 0.3);
  o.cell_size = 0;
  EXPECT_THROW(cell_edge(Box3{{1, 1, 1}, {1, 1, 1}}, o), InputError);
}

TEST(MesherSteps, CutLipschitzIsTheBoxsAtLeast) {
  EXPECT_EQ(cut_lipschitz(0), 0) << "unknown stays unknown";
  EXPECT_EQ(cut_lipschitz(0.25), 1);
  EXPECT_EQ(cut_lipschitz(1), 1);
  EXPECT_EQ(cut_lipschitz(3), 3);
}

TEST(MesherSteps, CutBoxIsInsideTheGridInFloats) {
  const Box3 region{{-0.3, -0.71, 0.1}, {0.9, 0.2, 0.35}};
  for (double shift : {0.0, 0.37}) {
    const MeshGrid grid = make_grid(region, 0.05, shift != 0 ? 1 : 0, shift);
    // Given: the region itself, to f32.
    const Box3 given = cut_box(grid, region, false);
    // Found: the grid's box.
    const Box3 found = cut_box(grid, region, true);
    for (int a = 0; a < 3; ++a) {
      EXPECT_TRUE(is_f32(given.lo[a]) && is_f32(given.hi[a]));
      EXPECT_GE(given.lo[a], grid.box.lo[a]);
      EXPECT_LE(given.hi[a], grid.box.hi[a]);
      EXPECT_NEAR(given.lo[a], region.lo[a], 1e-7);
      EXPECT_NEAR(given.hi[a], region.hi[a], 1e-7);
      EXPECT_EQ(found.lo[a], grid.box.lo[a]);
      EXPECT_EQ(found.hi[a], grid.box.hi[a]);
    }
  }
}

TEST(MesherSteps, TilesFromOptionsOrTheGrid) {
  const MeshGrid grid = make_grid(Box3{{0, 0, 0}, {1, 3, 2}}, 0.01, 1);  // 302 cells along y
  MeshOptions o;
  EXPECT_EQ(tiles_for(o, grid, 0), default_tiles(302, 4));
  EXPECT_EQ(tiles_for(o, grid, 1), default_tiles(302, 2)) << "halving with a Lipschitz bound";
  o.tiles = {16, 4};
  EXPECT_EQ(tiles_for(o, grid, 1), o.tiles);
}

TEST(MesherSteps, SubdividerIsKeptWhileItFits) {
  std::unique_ptr<Subdivider> sub;
  Subdivider* first = &subdivider_for(sub, {32, 8}, 2, 0);
  EXPECT_EQ(first, sub.get());
  EXPECT_EQ(&subdivider_for(sub, {32, 8}, 2, 0), first);
  EXPECT_EQ(subdivider_for(sub, {16, 8}, 2, 0).options().tiles, (std::vector<int>{16, 8}));
  EXPECT_EQ(subdivider_for(sub, {16, 8}, 2, 1).options().lipschitz, 1);
}

// Cells of the grid whose corners differ in sign (inside: f < 0), by evaluating every corner.
std::size_t cells_with_sign_changes(const Tape& tape, const MeshGrid& grid) {
  PointEvaluator pe;
  const int nx = grid.n[0] + 1, ny = grid.n[1] + 1, nz = grid.n[2] + 1;
  std::vector<char> in(static_cast<std::size_t>(nx) * ny * nz);
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x)
        in[static_cast<std::size_t>(x + nx * (y + ny * z))] =
            pe.eval(tape, static_cast<float>(grid.coord(0, x)), static_cast<float>(grid.coord(1, y)),
                    static_cast<float>(grid.coord(2, z))) < 0;
  std::size_t count = 0;
  for (int z = 0; z < grid.n[2]; ++z)
    for (int y = 0; y < grid.n[1]; ++y)
      for (int x = 0; x < grid.n[0]; ++x) {
        int inside = 0;
        for (int c = 0; c < 8; ++c)
          inside += in[static_cast<std::size_t>((x + (c & 1)) + nx * ((y + ((c >> 1) & 1)) + ny * (z + (c >> 2))))];
        count += inside > 0 && inside < 8;
      }
  return count;
}

TEST(MesherSteps, LeavesHoldEveryCellWithASignChange) {
  Ball b;
  MeshOptions o;
  o.threads = 2;
  const MeshGrid grid = make_grid(kCube, 2.0 / 30, 0);
  const Box3 cut = cut_box(grid, kCube, false);
  const Tape closed = close_at_box(b.tape, cut);
  std::unique_ptr<Subdivider> sub;
  for (const std::vector<int>& tiles : std::vector<std::vector<int>>{{16, 4}, {8}}) {
    SCOPED_TRACE(::testing::PrintToString(tiles));
    std::vector<double> cells_reported;
    o.progress = [&](const MeshProgress& p) {
      if (std::string(p.phase) == "cells") cells_reported.push_back(p.fraction);
    };
    MeshControl control(o);
    Subdivider& s = subdivider_for(sub, tiles, o.threads, 0);
    const Leaves leaves = build_leaves(s, closed, grid, cut, o, control, true);
    EXPECT_EQ(leaves.zero_corners, 0u);
    ASSERT_FALSE(cells_reported.empty());
    EXPECT_EQ(cells_reported.back(), 1.0);
    const std::vector<LeafRecord*> ordered = leaves.in_key_order();
    ASSERT_GT(ordered.size(), 1u);
    std::size_t cells = 0;
    std::set<std::uint64_t> keys;
    for (std::size_t i = 0; i < ordered.size(); ++i) {
      EXPECT_EQ(ordered[i]->key, leaf_key(ordered[i]->box.lo, tiles.back()));
      EXPECT_TRUE(keys.insert(ordered[i]->key).second) << "one record per leaf";
      if (i > 0) {
        EXPECT_LT(ordered[i - 1]->key, ordered[i]->key);
      }
      EXPECT_FALSE(ordered[i]->cells.empty());
      cells += ordered[i]->cells.size();
    }
    EXPECT_EQ(cells, cells_with_sign_changes(closed, grid));
    // Not reporting: no progress.
    cells_reported.clear();
    build_leaves(s, closed, grid, cut, o, control, false);
    EXPECT_TRUE(cells_reported.empty());
  }
}

TEST(MesherSteps, LeavesCountCornersOnTheSurfaceAndStopWhenCancelled) {
  Graph g;
  const Expr x = g.x(), y = g.y(), z = g.z();
  const Expr on_planes = max(max(abs(x) - 0.5f, abs(y) - 0.25f), abs(z) - 0.5f);  // faces on corners
  MeshOptions o;
  o.threads = 2;
  const MeshGrid grid = make_grid(kCube, 2.0 / 16, 0);
  const Box3 cut = cut_box(grid, kCube, false);
  const Tape closed = close_at_box(Tape::compile(g, on_planes.id()), cut);
  std::unique_ptr<Subdivider> sub;
  Subdivider& s = subdivider_for(sub, {8}, o.threads, 0);
  MeshControl control(o);
  EXPECT_GT(build_leaves(s, closed, grid, cut, o, control, false).zero_corners, 0u);
  std::atomic<bool> stop{true};
  o.cancel = &stop;
  MeshControl cancelled(o);
  EXPECT_THROW(build_leaves(s, closed, grid, cut, o, cancelled, false), MeshCancelled);
}

TEST(MesherSteps, GridPassesMeshShiftedGridsReportingOnce) {
  Ball b;
  MeshOptions o;
  o.resolution = 20;
  o.threads = 2;
  o.bounds = kCube;
  int reports = 0;
  o.progress = [&](const MeshProgress& p) { reports += std::string(p.phase) == "cells"; };
  MeshControl control(o);
  MeshStats st;
  const MeshRegion region = find_region(b.tape, o, control, st);
  std::unique_ptr<Subdivider> sub;
  GridPasses passes(b.tape, o, region, sub, control, st);
  const PassResult first = passes.run(0);
  EXPECT_EQ(st.cells, (std::array<int, 3>{20, 20, 20}));
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(st.bounds.lo[a], kCube.lo[a], 1e-6);
    EXPECT_NEAR(st.bounds.hi[a], kCube.hi[a], 1e-6);
  }
  EXPECT_DOUBLE_EQ(st.cell_size, 0.1);
  EXPECT_EQ(st.triangles, first.mesh.triangles.size());
  EXPECT_EQ(st.vertices, first.mesh.vertices.size());
  EXPECT_GT(st.leaves, 0u);
  EXPECT_GT(st.surface_cells, 0u);
  EXPECT_EQ(first.zero_corners, 0u);
  const int first_reports = reports;
  EXPECT_GT(first_reports, 0);
  // Moved by part of a cell: a cell more on every side to cover the bounds, the same cell edge.
  const PassResult moved = passes.run(0.37);
  EXPECT_EQ(st.cells, (std::array<int, 3>{22, 22, 22}));
  EXPECT_DOUBLE_EQ(st.cell_size, 0.1);
  for (int a = 0; a < 3; ++a) {
    EXPECT_LT(st.bounds.lo[a], kCube.lo[a]);
    EXPECT_GT(st.bounds.hi[a], kCube.hi[a]);
  }
  EXPECT_EQ(st.triangles, moved.mesh.triangles.size());
  EXPECT_NE(moved.mesh.vertices, first.mesh.vertices);
  EXPECT_EQ(reports, first_reports) << "progress comes from the first pass only";
}

// A stand-in for a pass: a one-vertex mesh at x = shift, and the stats a real pass would set.
struct FakePasses {
  MeshStats& st;
  std::map<double, std::size_t> unresolved;   // per shift
  std::map<double, std::uint64_t> zeros;      // per shift
  std::set<double> fail;                      // shifts that throw InputError
  std::vector<double> shifts;                 // asked for, in order

  PassResult operator()(double shift) {
    shifts.push_back(shift);
    if (fail.count(shift)) throw InputError("", 0, "a cell too many");
    st.unresolved = unresolved[shift];
    st.cells = {static_cast<int>(shifts.size()), 0, 0};
    st.seconds_cells += 1;
    PassResult r;
    r.mesh.vertices.push_back(Vec3{shift, 0, 0});
    r.zero_corners = zeros[shift];
    return r;
  }
};

TEST(MesherSteps, FirstMeshMovesOffCornersOnTheSurface) {
  for (bool found : {false, true}) {
    MeshStats st;
    FakePasses f{st, {}, {}, {}, {}};
    TriMesh m = first_mesh(std::ref(f), found, st);
    ASSERT_EQ(f.shifts.size(), 1u);
    EXPECT_EQ(f.shifts[0] != 0, found) << "only a found region's grid starts moved";
    EXPECT_FALSE(st.shifted);
    // Corners on the surface: once more, elsewhere.
    MeshStats st2;
    FakePasses z{st2, {}, {{f.shifts[0], 12}}, {}, {}};
    m = first_mesh(std::ref(z), found, st2);
    ASSERT_EQ(z.shifts.size(), 2u);
    EXPECT_NE(z.shifts[1], z.shifts[0]);
    EXPECT_EQ(m.vertices[0].x, z.shifts[1]);
    EXPECT_TRUE(st2.shifted);
    EXPECT_EQ(st2.zero_corners, 12u);
  }
}

TEST(MesherSteps, RetriesKeepTheLeastTangledMesh) {
  auto mesh_at = [](double x) {
    TriMesh m;
    m.vertices.push_back(Vec3{x, 0, 0});
    return m;
  };
  auto never = [] { return false; };
  // Nothing unresolved: no retry.
  {
    MeshStats st;
    FakePasses f{st, {}, {}, {}, {}};
    EXPECT_EQ(retry_while_unresolved(mesh_at(0), std::ref(f), never, st).vertices[0].x, 0);
    EXPECT_TRUE(f.shifts.empty());
  }
  // Better, then worse: the better kept, with its figures and the time of both passes.
  {
    MeshStats st;
    st.unresolved = 5;
    FakePasses f{st, {{0.37, 3}, {0.71, 4}}, {}, {}, {}};
    const TriMesh m = retry_while_unresolved(mesh_at(0), std::ref(f), never, st);
    EXPECT_EQ(f.shifts.size(), 2u);
    EXPECT_EQ(m.vertices[0].x, 0.37);
    EXPECT_EQ(st.unresolved, 3u);
    EXPECT_EQ(st.unresolved_first, 5u);
    EXPECT_TRUE(st.shifted);
    EXPECT_EQ(st.cells[0], 1) << "the kept pass's figures";
    EXPECT_EQ(st.seconds_cells, 2);
  }
  // Untangled on the first retry: no second.
  {
    MeshStats st;
    st.unresolved = 5;
    FakePasses f{st, {{0.37, 0}}, {}, {}, {}};
    EXPECT_EQ(retry_while_unresolved(mesh_at(0), std::ref(f), never, st).vertices[0].x, 0.37);
    EXPECT_EQ(f.shifts.size(), 1u);
    EXPECT_EQ(st.unresolved, 0u);
  }
  // Never better: the first mesh and its figures.
  {
    MeshStats st;
    st.unresolved = 5;
    FakePasses f{st, {{0.37, 5}, {0.71, 9}}, {}, {}, {}};
    EXPECT_EQ(retry_while_unresolved(mesh_at(0), std::ref(f), never, st).vertices[0].x, 0);
    EXPECT_EQ(st.unresolved, 5u);
    EXPECT_EQ(st.cells[0], 0);
    EXPECT_FALSE(st.shifted);
    EXPECT_EQ(st.seconds_cells, 2);
  }
  // A grid that cannot be made ends the retries.
  {
    MeshStats st;
    st.unresolved = 5;
    FakePasses f{st, {{0.71, 0}}, {}, {0.37}, {}};
    EXPECT_EQ(retry_while_unresolved(mesh_at(0), std::ref(f), never, st).vertices[0].x, 0);
    EXPECT_EQ(f.shifts.size(), 1u);
    EXPECT_EQ(st.unresolved, 5u);
  }
  // Cancelled between passes.
  {
    MeshStats st;
    st.unresolved = 5;
    FakePasses f{st, {}, {}, {}, {}};
    EXPECT_THROW(retry_while_unresolved(mesh_at(0), std::ref(f), [] { return true; }, st), MeshCancelled);
    EXPECT_TRUE(f.shifts.empty());
  }
}

}  // namespace
}  // namespace frep::contour

namespace frep::contour {
namespace {

// The pilot's estimate of surface cells against the real count on a grid just past the pilot
// threshold (cheap enough to mesh here): a sphere and a box, within 15%.
TEST(MesherMemory, PilotEstimatesTheSurfaceCells) {
  for (int shape = 0; shape < 2; ++shape) {
    Graph g;
    const Expr x = g.x(), y = g.y(), z = g.z();
    const Expr f = shape == 0 ? sqrt(square(x) + square(y) + square(z)) - 1.0f
                              : max(max(abs(x) - 0.9f, abs(y) - 0.5f), abs(z) - 0.7f);
    const Tape tape = Tape::compile(g, f.id());
    MeshOptions o;
    o.resolution = kPilotAbove + 88;
    o.bounds = Box3{{-1.1, -1.1, -1.1}, {1.1, 1.1, 1.1}};
    MeshRegion region;
    region.box = o.bounds;
    const std::uint64_t estimate = estimate_surface_cells(tape, o, region, cell_edge(region.box, o));
    MeshStats st;
    mesh_expression(tape, o, &st);
    ASSERT_GT(st.surface_cells, 0u);
    EXPECT_NEAR(static_cast<double>(estimate) / static_cast<double>(st.surface_cells), 1.0, 0.15) << "shape " << shape;
    // At or below the threshold no pilot runs.
    o.resolution = kPilotAbove;
    EXPECT_EQ(estimate_surface_cells(tape, o, region, cell_edge(region.box, o)), 0u);
  }
}

// A grid whose estimate exceeds the machine's memory is refused at once, naming the estimate,
// instead of being killed for lack of memory. The cube at 4096 cells across (allowed) needs about
// 100 million surface cells.
TEST(MesherMemory, GridsBeyondMemoryAreRefusedBeforeTheWork) {
  Graph g;
  const Expr x = g.x(), y = g.y(), z = g.z();
  const Expr f = max(max(abs(x) - 1.0f, abs(y) - 1.0f), abs(z) - 1.0f);
  const Tape tape = Tape::compile(g, f.id());
  MeshOptions o;
  o.resolution = kMaxMeshResolution;
  o.known_bounds = Box3{{-1, -1, -1}, {1, 1, 1}};
  MeshRegion region;
  region.box = o.known_bounds;
  region.margin = 1;
  const std::uint64_t estimate = estimate_surface_cells(tape, o, region, cell_edge(region.box, o));
  EXPECT_NEAR(static_cast<double>(estimate), 6.0 * kMaxMeshResolution * kMaxMeshResolution, 0.2 * 6.0 * kMaxMeshResolution * kMaxMeshResolution);
  if (physical_memory_bytes() > estimate * kBytesPerSurfaceCell)
    GTEST_SKIP() << "this machine has the memory for it: the refusal is not reached";
  try {
    mesh_expression(tape, o);
    FAIL() << "meshed a grid beyond the machine's memory";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("GB of memory"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace frep::contour
