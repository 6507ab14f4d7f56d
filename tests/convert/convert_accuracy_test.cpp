// Accuracy of the converter on every closed clean mesh of ../shared/data/meshes, for both sign
// methods: the expression, evaluated in f32, matches the distance oracle (closest point in double
// through a BVH, sign by winding number) within 1e-5 of the bounding-box diagonal, uniformly in
// the box grown by 10%, near the surface on both sides, and exactly on vertices and edges; and
// has no sign error where the distance is not tiny. The figures the docs state are asserted as
// stated: the largest error below 2e-7 of the diagonal (2.5e-6 on the sliver tetrahedron), the
// nodes per triangle of docs/convert.md's table, and armadillo's `.frep` size against `.vm`.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <ostream>
#include <streambuf>

#include "convert_test_util.hpp"
#include "frep/convert/make_solid.hpp"
#include "frep/error.hpp"
#include "frep/io/frep_file.hpp"
#include "frep/io/vm.hpp"
#include "frep/mesh/validate.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "mesh_test_util.hpp"

namespace frep {
namespace {

bool have_tetgen() { return std::system("command -v tetgen > /dev/null 2>&1") == 0; }

// TetGen cannot tetrahedralize every surface without adding points on it (-Y): on some it
// crashes or runs for many minutes. The test allows it 60 s; on the meshes listed as beyond it,
// a failure whose error names TetGen is reported as a skip (with the error), not a pass: nothing
// was measured. Any other failure fails the test.
const char* const kBeyondTetGen[] = {"menger_sponge_l3.obj", "thingi10k_73416.stl", "scallop_manifold.obj"};

// docs/convert.md, "Accuracy" (and the README): the largest error is below 2e-7 of the diagonal
// on every mesh, with both methods, but the near-zero-volume sliver tetrahedron (2.5e-6).
double documented_max_error(const std::string& file) { return file == "tet_sliver.ply" ? 2.5e-6 : 2e-7; }

// docs/convert.md, "Cost per triangle" (and the README's 76 on armadillo, 24 on tray_bottom):
// nodes per triangle {pseudonormal, tets}, as measured (the table rounds them to one decimal);
// 0 where it states none.
const std::map<std::string, std::pair<double, double>> kDocumentedNodesPerTriangle = {
    {"armadillo_libigl.obj", {76.35, 104.25}}, {"fandisk.obj", {52.23, 77.28}},
    {"plate_holes.stl", {39.6, 59.0}},       {"tray_bottom_ascii.stl", {24.4, 24.6}},
    {"menger_sponge_l3.obj", {10.1, 0}},     {"thingi10k_73416.stl", {9.5, 0}},
};

// Counts the bytes written to it, keeping none (armadillo's .vm is about 170 MB).
class CountingBuf : public std::streambuf {
 public:
  std::size_t count = 0;

