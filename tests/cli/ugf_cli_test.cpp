// End-to-end tests of `frep offset`, `frep shell` and `frep clearance`: run the built binary on
// expression files and on a mesh, check the meshes written (closed and manifold, at the right
// distance), the expressions written (equal to the library's), the clearance printed against
// the exact gap (for two meshes: the mesh-to-mesh query's, digit for digit, with crossing,
// touching and nested meshes named), and the errors (exit 1 naming the file for bad input, 2 for
// a bad command line).
#include <gtest/gtest.h>

#include <array>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "frep/expr/expr.hpp"
#include "frep/script/load.hpp"
#include "frep/io/vm.hpp"
#include "frep/mesh/mesh_field.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/mesh_pair.hpp"
#include "frep/mesh/validate.hpp"
#include "frep/ugf/offset.hpp"
#include "mesh_test_util.hpp"
#include "cli_test_util.hpp"
#include "test_util.hpp"

namespace frep {
namespace {

using test::CliRun;

namespace fs = std::filesystem;

class UgfCommands : public ::testing::Test {
 protected:
  void SetUp() override {
    ball_ = path("ball.vm");
    Graph g;
    save_vm(ball_, g, (sqrt(square(g.x() - 0.1f) + square(g.y()) + square(g.z())) - 0.6f).id());
    Graph h;
    ball2_ = path("ball2.vm");  // radius 0.3 at x = 1.2: a gap of 1.1 - 0.9 = 0.2 to ball
    save_vm(ball2_, h, (sqrt(square(h.x() - 1.2f) + square(h.y()) + square(h.z())) - 0.3f).id());
    Graph k;
    ball3_ = path("ball3.vm");  // radius 0.4 at x = 0.9: overlaps ball by 0.6 + 0.4 - 0.8 = 0.2
    save_vm(ball3_, k, (sqrt(square(k.x() - 0.9f) + square(k.y()) + square(k.z())) - 0.4f).id());
    cube_ = path("cube.obj");
    write_mesh(cube_, test::make_box());
  }
  std::string path(const std::string& name) const { return dir_.path(name); }

  CliRun run(const std::string& args) { return test::run_frep(dir_, args); }

