// End-to-end tests of `frep sample --normalize` and `--json` (what frep dataset runs per mesh):
// a normalized sample is the original mesh's distance times the scale at the mapped point,
// --normalize none changes nothing, and the JSON line states the scale and offset that map back.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "frep/io/npy.hpp"
#include "frep/mesh/mesh_field.hpp"
#include "frep/mesh/mesh_io.hpp"

#include "cli_test_util.hpp"

namespace frep {
namespace {

using test::CliRun;

const std::string kBracket = FREP_SOURCE_DIR "/examples/bracket.obj";

// The number after "key": in a one-line JSON object (enough for the flat fields frep sample prints).
double json_number(const std::string& json, const std::string& key, int index = 0) {
  std::size_t at = json.find("\"" + key + "\":");
  EXPECT_NE(at, std::string::npos) << key << " missing in " << json;
  if (at == std::string::npos) return NAN;
  at += key.size() + 3;
  while (json[at] == ' ' || json[at] == '[') ++at;
  for (int i = 0; i < index; ++i) at = json.find(',', at) + 1;
  return std::stod(json.substr(at));
}

// normalized / scale + offset, printed so that it reads back the same.
std::string mapped(double normalized, double scale, double offset) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", normalized / scale + offset);
  return buf;
}

class SampleNormalize : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return dir_.path(name); }
  CliRun run(const std::string& args) { return test::run_frep(dir_, args); }
  test::ScratchDir dir_;
};

TEST_F(SampleNormalize, NoneChangesNothing) {
  const std::string q = test::shell_quote(kBracket);
  for (const std::string& what : {std::string("--grid 10"), std::string("--points 300 --seed 3")}) {
    ASSERT_EQ(run("sample " + q + " " + what + " -q -o " + test::shell_quote(path("a.npy"))).code, 0);
    const CliRun r = run("sample " + q + " " + what + " --normalize none --json -o " + test::shell_quote(path("b.npy")));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(test::read_text(path("a.npy")), test::read_text(path("b.npy"))) << what;
    EXPECT_EQ(json_number(r.out, "scale"), 1.0);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(json_number(r.out, "offset", i), 0.0);
  }
}

// Each normalized point, mapped back (p / scale + offset), has the original distance times scale.
TEST_F(SampleNormalize, DistancesAreTheOriginalsScaled) {
  const TriMesh mesh = read_mesh(kBracket);
  const MeshField field(mesh);
  const Box3 box = bounding_box(mesh);
  for (const char* mode : {"unit-cube", "unit-sphere"}) {
    const CliRun r = run("sample " + test::shell_quote(kBracket) + " --points 400 --near-surface 400 --sigma 0.01 "
                         "--normalize " + mode + " --json -o " + test::shell_quote(path("n.npy")));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << "one line: " << r.out;
    EXPECT_NE(r.out.find("\"normalize\": \"" + std::string(mode) + "\""), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\"solid\": true"), std::string::npos) << r.out;
    EXPECT_EQ(json_number(r.out, "count"), 800);
    EXPECT_EQ(json_number(r.out, "triangles"), static_cast<double>(mesh.num_triangles()));
    const double scale = json_number(r.out, "scale");
    const Vec3 offset{json_number(r.out, "offset", 0), json_number(r.out, "offset", 1), json_number(r.out, "offset", 2)};
    // The documented normalization: the box's centre to the origin; the longest side, or the
    // farthest vertex's distance, to 1.
    const Vec3 c = box.center(), s = box.size();
    EXPECT_NEAR(offset.x, c.x, 1e-12);
    EXPECT_NEAR(offset.y, c.y, 1e-12);
    EXPECT_NEAR(offset.z, c.z, 1e-12);
    double extent = std::max({s.x, s.y, s.z});
    if (std::string(mode) == "unit-sphere") {
      extent = 0;
      for (const Vec3& v : mesh.vertices) extent = std::max(extent, length(v - c));
    }
    EXPECT_NEAR(scale, 1 / extent, 1e-12 / extent);
    const double half = std::string(mode) == "unit-cube" ? 0.55 : 1.1;
    EXPECT_EQ(json_number(r.out, "bounds", 0), -half);
    EXPECT_EQ(json_number(r.out, "bounds", 5), half);
    const NpyArray a = read_npy(path("n.npy"));
    ASSERT_EQ(a.shape, (std::vector<std::size_t>{800, 4}));
    for (std::size_t i = 0; i < 800; ++i) {
      const float* row = &a.data[4 * i];
      const Vec3 p{row[0] / scale + offset.x, row[1] / scale + offset.y, row[2] / scale + offset.z};
      // float32 coordinates and distances: agreement to float precision of the unit box.
      EXPECT_NEAR(row[3], field.signed_distance(p) * scale, 2e-6) << mode << " row " << i;
    }
  }
}

// A grid of the normalized mesh equals the grid of the original over the mapped bounds, scaled.
TEST_F(SampleNormalize, GridMatchesTheMappedOriginal) {
  const CliRun n = run("sample " + test::shell_quote(kBracket) + " --grid 12 --json -o " +
                       test::shell_quote(path("n.npy")) + " --normalize unit-cube");
  ASSERT_EQ(n.code, 0) << n.err;
  const double scale = json_number(n.out, "scale");
  std::string bounds;
  for (int i = 0; i < 6; ++i)
    bounds += (i ? "," : "") + mapped(i < 3 ? -0.55 : 0.55, scale, json_number(n.out, "offset", i % 3));
  const CliRun o = run("sample " + test::shell_quote(kBracket) + " --grid 12 -q --bounds " + bounds + " -o " +
                       test::shell_quote(path("o.npy")));
  ASSERT_EQ(o.code, 0) << o.err;
  const NpyArray a = read_npy(path("n.npy")), b = read_npy(path("o.npy"));
  ASSERT_EQ(a.data.size(), b.data.size());
  for (std::size_t i = 0; i < a.data.size(); ++i) EXPECT_NEAR(a.data[i], b.data[i] * scale, 2e-6) << i;
}

TEST_F(SampleNormalize, Refusals) {
  // Expressions have no mesh to normalize.
  const std::string vm = path("c.vm");
  test::write_text(vm, "_0 var-x\n_1 var-y\n_2 var-z\n_3 square _0\n_4 square _1\n_5 add _3 _4\n_6 square _2\n"
                       "_7 add _5 _6\n_8 sqrt _7\n_9 const 1\n_10 sub _8 _9\n");
  CliRun r = run("sample " + test::shell_quote(vm) + " --grid 4 --normalize unit-cube -o " +
                 test::shell_quote(path("c.npy")));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("meshes"), std::string::npos) << r.err;
  r = run("sample " + test::shell_quote(kBracket) + " --grid 4 --normalize unit-box -o " +
          test::shell_quote(path("c.npy")));
  EXPECT_EQ(r.code, 2) << r.err;
}

}  // namespace
}  // namespace frep
