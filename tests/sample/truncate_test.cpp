// Tests of truncated grids (MeshGridOptions::truncate, ExprGridOptions::truncate): a grid
// truncated at D must equal the untruncated grid clamped to [-D, D], bit for bit, whatever D
// (below a voxel, a few voxels, wide enough for the reach walk, beyond every distance), whatever
// the bounds (around the mesh, cutting it, far from it, inside it) and the thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>

#include "frep/error.hpp"
#include "frep/expr/expr.hpp"
#include "frep/mesh/mesh_field.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/sample/grid.hpp"
#include "mesh_test_util.hpp"

namespace frep {
namespace {

// The reference: clamp(v, -D, D) of an untruncated value, in double, rounded once (for float
// grids this is also the clamp of the float value to [-D, D]: rounding is monotonic).
template <class T>
T clamped(T v, double d) {
  return static_cast<T>(std::clamp(static_cast<double>(v), -d, d));
}

template <class T>
std::uint64_t bits(T v) {
  if constexpr (sizeof(T) == 4) return std::bit_cast<std::uint32_t>(v);
  else return std::bit_cast<std::uint64_t>(v);
}

template <class T>
void expect_clamp_of(const std::vector<T>& full, const std::vector<T>& cut, const GridSpec& grid, double d,
                     const std::string& what) {
  ASSERT_EQ(full.size(), grid.size()) << what;
  ASSERT_EQ(cut.size(), grid.size()) << what;
  std::size_t bad = 0;
  for (int i = 0; i < grid.counts[0]; ++i)
    for (int j = 0; j < grid.counts[1]; ++j)
      for (int k = 0; k < grid.counts[2]; ++k) {
        const std::size_t at = grid.index(i, j, k);
        const T want = clamped(full[at], d);
        if (bits(want) != bits(cut[at]) && bad++ < 5)
          ADD_FAILURE() << what << ": sample (" << i << ", " << j << ", " << k << ") = " << cut[at] << ", want "
                        << want << " (untruncated " << full[at] << ")";
      }
  EXPECT_EQ(bad, 0u) << what;
}

double voxel(const GridSpec& g) {
  double h = 0;
  for (int a = 0; a < 3; ++a) h = std::max(h, (g.bounds.hi[a] - g.bounds.lo[a]) / (g.counts[a] - 1));
  return h;
}

// Truncated at D (in voxels) on 1 and 2 threads, in float and double, against the untruncated
// grid (which equals the oracle: sample_test.cpp). Returns the stats of the float run.
MeshGridStats check_mesh(const MeshField& field, const GridSpec& grid, double voxels, const std::string& name) {
  const double d = voxels * voxel(grid);
  const std::string what = name + ", D = " + std::to_string(voxels) + " voxels";
  const std::vector<float> full = sample_grid(field, grid);
  MeshGridStats st;
  std::vector<float> first;
  for (int threads : {1, 2}) {
    MeshGridOptions o;
    o.threads = threads;
    o.truncate = d;
    MeshGridStats s;
    std::vector<float> cut = sample_grid(field, grid, o, &s);
    expect_clamp_of(full, cut, grid, d, what + ", " + std::to_string(threads) + " threads");
    if (threads == 1) {
      first = std::move(cut);
      st = s;
    } else {
      EXPECT_TRUE(std::equal(first.begin(), first.end(), cut.begin(), cut.end(),
                             [](float a, float b) { return bits(a) == bits(b); }))
          << what << ": thread counts disagree";
    }
  }
  // In double precision the transform and the oracle queries differ in the last bits (they
  // agree once rounded to float): bit for bit when both grids come from the same method (bounds
  // that contain the mesh), else within 1e-14 of the grid's size.
  MeshGridOptions o;
  o.truncate = d;
  MeshGridStats full_st, cut_st;
  const std::vector<double> full64 = sample_grid_f64(field, grid, {}, &full_st);
  const std::vector<double> cut64 = sample_grid_f64(field, grid, o, &cut_st);
  if (full_st.method == cut_st.method) {
    expect_clamp_of(full64, cut64, grid, d, what + ", double");
  } else {
    const double tol = 1e-14 * length(grid.bounds.size());
    std::size_t bad = 0;
    for (std::size_t i = 0; i < grid.size(); ++i)
      if (!(std::fabs(clamped(full64[i], d) - cut64[i]) <= tol) && bad++ < 5)
        ADD_FAILURE() << what << ", double: sample " << i << " = " << cut64[i] << ", want " << clamped(full64[i], d);
    EXPECT_EQ(bad, 0u) << what << ", double";
  }
  return st;
}

const double kVoxels[] = {0.3, 1, 3, 7.5, 30, 1e6};

TEST(TruncatedGrid, GeneratedMeshes) {
  struct Case {
    const char* name;
    TriMesh mesh;
    int n;
  };
  const Case cases[] = {{"box", test::make_box(), 21},
                        {"fine box", test::make_fine_box(5, {-1, -0.5, -0.7}, {0.9, 0.6, 0.8}), 26},
                        {"sphere", test::make_sphere(2, 0.8), 29}};
  for (const Case& c : cases) {
    const MeshField field(c.mesh);
    ASSERT_TRUE(field.solid()) << c.name << ": " << field.summary();
    // A grid that is not a cube, not centred, with voxels of different sizes per axis.
    const Box3 mb = field.box();
    const GridSpec grid{{mb.lo - Vec3{0.31, 0.12, 0.2}, mb.hi + Vec3{0.07, 0.4, 0.13}}, {c.n, c.n + 5, c.n - 3}};
    for (double v : kVoxels) {
      const MeshGridStats st = check_mesh(field, grid, v, c.name);
      EXPECT_EQ(st.method, MeshGridMethod::Cpt) << c.name;
      EXPECT_EQ(st.side_queries, 0u) << c.name;
      EXPECT_EQ(st.fallback_samples, 0u) << c.name;
      if (v <= 1) {
        EXPECT_LT(st.band_samples, grid.size() / 2) << c.name << " " << v;
      }
    }
  }
}

// Bounds that cut the mesh: narrow bands still run the transform (features outside the grid
// scan into it); wide ones query the oracle at every sample and clamp.
TEST(TruncatedGrid, BoundsThatCutTheMesh) {
  const MeshField field(test::make_sphere(2, 1.0));
  const GridSpec grid{{{-0.2, -1.3, 0.1}, {1.4, 0.45, 0.75}}, {27, 30, 17}};
  for (double v : kVoxels) {
    const MeshGridStats st = check_mesh(field, grid, v, "cut sphere");
    EXPECT_EQ(st.method, v <= 32 ? MeshGridMethod::Cpt : MeshGridMethod::Queries) << v;
  }
  // Asking for the transform with a wide band and such bounds is refused.
  MeshGridOptions o;
  o.method = MeshGridMethod::Cpt;
  o.truncate = 33 * voxel(grid);
  EXPECT_THROW(sample_grid(field, grid, o), InputError);
}

// Bands wider than kScanBandVoxels use the reach walk, capped at the band: a grid far larger than
// the mesh, so that its corners lie beyond such a band.
TEST(TruncatedGrid, WideBandsWalk) {
  const MeshField field(test::make_sphere(2, 0.5));
  const GridSpec grid = cube_grid({{-2, -2, -2}, {2, 2, 2}}, 61);
  const MeshGridStats st = check_mesh(field, grid, 40, "wide band");
  EXPECT_EQ(st.method, MeshGridMethod::Cpt);
  EXPECT_LT(st.band_samples, grid.size());
}

// A grid the surface misses: all +D outside the mesh, all -D inside it, from one oracle query.
TEST(TruncatedGrid, GridsTheSurfaceMisses) {
  const MeshField field(test::make_fine_box(3, {-2, -2, -2}, {2, 2, 2}));
  for (const Box3& b : {Box3{{3, 2.5, -1}, {5, 4, 1}}, Box3{{-1, -0.5, -1.2}, {0.8, 1, 1.1}}}) {
    const GridSpec grid{b, {9, 11, 8}};
    const bool inside = b.hi.x < 2;
    for (double v : {0.5, 2.0}) {
      const MeshGridStats st = check_mesh(field, grid, v, inside ? "inside" : "outside");
      EXPECT_EQ(st.method, MeshGridMethod::Cpt);
      EXPECT_EQ(st.band_samples, 0u);
      EXPECT_EQ(st.side_queries, 1u);
    }
    MeshGridOptions o;
    o.truncate = 0.25;
    for (float x : sample_grid(field, grid, o)) ASSERT_EQ(x, inside ? -0.25f : 0.25f);
  }
}

TEST(TruncatedGrid, SharedMeshes) {
  FREP_REQUIRE_SHARED_MESHES();
  for (const char* name : {"spot.obj", "fandisk.obj"}) {
    const std::string path = test::shared_mesh_dir() + "/" + name;
    const MeshField field(read_mesh(path));
    ASSERT_TRUE(field.solid()) << name << ": " << field.summary();
    const GridSpec grid = cube_grid(default_mesh_bounds(field.box()), 40);
    for (double v : {0.5, 1.0, 3.0, 16.0}) {
      const MeshGridStats st = check_mesh(field, grid, v, name);
      EXPECT_EQ(st.method, MeshGridMethod::Cpt) << name;
      EXPECT_EQ(st.side_queries, 0u) << name;
    }
    // Bounds through the middle of the part.
    const Box3 mb = field.box();
    const GridSpec cut{{mb.lo + mb.size() * 0.3, mb.hi + mb.size() * 0.05}, {31, 28, 33}};
    check_mesh(field, cut, 2.0, std::string(name) + ", cut");
  }
}

// A mesh that is not a valid solid (winding-number signs): every sample is queried and clamped.
TEST(TruncatedGrid, NonSolidsAreQueriedAndClamped) {
  TriMesh open = test::make_fine_box(2);
  open.triangles.pop_back();
  if (open.has_origins()) open.origins.pop_back();
  const MeshField field(open);
  ASSERT_FALSE(field.solid());
  const GridSpec grid = cube_grid(default_mesh_bounds(field.box()), 14);
  const MeshGridStats st = check_mesh(field, grid, 2, "open box");
  EXPECT_EQ(st.method, MeshGridMethod::Queries);
}

TEST(TruncatedGrid, BadDistancesAreRefused) {
  const MeshField field(test::make_box());
  const GridSpec grid = cube_grid(default_mesh_bounds(field.box()), 5);
  for (double d : {-1.0, double(NAN), double(INFINITY)}) {
    MeshGridOptions o;
    o.truncate = d;
    EXPECT_THROW(sample_grid(field, grid, o), InputError) << d;
    ExprGridOptions e;
    e.truncate = d;
    Graph g;
    EXPECT_THROW(sample_grid(Tape::compile(g, (g.x() - 0.5f).id()), grid, e), InputError) << d;
  }
}

// Expressions: the clamp of the untruncated grid, with and without a Lipschitz bound (boxes
// beyond +-D are then settled from their centre's value).
TEST(TruncatedGrid, Expressions) {
  Graph g;
  const Expr x = g.x(), y = g.y(), z = g.z();
  const Expr ball = sqrt(square(x - 0.1f) + square(y + 0.05f) + square(z)) - 0.55f;
  const Expr box = max(max(abs(x) - 0.4f, abs(y - 0.2f) - 0.3f), abs(z) - 0.5f);
  const GridSpec grid{{{-1, -0.9, -1.1}, {1.05, 1, 0.95}}, {41, 37, 45}};
  for (const Expr& e : {ball, min(ball, box)}) {
    const Tape tape = Tape::compile(g, e.id());
    ExprGridOptions base;
    base.tiles = {16, 4};
    const std::vector<float> full = sample_grid(tape, grid, base);
    for (double v : {0.4, 2.0, 5.0}) {
      for (double lipschitz : {0.0, 1.0}) {
        for (int threads : {1, 2}) {
          ExprGridOptions o = base;
          o.truncate = v * voxel(grid);
          o.lipschitz = lipschitz;
          o.threads = threads;
          expect_clamp_of(full, sample_grid(tape, grid, o), grid, o.truncate,
                          "expression, D = " + std::to_string(v) + " voxels, L = " + std::to_string(lipschitz));
        }
      }
    }
  }
}

}  // namespace
}  // namespace frep
