// Every command that reads a mesh, end to end on a real part (fandisk, or a generated box where
// ../shared is absent): meshes out are valid solids at the right distance, pictures show the
// part, grids and points carry the exact distance, .frep round trips, scripts load meshes.
#include <gtest/gtest.h>

#include <filesystem>

#include "cli_test_util.hpp"
#include "frep/mesh/mesh_distance.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/validate.hpp"
#include "frep/mesh/weld.hpp"
#include "mesh_test_util.hpp"

namespace frep {
namespace {

class MeshFieldCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string shared = test::shared_mesh_dir() + "/fandisk.obj";
    if (std::filesystem::exists(shared)) {
      part_ = shared;
    } else {
      std::fprintf(stderr, "../shared/data/meshes is absent: testing a generated box\n");
      part_ = dir_.path("box.stl");
      write_mesh(part_, test::make_fine_box(6));
    }
    mesh_ = read_mesh(part_);
  }
  test::CliRun run(const std::string& args) { return test::run_frep(dir_, args); }
  std::string path(const std::string& name) const { return dir_.path(name); }
  // Output vertices' distance to the part minus `at` (by the part's exact signed distance), worst.
  double worst(const std::string& out, double at, bool shell = false) const {
    const MeshDistance d(mesh_);
    double w = 0;
    for (const Vec3& v : weld(read_mesh(out), {}).mesh.vertices) {
      const double s = d.signed_distance(v, SignMethod::Pseudonormal);
      w = std::max(w, shell ? std::min(std::fabs(s), std::fabs(s + at)) : std::fabs(s - at));
    }
    return w;
  }
  test::ScratchDir dir_;
  std::string part_;
  TriMesh mesh_;
};

TEST_F(MeshFieldCli, OffsetShellAndRemeshAreSolidsAtTheirDistance) {
  const double size = length(bounding_box(mesh_).size());
  const double d = 0.02 * size;
  struct Job {
    std::string args, out;
    double at;
    bool shell;
  };
  const Job jobs[] = {{"offset", "grown.stl", d, false},
                      {"offset", "shrunk.obj", -d, false},
                      {"shell", "hollow.ply", d, true},
                      {"mesh", "remeshed.stl", 0, false}};
  for (const Job& j : jobs) {
    SCOPED_TRACE(j.args + " " + j.out);
    const std::string sign = j.at < 0 ? "-" : "";
    const std::string cmd = j.args + " " + test::shell_quote(part_) + " -r 96 -q -o " + test::shell_quote(path(j.out)) +
                            (j.args == "mesh" ? "" : " -- " + sign + std::to_string(std::fabs(j.at)));
    const test::CliRun r = run(cmd);
    ASSERT_EQ(r.code, 0) << cmd << "\n" << r.err;
    const ValidationReport v = validate_mesh(read_mesh(path(j.out)));
    EXPECT_TRUE(v.is_solid()) << v.summary();
    const double cell = size / 96;
    EXPECT_LT(worst(path(j.out), j.at, j.shell), 0.6 * cell);
  }
}

TEST_F(MeshFieldCli, RenderSampleAndFrepRoundTrip) {
  ASSERT_EQ(run("render " + test::shell_quote(part_) + " --3d --size 96 -q -o " + test::shell_quote(path("p.png"))).code, 0);
  EXPECT_GT(std::filesystem::file_size(path("p.png")), 500u);
  // Points through the mesh and through its converted .frep: the same file, bit for bit.
  ASSERT_EQ(run("convert " + test::shell_quote(part_) + " -q -o " + test::shell_quote(path("part.frep"))).code, 0);
  for (const std::string& in : {part_, path("part.frep")}) {
    const test::CliRun r = run("sample " + test::shell_quote(in) + " --near-surface 500 --sigma 0.01 -q -o " +
                         test::shell_quote(path(in == part_ ? "a.npy" : "b.npy")));
    ASSERT_EQ(r.code, 0) << r.err;
  }
  EXPECT_TRUE(test::read_text(path("a.npy")) == test::read_text(path("b.npy"))) << "the samples differ";
  // The .frep is a mesh field again (one oracle node) whose .vm is the converted formula.
  const test::CliRun info = run("info " + test::shell_quote(path("part.frep")));
  EXPECT_NE(info.out.find("oracle   1"), std::string::npos) << info.out;
  // Both read back and written by the same command (reading folds identities the converter's
  // own graph may leave, such as a + (-b)).
  ASSERT_EQ(run("convert " + test::shell_quote(part_) + " -q -o " + test::shell_quote(path("direct.vm"))).code, 0);
  ASSERT_EQ(run("offset " + test::shell_quote(path("direct.vm")) + " 0 -q -o " + test::shell_quote(path("via_vm.vm"))).code, 0);
  ASSERT_EQ(run("offset " + test::shell_quote(path("part.frep")) + " 0 -q -o " + test::shell_quote(path("back.vm"))).code, 0);
  const std::string direct = test::read_text(path("via_vm.vm")), back = test::read_text(path("back.vm"));
  // The same nodes (the headers may differ in the box).
  EXPECT_TRUE(direct.substr(direct.find("\n_0 ")) == back.substr(back.find("\n_0 "))) << "the formula changed";
  // A truncated grid.
  const test::CliRun t = run("sample " + test::shell_quote(part_) + " --grid 24 --truncate 0.1 -q -o " + test::shell_quote(path("t.npy")));
  EXPECT_EQ(t.code, 0) << t.err;
}

TEST_F(MeshFieldCli, ScriptsLoadMeshesAndRefusalsNameTheFile) {
  test::write_text(path("s.rhai"), "let p = mesh(\"" + part_ + "\");\nunion(p, move(p, [0.5, 0.0, 0.0]))\n");
  test::CliRun r = run("mesh " + test::shell_quote(path("s.rhai")) + " -r 48 -q -o " + test::shell_quote(path("s.stl")) +
                 " --bounds -10,-10,-10,20,30,10");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(validate_mesh(read_mesh(path("s.stl"))).is_solid());
  // An open mesh: refused with the check's words, naming it; exit 1.
  test::write_text(path("open.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 2 3 4\n");
  r = run("offset " + test::shell_quote(path("open.obj")) + " 0.1 -o " + test::shell_quote(path("o.stl")));
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("open.obj"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("cannot convert"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(path("o.stl")));
}

}  // namespace
}  // namespace frep