  test::ScratchDir dir_;
  std::string ball_, ball2_, ball3_, cube_;
};

double radius_error(const TriMesh& m, Vec3 c, double r) {
  double worst = 0;
  for (const Vec3& v : m.vertices) worst = std::max(worst, std::fabs(length(v - c) - r));
  return worst;
}

TEST_F(UgfCommands, OffsetMeshesAndSaves) {
  const std::string out = path("grown.stl");
  CliRun r = run("offset '" + ball_ + "' 0.25 -o '" + out + "' -r 40");
  ASSERT_EQ(r.code, 0) << r.err;
  const TriMesh m = read_mesh(out);
  const ValidationReport v = validate_mesh(m);
  EXPECT_TRUE(v.is_solid()) << v.summary();
  // The grown ball of radius 0.85 fits the bounds grown by the offset (no caps), to a fraction of a cell.
  EXPECT_EQ(r.out.find("cut there"), std::string::npos) << r.out;
  EXPECT_LT(radius_error(m, {0.1, 0, 0}, 0.85), 0.01);
  // Negative offsets (also after `--`); and `frep check` accepts the output.
  r = run("offset '" + ball_ + "' -0.2 -o '" + path("shrunk.obj") + "' -r 30");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_LT(radius_error(read_mesh(path("shrunk.obj")), {0.1, 0, 0}, 0.4), 0.01);
  r = run("offset '" + ball_ + "' -o '" + path("shrunk.ply") + "' -r 30 -- -0.2");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_LT(radius_error(read_mesh(path("shrunk.ply")), {0.1, 0, 0}, 0.4), 0.01);
  EXPECT_EQ(run("check '" + path("shrunk.ply") + "'").code, 0);
  // Expression output: the library's field.
  r = run("offset '" + ball_ + "' 0.25 -o '" + path("grown.rhai") + "'");
  ASSERT_EQ(r.code, 0) << r.err;
  const Model saved = load_expression(path("grown.rhai"));
  const Model in = load_expression(ball_);
  const Expr ref = ugf::offset(in.root_expr(), 0.25f);
  for (float px : {-1.f, 0.f, 0.3f, 0.95f, 2.f})
    EXPECT_EQ(test::eval_graph<float>(*saved.graph, saved.root, px, 0.1f, 0.2f),
              test::eval_graph<float>(*in.graph, ref.id(), px, 0.1f, 0.2f));
}

TEST_F(UgfCommands, OffsetOfAMeshIsRoundedAndClosed) {
  const std::string out = path("cube_grown.obj");
  const CliRun r = run("offset '" + cube_ + "' 0.2 -o '" + out + "' -r 30 -q");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  const TriMesh m = read_mesh(out);
  EXPECT_TRUE(validate_mesh(m).is_solid());
  // Every vertex lies at distance 0.2 from the cube (faces flat, edges and corners round).
  double worst = 0;
  for (const Vec3& v : m.vertices) {
    const Vec3 q{std::max(std::fabs(v.x) - 1, 0.0), std::max(std::fabs(v.y) - 1, 0.0), std::max(std::fabs(v.z) - 1, 0.0)};
    worst = std::max(worst, std::fabs(length(q) - 0.2));
  }
  EXPECT_LT(worst, 0.15 * 2.4 / 30) << "within 0.15 of a cell (the grown cube is 2.4 across, 30 cells)";
}

TEST_F(UgfCommands, ShellIsHollowInwardByDefault) {
  const std::string out = path("hollow.stl");
  CliRun r = run("shell '" + cube_ + "' 0.3 -o '" + out + "' -r 32");
  ASSERT_EQ(r.code, 0) << r.err;
  TriMesh m = read_mesh(out);
  ValidationReport v = validate_mesh(m);
  EXPECT_TRUE(v.is_solid()) << v.summary();
  // Two shells: the outer cube and the inner one of side 1.4, facing in.
  double outer = 0, inner = 0;
  for (const Vec3& p : m.vertices) {
    const double c = std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
    (c > 0.85 ? outer : inner) = std::max(c > 0.85 ? outer : inner, c);
  }
  EXPECT_NEAR(outer, 1.0, 0.01);
  EXPECT_NEAR(inner, 0.7, 0.01);
  EXPECT_EQ(r.err.find("thinner"), std::string::npos) << r.err;
  // A wall thinner than two cells: a warning (the mesh is still a valid solid).
  r = run("shell '" + cube_ + "' 0.1 -o '" + path("thin.stl") + "' -r 32");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("thinner than two cells"), std::string::npos) << r.err;
  EXPECT_TRUE(validate_mesh(read_mesh(path("thin.stl"))).is_solid());
  // Without --resolution the wall gets 3 cells: 0.03 across a cube of side 2 (plus margins) needs
  // more than the default 128 cells, and nothing is lost.
  r = run("shell '" + cube_ + "' 0.03 -o '" + path("auto.stl") + "'");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("so that the wall is 3 cells thick"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("thinner"), std::string::npos) << r.err;
  EXPECT_EQ(validate_mesh(read_mesh(path("auto.stl"))).components, 2u);
  // Outward: the wall from 1.0 to 1.3; centred: 0.85 to 1.15.
  r = run("shell '" + cube_ + "' 0.3 --side outward -o '" + path("out.stl") + "' -r 32 -q");
  ASSERT_EQ(r.code, 0) << r.err;
  m = read_mesh(path("out.stl"));
  EXPECT_TRUE(validate_mesh(m).is_solid());
  double far = 0;
  for (const Vec3& p : m.vertices) far = std::max(far, std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)}));
  EXPECT_NEAR(far, 1.3, 0.01);
  r = run("shell '" + ball_ + "' 0.2 --side centred -o '" + path("c.vm") + "' -q");
  ASSERT_EQ(r.code, 0) << r.err;
  const Model c = load_expression(path("c.vm"));
  EXPECT_NEAR(test::eval_graph<float>(*c.graph, c.root, 0.1f + 0.6f, 0.f, 0.f), -0.1f, 1e-6f);
  EXPECT_NEAR(test::eval_graph<float>(*c.graph, c.root, 0.1f, 0.f, 0.f), 0.5f, 1e-6f);
}

