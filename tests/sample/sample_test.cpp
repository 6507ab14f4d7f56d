// Tests of the samplers behind `frep sample`: grids from meshes against an independent brute-force
// signed distance (tests/brute_force_sdf.hpp: every triangle's distance, winding-number sign) at
// every sample of small meshes, with both grid methods and both sign methods, and against
// MeshDistance on the shared meshes; grids from expressions against the point evaluator; point
// samples (uniform and near the surface, whose signed distances must follow the requested
// Gaussian) against the brute-force distance; the .npy layout byte by byte against NumPy's format
// description.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <algorithm>
#include <cstring>

#include "frep/convert/convert.hpp"
#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/expr/expr.hpp"
#include "frep/io/npy.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/sample/grid.hpp"
#include "frep/mesh/mesh_field.hpp"
#include "frep/sample/points.hpp"
#include "brute_force_sdf.hpp"
#include "mesh_test_util.hpp"

namespace frep {
namespace {

const std::string kBracket = FREP_SOURCE_DIR "/examples/bracket.obj";

// Every sample of `grid` equals the oracle at that sample's coordinates, rounded once to float.
void expect_grid_matches_oracle(const MeshField& field, const GridSpec& grid, const std::vector<float>& v,
                                const std::string& what) {
  ASSERT_EQ(v.size(), grid.size());
  std::size_t bad = 0;
  for (int i = 0; i < grid.counts[0]; ++i)
    for (int j = 0; j < grid.counts[1]; ++j)
      for (int k = 0; k < grid.counts[2]; ++k) {
        const Vec3 p{grid.coord(0, i), grid.coord(1, j), grid.coord(2, k)};
        const float want = static_cast<float>(field.signed_distance(p));
        const float got = v[grid.index(i, j, k)];
        if (std::bit_cast<std::uint32_t>(want) != std::bit_cast<std::uint32_t>(got) && bad++ < 5)
          ADD_FAILURE() << what << ": sample (" << i << ", " << j << ", " << k << ") = " << got << ", oracle " << want;
      }
  EXPECT_EQ(bad, 0u) << what;
}

// Every sample of `grid` is the brute-force signed distance of `mesh` at that sample's
// coordinates, rounded to float. Where the winding number is within 1e-3 of 1/2 (only beside an
// open mesh's hole, where MeshDistance's far-field approximation may decide it either way), either
// sign is accepted.
void expect_grid_matches_brute_force(const TriMesh& mesh, const GridSpec& grid, const std::vector<float>& v,
                                     const std::string& what) {
  ASSERT_EQ(v.size(), grid.size());
  const test::BruteForceSdf bf{mesh};
  const double slack = 1e-12 * length(bounding_box(mesh).size());
  std::size_t bad = 0, ambiguous = 0;
  for (int i = 0; i < grid.counts[0]; ++i)
    for (int j = 0; j < grid.counts[1]; ++j)
      for (int k = 0; k < grid.counts[2]; ++k) {
        const Vec3 p{grid.coord(0, i), grid.coord(1, j), grid.coord(2, k)};
        const double d = bf.unsigned_distance(p), w = bf.winding_number(p);
        const float got = v[grid.index(i, j, k)];
        const bool either = std::fabs(w - 0.5) < 1e-3;
        ambiguous += either;
        const bool ok = test::bf_float_matches(got, w > 0.5 ? -d : d, slack) ||
                        (either && test::bf_float_matches(got, w > 0.5 ? d : -d, slack));
        if (!ok && bad++ < 5)
          ADD_FAILURE() << what << ": sample (" << i << ", " << j << ", " << k << ") = " << got << ", brute force "
                        << (w > 0.5 ? -d : d) << " (winding number " << w << ")";
      }
  EXPECT_EQ(bad, 0u) << what;
  EXPECT_LT(ambiguous, grid.size() / 100) << what;
}

TEST(SampleGrid, Layout) {
  const GridSpec g{{{-1, 0, 2}, {3, 1, 2.5}}, {5, 3, 2}};
  EXPECT_EQ(g.coord(0, 0), -1);
  EXPECT_EQ(g.coord(0, 4), 3);
  EXPECT_EQ(g.coord(0, 1), 0);
  EXPECT_EQ(g.coord(1, 1), 0.5);
  EXPECT_EQ(g.coord(2, 1), 2.5);
  EXPECT_EQ(g.index(0, 0, 1), 1u);   // z fastest
  EXPECT_EQ(g.index(0, 1, 0), 2u);
  EXPECT_EQ(g.index(1, 0, 0), 6u);
  EXPECT_EQ(g.size(), 30u);
  EXPECT_THROW((GridSpec{{{0, 0, 0}, {1, 1, 1}}, {1, 2, 2}}.check()), InputError);
  EXPECT_THROW((GridSpec{{{0, 0, 0}, {0, 1, 1}}, {2, 2, 2}}.check()), InputError);
  // Default mesh bounds: a cube holding the box with 5% of its diagonal to spare on its longest axis.
  const Box3 box{{0, 0, 0}, {4, 2, 1}};
  const Box3 b = default_mesh_bounds(box);
  const double m = 0.05 * std::sqrt(21.0);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(b.hi[a] - b.lo[a], 4 + 2 * m, 1e-12);
    EXPECT_LE(b.lo[a], box.lo[a] - m + 1e-12);
    EXPECT_GE(b.hi[a], box.hi[a] + m - 1e-12);
  }
}

// Both methods, with either sign method, equal the brute-force signed distance at every sample,
// on grids that are not cubes and not centred, over the bracket and a sphere (curved: every
// sample's closest feature differs).
TEST(SampleGrid, MeshGridIsTheBruteForceDistance) {
  const TriMesh bracket = read_mesh(kBracket), sphere = test::make_sphere(2, 0.8);
  for (const TriMesh* mesh : {&bracket, &sphere}) {
    for (SignMethod sign : {SignMethod::Pseudonormal, SignMethod::WindingNumber}) {
      MeshFieldOptions fo;
      fo.sign = sign;
      const MeshField field(*mesh, fo);
      ASSERT_TRUE(field.solid()) << field.summary();
      const Box3 mb = field.box();
      const GridSpec grid{{mb.lo - Vec3{0.1, 0.05, 0.2}, mb.hi + Vec3{0.07, 0.3, 0.01}}, {23, 19, 29}};
      for (MeshGridMethod method : {MeshGridMethod::Cpt, MeshGridMethod::Queries}) {
        if (method == MeshGridMethod::Cpt && sign != SignMethod::Pseudonormal) continue;  // Cpt needs pseudonormals
        MeshGridOptions o;
        o.method = method;
        MeshGridStats st;
        const std::vector<float> v = sample_grid(field, grid, o, &st);
        EXPECT_EQ(st.method, method);
        const std::string what = std::string(mesh == &bracket ? "bracket, " : "sphere, ") +
                                 (method == MeshGridMethod::Cpt ? "cpt" : "queries") +
                                 (sign == SignMethod::Pseudonormal ? ", pseudonormal" : ", winding");
        expect_grid_matches_brute_force(*mesh, grid, v, what);
        // Both signs occur: the grid goes through the solid.
        EXPECT_LT(*std::min_element(v.begin(), v.end()), 0) << what;
        EXPECT_GT(*std::max_element(v.begin(), v.end()), 0) << what;
      }
    }
  }
}

TEST(SampleGrid, SharedMeshesMatchTheOracle) {
  FREP_REQUIRE_SHARED_MESHES();
  for (const char* name : {"fandisk.obj", "sphere_icosa_1280.stl", "tray_bottom_ascii.stl"}) {
    const MeshField field(read_mesh(test::shared_mesh_dir() + "/" + name));
    ASSERT_TRUE(field.solid()) << name << ": " << field.summary();
    const GridSpec grid = cube_grid(default_mesh_bounds(field.box()), 33);
    MeshGridStats st;
    const std::vector<float> v = sample_grid(field, grid, {}, &st);
    EXPECT_EQ(st.method, MeshGridMethod::Cpt) << name;
    EXPECT_EQ(st.fallback_samples, 0u) << name;
    expect_grid_matches_oracle(field, grid, v, name);
  }
}

TEST(SampleGrid, CptRefusesNonSolids) {
  TriMesh open = test::make_box();
  open.triangles.pop_back();
  open.origins.pop_back();
  const MeshField field(open);
  EXPECT_FALSE(field.solid());
  const GridSpec grid = cube_grid(default_mesh_bounds(field.box()), 8);
  MeshGridOptions o;
  o.method = MeshGridMethod::Cpt;
  EXPECT_THROW(sample_grid(field, grid, o), InputError);
  // Auto falls back to queries (winding-number signs): the brute-force distance, signed by the
  // generalized winding number.
  MeshGridStats st;
  const std::vector<float> v = sample_grid(field, grid, {}, &st);
  EXPECT_EQ(st.method, MeshGridMethod::Queries);
  expect_grid_matches_brute_force(open, grid, v, "open box");
}

// An expression grid is the point evaluator at the float32 sample coordinates, bit for bit; the
// converted bracket's grid is also the mesh's grid within 1e-5 of the diagonal.
TEST(SampleGrid, ExpressionGridIsThePointEvaluator) {
  const TriMesh mesh = read_mesh(kBracket);
  const Model m = convert_mesh(mesh).model;
  const Tape tape = Tape::compile(*m.graph, m.root);
  const MeshField field(mesh);
  const Box3 mb = field.box();
  const GridSpec grid{{mb.lo - Vec3{0.2, 0.1, 0.15}, mb.hi + Vec3{0.1, 0.25, 0.05}}, {37, 21, 26}};
  ExprGridOptions eo;
  eo.tiles = {16, 4};  // several levels of subdivision even on this small grid
  const std::vector<float> v = sample_grid(tape, grid, eo);
  ASSERT_EQ(v.size(), grid.size());
  const std::vector<float> mv = sample_grid(field, grid);
  const double tol = 1e-5 * length(mb.size());
  PointEvaluator pe;
  std::size_t bad = 0;
  double worst = 0;
  for (int i = 0; i < grid.counts[0]; ++i)
    for (int j = 0; j < grid.counts[1]; ++j)
      for (int k = 0; k < grid.counts[2]; ++k) {
        const std::size_t at = grid.index(i, j, k);
        const float want = pe.eval(tape, static_cast<float>(grid.coord(0, i)), static_cast<float>(grid.coord(1, j)),
                                   static_cast<float>(grid.coord(2, k)));
        if (std::bit_cast<std::uint32_t>(want) != std::bit_cast<std::uint32_t>(v[at]) && bad++ < 5)
          ADD_FAILURE() << "sample (" << i << ", " << j << ", " << k << ") = " << v[at] << ", evaluator " << want;
        worst = std::max(worst, std::fabs(double(v[at]) - mv[at]));
      }
  EXPECT_EQ(bad, 0u);
  EXPECT_LE(worst, tol);
}

// Near-surface points of a flat-faced solid: the signed distance of surface point + N(0, s^2 I)
// is, away from edges, the normal component of the noise, N(0, s^2). Its mean, deviation and the
// share within one deviation must match (with bounds several standard errors wide).
void expect_gaussian_distances(const std::vector<float>& rows, double sigma, const std::string& what) {
  const std::size_t n = rows.size() / 4;
  ASSERT_GT(n, 1000u);
  double sum = 0, sum2 = 0;
  std::size_t within = 0;
  for (std::size_t r = 0; r < n; ++r) {
    const double d = rows[4 * r + 3];
    sum += d, sum2 += d * d;
    within += std::fabs(d) <= sigma;
  }
  const double mean = sum / n, dev = std::sqrt(sum2 / n);
  EXPECT_LT(std::fabs(mean), 5 * sigma / std::sqrt(double(n))) << what;
  EXPECT_NEAR(dev / sigma, 1.0, 0.04) << what;
  EXPECT_NEAR(double(within) / n, 0.6827, 0.02) << what;
}

TEST(SamplePoints, MeshPoints) {
  const MeshField field(read_mesh(kBracket));
  const double sigma = 0.002 * length(field.box().size());
  PointSampleOptions o;
  o.seed = 7;
  const std::vector<float> near = sample_near_surface(field, 20000, sigma, o);
  ASSERT_EQ(near.size(), 4u * 20000);
  expect_gaussian_distances(near, sigma, "bracket");
  const Box3 b = default_mesh_bounds(field.box());
  const std::vector<float> uni = sample_uniform(field, b, 3000, o);
  ASSERT_EQ(uni.size(), 4u * 3000);
  // Every distance is the brute-force signed distance at the written (float) point, rounded to
  // float; uniform points lie in the bounds.
  const TriMesh mesh = read_mesh(kBracket);
  const test::BruteForceSdf bf{mesh};
  const double slack = 1e-12 * length(field.box().size());
  for (const std::vector<float>* rows : {&near, &uni})
    for (std::size_t r = 0; r < rows->size() / 4; r += 7) {
      const float* p = rows->data() + 4 * r;
      const double want = bf.signed_distance({p[0], p[1], p[2]});
      ASSERT_TRUE(test::bf_float_matches(p[3], want, slack)) << "row " << r << ": " << p[3] << ", brute force " << want;
    }
  for (std::size_t r = 0; r < 3000; ++r)
    for (int a = 0; a < 3; ++a) {
      ASSERT_GE(uni[4 * r + a], b.lo[a]);
      ASSERT_LE(uni[4 * r + a], b.hi[a]);
    }
  // Reproducible whatever the thread count; another seed gives other points.
  PointSampleOptions one = o;
  one.threads = 1;
  EXPECT_EQ(sample_near_surface(field, 20000, sigma, one), near);
  one.seed = 8;
  EXPECT_NE(sample_near_surface(field, 20000, sigma, one), near);
}

// Noise that moves points beyond float32 is refused (an infinite point used to hang the mesh
// oracle, and expressions wrote rows of inf and nan); so are point counts whose memory overflows.
TEST(SamplePoints, AbsurdSigmaAndCountsAreRefused) {
  const MeshField field(test::make_box());
  EXPECT_THROW(sample_near_surface(field, 50, 1e39, {}), InputError);
  Graph g;
  const Tape tape = Tape::compile(g, (sqrt(square(g.x()) + square(g.y()) + square(g.z())) - 0.5f).id());
  EXPECT_THROW(sample_near_surface(tape, {{-1, -1, -1}, {1, 1, 1}}, 50, 1e300, {}), InputError);
  EXPECT_THROW(sample_uniform(field, {{-1, -1, -1}, {1, 1, 1}}, std::size_t(1) << 62, {}), InputError);
  EXPECT_THROW(sample_uniform(tape, {{-1, -1, -1}, {1, 1, 1}}, std::size_t(1) << 63, {}), InputError);
}

// Nothing to measure distances to: every triangle merged by a weld tolerance as large as the
// mesh is an error naming the tolerance (it used to fail later on an empty box).
TEST(SamplePoints, AMeshWithNoAreaIsRefused) {
  MeshFieldOptions o;
  o.weld_tolerance = 1e300;
  try {
    const MeshField field(test::make_box(), o);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no area after welding within 1e+300"), std::string::npos) << e.what();
  }
}

TEST(SamplePoints, ExpressionPoints) {
  Graph g;
  const Expr x = g.x(), y = g.y(), z = g.z();
  const NodeId root = (sqrt(square(x - 0.1f) + square(y) + square(z)) - 0.6f).id();
  const Tape tape = Tape::compile(g, root);
  const Box3 b{{-1, -1, -1}, {1, 1, 1}};
  const double sigma = 0.004;  // curvature changes the distances by about sigma / radius: under 1%
  const std::vector<float> near = sample_near_surface(tape, b, 20000, sigma);
  ASSERT_EQ(near.size(), 4u * 20000);
  expect_gaussian_distances(near, sigma, "ball");
  PointEvaluator pe;
  const std::vector<float> uni = sample_uniform(tape, b, 2000);
  for (const std::vector<float>* rows : {&near, &uni})
    for (std::size_t r = 0; r < rows->size() / 4; r += 5) {
      const float* p = rows->data() + 4 * r;
      ASSERT_EQ(p[3], pe.eval(tape, p[0], p[1], p[2])) << "row " << r;
      // The independent reference: the ball's distance in double precision.
      ASSERT_NEAR(p[3], std::hypot(p[0] - 0.1, p[1], p[2]) - 0.6, 1e-6);
    }
  // No surface in the bounds: a clear error.
  EXPECT_THROW(sample_near_surface(tape, Box3{{2, 2, 2}, {3, 3, 3}}, 10, sigma), InputError);
}

// The .npy bytes against NumPy's format description (numpy.lib.format, version 1.0).
TEST(Npy, BytesFollowTheFormat) {
  std::vector<float> v(2 * 3 * 4);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = 0.25f * static_cast<float>(i) - 1.5f;
  const std::string b = npy_bytes(v.data(), {2, 3, 4});
  ASSERT_GE(b.size(), 10u);
  EXPECT_EQ(b.substr(0, 6), std::string("\x93NUMPY", 6));
  EXPECT_EQ(b[6], 1);
  EXPECT_EQ(b[7], 0);
  const std::size_t hl = static_cast<unsigned char>(b[8]) | static_cast<std::size_t>(static_cast<unsigned char>(b[9])) << 8;
  EXPECT_EQ((10 + hl) % 64, 0u);
  const std::string header = b.substr(10, hl);
  EXPECT_EQ(header.back(), '\n');
  EXPECT_NE(header.find("'descr': '<f4'"), std::string::npos) << header;
  EXPECT_NE(header.find("'fortran_order': False"), std::string::npos) << header;
  EXPECT_NE(header.find("'shape': (2, 3, 4)"), std::string::npos) << header;
  ASSERT_EQ(b.size(), 10 + hl + 4 * v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    std::uint32_t u = 0;
    for (int k = 0; k < 4; ++k) u |= std::uint32_t(static_cast<unsigned char>(b[10 + hl + 4 * i + k])) << (8 * k);
    EXPECT_EQ(std::bit_cast<float>(u), v[i]);
  }
  // One-element shapes are Python tuples with their trailing comma.
  EXPECT_NE(npy_bytes(v.data(), {24}).find("'shape': (24,)"), std::string::npos);
  // Read back; truncation and other dtypes are errors naming the file.
  const NpyArray a = parse_npy(b, "a.npy");
  EXPECT_EQ(a.shape, (std::vector<std::size_t>{2, 3, 4}));
  EXPECT_EQ(a.data, v);
  try {
    parse_npy(std::string_view(b).substr(0, b.size() - 3), "cut.npy");
    ADD_FAILURE() << "a truncated file was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "cut.npy");
  }
  std::string f8 = b;
  f8.replace(f8.find("<f4"), 3, "<f8");
  EXPECT_THROW(parse_npy(f8, "f8.npy"), InputError);
}

}  // namespace
}  // namespace frep
