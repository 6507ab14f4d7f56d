// Meshes and points far from float's comfort, end to end: `frep sample --sigma 1e30` writes only
// finite values (from the mesh and from its converted expression alike) or refuses, naming the
// option, and writes no file; bounds beyond float range are a command-line error; `frep convert`
// and the commands that read a mesh as its distance refuse the tetrahedron with a vertex at 1e30
// and vertices beyond float range, naming the vertex.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "cli_test_util.hpp"
#include "frep/io/npy.hpp"

namespace frep {
namespace {

namespace fs = std::filesystem;

const char* kTet = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";

bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

class FarSamples : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return dir_.path(name); }
  std::string q(const std::string& name) const { return test::shell_quote(path(name)); }
  test::CliRun run(const std::string& args) { return test::run_frep(dir_, args); }
  test::ScratchDir dir_;
};

TEST_F(FarSamples, Sigma1e30GivesFiniteDistancesFromTheMeshAndItsExpression) {
  test::write_text(path("tet.obj"), kTet);
  test::CliRun r = run("sample " + q("tet.obj") + " --near-surface 300 --sigma 1e30 -q -o " + q("mesh.npy"));
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(run("convert " + q("tet.obj") + " -q -o " + q("tet.vm")).code, 0);
  r = run("sample " + q("tet.vm") + " --near-surface 300 --sigma 1e30 -q -o " + q("expr.npy"));
  ASSERT_EQ(r.code, 0) << r.err;
  const NpyArray m = read_npy(path("mesh.npy")), e = read_npy(path("expr.npy"));
  ASSERT_EQ(m.shape, (std::vector<std::size_t>{300, 4}));
  ASSERT_EQ(e.shape, m.shape);
  for (std::size_t i = 0; i < 300; ++i) {
    const float d = m.data[4 * i + 3];
    ASSERT_TRUE(std::isfinite(d)) << i;
    ASSERT_TRUE(std::isfinite(e.data[4 * i + 3])) << i;
    EXPECT_GT(d, 1e25f) << i;  // points are 1e30 away, give or take
    // The surface points differ (the expression's are found by Newton steps), the noise does not:
    // at 1e30, both are the same distance to float precision.
    EXPECT_NEAR(e.data[4 * i + 3], d, 1e-5 * d) << i;
  }
}

TEST_F(FarSamples, NonFiniteValuesAreRefusedNamingTheOption) {
  // x^8 - 0.5^8: a surface at |x| = 0.5, and inf beyond |x| of about 6e4.
  test::write_text(path("x8.vm"),
                   "_0 var-x\n_1 square _0\n_2 square _1\n_3 square _2\n_4 const 0.00390625\n_5 sub _3 _4\n");
  test::CliRun r = run("sample " + q("x8.vm") + " --grid 4 --bounds=-1e10,-1,-1,1e10,1,1 -q -o " + q("g.npy"));
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_TRUE(contains(r.err, "x8.vm: the field is inf at (-1e+10, -1, -1) (64 of 64 samples), and frep sample writes "
                              "only finite values: give a smaller --bounds"))
      << r.err;
  r = run("sample " + q("x8.vm") + " --near-surface 50 --sigma 1e30 -q -o " + q("n.npy"));
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_TRUE(contains(r.err, "give a smaller --sigma")) << r.err;
  r = run("sample " + q("x8.vm") + " --points 50 --bounds=-1e10,-1,-1,1e10,1,1 -q -o " + q("p.npy"));
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_TRUE(contains(r.err, "give a smaller --bounds")) << r.err;
  EXPECT_FALSE(fs::exists(path("g.npy")));
  EXPECT_FALSE(fs::exists(path("n.npy")));
  EXPECT_FALSE(fs::exists(path("p.npy")));
  // Within range: written.
  EXPECT_EQ(run("sample " + q("x8.vm") + " --grid 4 -q -o " + q("ok.npy")).code, 0);
  // A mesh's distance beyond float range (a grid corner 5e38 from it).
  test::write_text(path("tet.obj"), kTet);
  r = run("sample " + q("tet.obj") + " --grid 4 --bounds=-3e38,-3e38,-3e38,3e38,3e38,3e38 -q -o " + q("m.npy"));
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_TRUE(contains(r.err, "tet.obj: the distance is inf at (-3e+38, -3e+38, -3e+38)")) << r.err;
  EXPECT_TRUE(contains(r.err, "does not fit a 32-bit float")) << r.err;
  // Bounds that are not floats at all: a command-line error.
  r = run("sample " + q("tet.obj") + " --grid 4 --bounds=-1e39,0,0,1,1,1 -q -o " + q("b.npy"));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(contains(r.err, "--bounds: -1e+39 is beyond the range of 32-bit floats")) << r.err;
  EXPECT_FALSE(fs::exists(path("m.npy")));
  EXPECT_FALSE(fs::exists(path("b.npy")));
}

TEST_F(FarSamples, StrayAndOutOfRangeVerticesAreRefusedByEveryCommand) {
  test::write_text(path("tall.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1e30\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n");
  test::write_text(path("wide.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1e39\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n");
  test::write_text(path("p.txt"), "0.1 0.1 -1\n0.2 0.2 -8\n");
  const std::pair<const char*, const char*> cases[] = {
      {"tall", "tall.obj: the mesh spans more than 32-bit floats can carry: vertex 3 (a corner of triangle 1, line 6) "
               "at (0, 0, 1e+30)"},
      {"wide", "wide.obj: vertex 3 (a corner of triangle 1, line 6) at (0, 0, 1e+39) lies beyond the range of 32-bit "
               "floats"}};
  for (const auto& [name, message] : cases) {
    const std::string mesh = q(std::string(name) + ".obj");
    for (const std::string& cmd : {"convert " + mesh + " -o " + q("out.vm"), "eval " + mesh + " --points " + q("p.txt"),
                                   "sample " + mesh + " --grid 4 -o " + q("out.npy")}) {
      const test::CliRun r = run(cmd);
      EXPECT_EQ(r.code, 1) << cmd << "\n" << r.err;
      EXPECT_TRUE(contains(r.err, message)) << cmd << "\n" << r.err;
    }
  }
  EXPECT_FALSE(fs::exists(path("out.vm")));
  EXPECT_FALSE(fs::exists(path("out.npy")));
}

}  // namespace
}  // namespace frep