TEST_F(UgfCommands, ClearancePrintsTheGapOrTheInterference) {
  CliRun r = run("clearance '" + ball_ + "' '" + ball2_ + "'");
  ASSERT_EQ(r.code, 0) << r.err;
  float gap = 0;
  ASSERT_EQ(std::sscanf(r.out.c_str(), "gap: %f", &gap), 1) << r.out;
  EXPECT_NEAR(gap, 0.2f, 1e-5f);
  // The nearest points are (0.7, 0, 0) on ball and (0.9, 0, 0) on ball2.
  EXPECT_NE(r.out.find("nearest points: 0.7, "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(", 0.9, "), std::string::npos) << r.out;
  r = run("clearance '" + ball_ + "' '" + ball3_ + "'");
  ASSERT_EQ(r.code, 0) << r.err;
  float depth = 0;
  ASSERT_EQ(std::sscanf(r.out.c_str(), "interference: depth %f", &depth), 1) << r.out;
  EXPECT_NEAR(depth, 0.2f, 1e-5f);
  // The deepest point is inside both, as printed (the minimizer of A + B may lie anywhere on the
  // deepest segment, and was printed outside one body): here where both depths are 0.1.
  const auto deep = [&](const CliRun& run_result) {
    float x = NAN, y = NAN, z = NAN;
    const std::size_t at = run_result.out.find("deepest point: ");
    if (at != std::string::npos) std::sscanf(run_result.out.c_str() + at, "deepest point: %f, %f, %f", &x, &y, &z);
    return std::array<float, 3>{x, y, z};
  };
  EXPECT_NE(r.out.find("(inside both;"), std::string::npos) << r.out;
  std::array<float, 3> q = deep(r);
  EXPECT_NEAR(q[0], 0.6f, 1e-4f) << r.out;  // ball: radius 0.6 at 0.1, so x in [-0.5, 0.7]; ball3 from 0.5
  // A mesh against an expression: the cube [-1, 1]^3 and ball2 moved to x = 1.2 is 1.2 - 0.3 - 1 away... overlapping by 0.1.
  r = run("clearance '" + cube_ + "' '" + ball2_ + "'");
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(std::sscanf(r.out.c_str(), "interference: depth %f", &depth), 1) << r.out;
  EXPECT_NEAR(depth, 0.1f, 1e-4f);
  EXPECT_NE(r.out.find("(inside both;"), std::string::npos) << r.out;
  q = deep(r);
  EXPECT_NEAR(q[0], 0.95f, 1e-3f) << r.out;  // the cube ends at 1, ball2 starts at 0.9
}

TriMesh moved_mesh(TriMesh m, const Vec3& t) {
  for (Vec3& v : m.vertices) v += t;
  return m;
}

// "nearest points: x, y, z on A, x, y, z on B", parsed; NaN if absent.
std::array<double, 6> nearest_points(const std::string& out) {
  std::array<double, 6> p;
  p.fill(NAN);
  const std::size_t at = out.find("nearest points: ");
  if (at == std::string::npos) return p;
  std::sscanf(out.c_str() + at, "nearest points: %lf, %lf, %lf on %*[^,], %lf, %lf, %lf", &p[0], &p[1], &p[2], &p[3],
              &p[4], &p[5]);
  return p;
}

TEST_F(UgfCommands, ClearanceOfTwoMeshesIsTheirExactDistance) {
  const std::string ball = path("ball.obj"), far = path("far.obj");
  write_mesh(ball, test::make_sphere(2, 0.5));
  const Vec3 t{1.75, 0.25, 0.125};  // floats: scripts move by float constants
  write_mesh(far, moved_mesh(read_mesh(ball), t));
  CliRun r = run("clearance '" + ball + "' '" + far + "'");
  ASSERT_EQ(r.code, 0) << r.err;
  // The library's answer on the same files, digit for digit.
  const MeshField fa(read_mesh(ball)), fb(read_mesh(far));
  const MeshPairResult lib = compare_meshes(fa, fb);
  ASSERT_TRUE(lib.apart());
  double gap = 0;
  ASSERT_EQ(std::sscanf(r.out.c_str(), "gap: %lf", &gap), 1) << r.out;
  EXPECT_EQ(gap, lib.distance) << r.out;
  const std::array<double, 6> p = nearest_points(r.out);
  EXPECT_EQ(p[0], lib.point_a.x);
  EXPECT_EQ(p[1], lib.point_a.y);
  EXPECT_EQ(p[2], lib.point_a.z);
  EXPECT_EQ(p[3], lib.point_b.x);
  EXPECT_EQ(p[4], lib.point_b.y);
  EXPECT_EQ(p[5], lib.point_b.z);
  EXPECT_NE(r.out.find("exact: the distance between triangle " + std::to_string(lib.triangle_a)), std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("proven lower bound"), std::string::npos) << r.out;  // nothing left to prove
  EXPECT_NE(r.err.find("frep: read"), std::string::npos) << r.err;
  // Quiet: the result only.
  r = run("clearance -q '" + ball + "' '" + far + "'");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find("frep: read"), std::string::npos) << r.err;
  // The copy moved by a script instead (a moved mesh leaf): the same coordinates, the same gap.
  const std::string script = path("moved.rhai");
  test::write_text(script, "move(mesh(\"ball.obj\"), [1.75, 0.25, 0.125])\n");
  r = run("clearance -q '" + ball + "' '" + script + "'");
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(std::sscanf(r.out.c_str(), "gap: %lf", &gap), 1) << r.out;
  EXPECT_EQ(gap, compare_meshes(fa, {fa, Affine3::translation(t)}).distance) << r.out;
}