 protected:
  int_type overflow(int_type c) override { return ++count, traits_type::not_eof(c); }
  std::streamsize xsputn(const char*, std::streamsize n) override { return count += static_cast<std::size_t>(n), n; }
};

// docs/convert.md, "The .frep format" (and the README): armadillo's expression is 25.8 MB as
// .frep, about 6.7 times smaller than as .vm.
void check_documented_sizes(const ConvertResult& r) {
  const std::size_t frep_bytes = serialize_frep(*r.model.graph, r.model.root, r.model.info).size();
  CountingBuf counter;
  std::ostream vm(&counter);
  write_vm(vm, *r.model.graph, r.model.root, r.model.info);
  const double ratio = static_cast<double>(counter.count) / static_cast<double>(frep_bytes);
  std::printf("[convert-accuracy] armadillo's expression: %.2f MB as .frep, %.2f MB as .vm (%.2f times)\n",
              frep_bytes / 1e6, counter.count / 1e6, ratio);
  EXPECT_NEAR(frep_bytes / 1e6, 25.8, 0.1);
  EXPECT_NEAR(ratio, 6.7, 0.1);
}

void check_mesh(const std::string& file, SignMode sign, std::size_t uniform = 3000, std::size_t near = 3000,
                std::size_t on = 1000) {
  SCOPED_TRACE(file + (sign == SignMode::Pseudonormal ? " (pseudonormal)" : " (tets)"));
  const TriMesh mesh = read_mesh(test::shared_mesh_dir() + "/" + file);
  ConvertOptions opt;
  opt.sign = sign;
  opt.tetgen_timeout = 60;
  ConvertResult r;
  try {
    r = convert_mesh(mesh, opt);
  } catch (const InputError& e) {
    const bool beyond = std::find(std::begin(kBeyondTetGen), std::end(kBeyondTetGen), file) != std::end(kBeyondTetGen);
    if (sign == SignMode::Tetrahedra && beyond && std::string(e.what()).find("TetGen") != std::string::npos)
      GTEST_SKIP() << "TetGen cannot tetrahedralize " << file << " (a known limit, kBeyondTetGen): " << e.what();
    throw;
  }
  const test::Samples s = test::sample_around(mesh, uniform, near, on);
  const test::Accuracy a = test::measure(r.model, mesh, s);
  ::testing::Test::RecordProperty(file + "_max_error", std::to_string(a.max_error));
  const double per_triangle = static_cast<double>(r.stats.nodes) / static_cast<double>(r.stats.triangles);
  std::printf("[convert-accuracy] %s %s: %zu points, max error %.3g of the diagonal, %zu sign errors, %.2f nodes/triangle\n",
              file.c_str(), sign == SignMode::Pseudonormal ? "pseudonormal" : "tets", a.count, a.max_error,
              a.sign_errors, per_triangle);
  EXPECT_EQ(a.nonfinite, 0u);
  EXPECT_LE(a.max_error, 1e-5) << a.worst;
  EXPECT_LE(a.max_error, documented_max_error(file)) << "above the figure docs/convert.md states; " << a.worst;
  EXPECT_EQ(a.sign_errors, 0u);
  if (const auto it = kDocumentedNodesPerTriangle.find(file); it != kDocumentedNodesPerTriangle.end()) {
    const double documented = sign == SignMode::Pseudonormal ? it->second.first : it->second.second;
    if (documented > 0) {
      EXPECT_NEAR(per_triangle, documented, 0.05 + 1e-9) << "nodes per triangle, as docs/convert.md states";
    }
  }
  if (file == "armadillo_libigl.obj" && sign == SignMode::Pseudonormal) check_documented_sizes(r);
}

class ConvertAccuracy : public ::testing::TestWithParam<std::string> {};

// Benchy, the benchmark of 3D printing, crosses itself: repaired exactly, its converted expression
// matches the repaired mesh's exact distance.
TEST(SharedMeshes, RepairedBenchyConvertsExactly) {
  FREP_REQUIRE_SHARED_MESHES();
  const TriMesh input = read_mesh(test::shared_mesh_dir() + "/benchy.stl");
  ASSERT_FALSE(validate_mesh(input).is_solid());
  const RepairResult repaired = make_solid(input);
  ASSERT_TRUE(repaired.report.exact);
  ASSERT_TRUE(validate_mesh(repaired.mesh).is_solid());
  const ConvertResult r = convert_mesh(repaired.mesh);
  const test::Samples s = test::sample_around(repaired.mesh, 2000, 2000, 500);
  const test::Accuracy a = test::measure(r.model, repaired.mesh, s);
  std::printf("[convert-accuracy] benchy.stl repaired: %zu points, max error %.3g of the diagonal, %zu sign errors\n",
              a.count, a.max_error, a.sign_errors);
  EXPECT_EQ(a.nonfinite, 0u);
  EXPECT_LE(a.max_error, 1e-5) << a.worst;
  EXPECT_EQ(a.sign_errors, 0u);
}

TEST_P(ConvertAccuracy, Pseudonormal) {
  FREP_REQUIRE_SHARED_MESHES();
  check_mesh(GetParam(), SignMode::Pseudonormal);
}

TEST_P(ConvertAccuracy, Tetrahedra) {
  FREP_REQUIRE_SHARED_MESHES();
  if (!have_tetgen()) GTEST_SKIP() << "the tetgen program is not installed (Debian package tetgen)";
  check_mesh(GetParam(), SignMode::Tetrahedra);
}

// Every mesh of the shared set that `frep check` accepts as a solid.
INSTANTIATE_TEST_SUITE_P(SharedMeshes, ConvertAccuracy,
                         ::testing::Values("cube_unit_bin.stl", "cube_quads.off", "sphere_icosa_1280.stl", "spot.obj",
                                           "bunny_closed_libigl.off", "fandisk.obj", "plate_holes.stl",
                                           "tray_bottom_ascii.stl", "menger_sponge_l3.obj", "armadillo_libigl.obj",
                                           "scallop_manifold.obj", "thingi10k_73416.stl", "cray_right_fltmax.obj",
                                           "capsule_collapsed_poles.obj", "tet_sliver.ply"),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string n = info.param;
                           for (char& c : n)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return n;
                         });

}  // namespace
}  // namespace frep