TEST_F(UgfCommands, ClearanceNamesCrossingNestedAndTouchingMeshes) {
  const std::string ball = path("ball.obj"), near = path("near.obj"), small = path("small.obj");
  write_mesh(ball, test::make_sphere(3, 0.5));
  write_mesh(near, moved_mesh(test::make_sphere(3, 0.5), {0.5, 0, 0}));
  write_mesh(small, moved_mesh(test::make_sphere(2, 0.2), {0.05, 0, 0}));
  // Crossing: two balls of radius 0.5, 0.5 apart, overlap by about 0.5 (faceted).
  CliRun r = run("clearance -q '" + ball + "' '" + near + "'");
  ASSERT_EQ(r.code, 0) << r.err;
  const MeshPairResult lib = compare_meshes(MeshField(read_mesh(ball)), MeshField(read_mesh(near)));
  EXPECT_NE(r.out.find("surfaces cross: " + std::to_string(lib.crossing) + " triangle pairs (first: triangle " +
                       std::to_string(lib.examples.front().a)),
            std::string::npos)
      << r.out;
  float depth = 0;
  const std::size_t at = r.out.find("interference: depth ");
  ASSERT_NE(at, std::string::npos) << r.out;
  ASSERT_EQ(std::sscanf(r.out.c_str() + at, "interference: depth %f", &depth), 1) << r.out;
  EXPECT_NEAR(depth, 0.5f, 0.01f) << r.out;
  EXPECT_NE(r.out.find("(inside both;"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("proven lower bound of A + B: "), std::string::npos) << r.out;
  // Nested: the small ball (radius 0.2, centre 0.05 off) inside the big one (radius 0.5): A + B
  // is smallest, |c| - 0.7, between the two centres.
  r = run("clearance -q '" + ball + "' '" + small + "'");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("nested: " + small + " lies inside " + ball), std::string::npos) << r.out;
  const std::size_t at2 = r.out.find("interference: depth ");
  ASSERT_NE(at2, std::string::npos) << r.out;
  ASSERT_EQ(std::sscanf(r.out.c_str() + at2, "interference: depth %f", &depth), 1) << r.out;
  EXPECT_NEAR(depth, 0.65f, 0.01f) << r.out;
  // Touching: the cube [-1, 1]^3 and the cube [1, 3] x [-1, 1]^2 share a face plane.
  const std::string beside = path("beside.obj");
  write_mesh(beside, test::make_box({1, -1, -1}, {3, 1, 1}));
  r = run("clearance -q '" + cube_ + "' '" + beside + "'");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("surfaces touch: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("none crossing"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("gap: 0 (the surfaces touch"), std::string::npos) << r.out;
  EXPECT_EQ(nearest_points(r.out)[0], 1) << r.out;
}

// The case: a real part and a copy of it moved along x, apart by 0.3 widths, and
// crossing it when moved by a third of its width.
TEST_F(UgfCommands, ClearanceOfARealPartAndMovedCopies) {
  FREP_REQUIRE_SHARED_MESHES();
  const std::string part = test::shared_mesh_dir() + "/fandisk.obj";
  const TriMesh m = read_mesh(part);
  const double w = bounding_box(m).size().x;
  const std::string apart = path("apart.obj"), third = path("third.obj");
  write_mesh(apart, moved_mesh(m, {1.3 * w, 0, 0}));
  write_mesh(third, moved_mesh(m, {w / 3, 0, 0}));
  const auto t0 = std::chrono::steady_clock::now();
  CliRun r = run("clearance '" + part + "' '" + apart + "'");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_EQ(r.code, 0) << r.err;
  double gap = 0;
  ASSERT_EQ(std::sscanf(r.out.c_str(), "gap: %lf", &gap), 1) << r.out;
  EXPECT_NEAR(gap, 0.3 * w, 1e-12 * w) << r.out;
  EXPECT_NE(r.out.find("exact: "), std::string::npos) << r.out;
  r = run("clearance '" + part + "' '" + third + "'");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("surfaces cross: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("interference: depth "), std::string::npos) << r.out;
  std::printf("[clearance] fandisk and a copy 1.3 widths along x: gap %.9g, %.2f s for the whole command\n", gap,
              seconds);
}

TEST_F(UgfCommands, ErrorsNameTheFileAndUseTheExitCodes) {
  // Bad input: exit 1, the file named.
  CliRun r = run("offset '" + path("missing.stl") + "' 0.1 -o '" + path("o.stl") + "'");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("missing.stl"), std::string::npos) << r.err;
  r = run("offset '" + ball_ + "' 0.1 -o '" + path("o.png") + "'");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("o.png"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(".stl"), std::string::npos) << r.err;
  r = run("shell '" + ball_ + "' 0.1 -o '" + path("nodir/o.stl") + "'");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("does not exist"), std::string::npos) << r.err;
  r = run("offset '" + ball_ + "' -2 -o '" + path("gone.stl") + "'");  // shrinks to nothing
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("empty"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("gone.stl")));
  r = run("clearance '" + ball_ + "' '" + path("nothing.vm") + "'");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("nothing.vm"), std::string::npos) << r.err;
  // Bad command lines: exit 2.
  EXPECT_EQ(run("shell '" + ball_ + "' 0 -o '" + path("o.stl") + "'").code, 2);
  EXPECT_EQ(run("shell '" + ball_ + "' 0.1 --side sideways -o '" + path("o.stl") + "'").code, 2);
  EXPECT_EQ(run("offset '" + ball_ + "' 0.1").code, 2);
  EXPECT_EQ(run("offset '" + ball_ + "' nan -o '" + path("o.stl") + "'").code, 2);
  EXPECT_EQ(run("offset '" + ball_ + "' 0.1 -o '" + path("o.stl") + "' --bounds 1,1,1,0,2,2").code, 2);
  EXPECT_EQ(run("clearance '" + ball_ + "'").code, 2);
  for (const char* sub : {"offset", "shell", "clearance"}) {
    r = run(std::string(sub) + " --help");
    EXPECT_EQ(r.code, 0) << sub;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << sub;
  }
}

}  // namespace
}  // namespace frep
