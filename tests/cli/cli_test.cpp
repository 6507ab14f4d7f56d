// End-to-end tests of the `frep` command-line tool: run the built binary, capture stdout, stderr
// and the exit code, and compare with the library.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "frep/expr/expr.hpp"
#include "frep/io/vm.hpp"
#include "frep/render/render2d.hpp"
#include "cli_test_util.hpp"
#include "test_util.hpp"

namespace frep {
namespace {

namespace fs = std::filesystem;

using RunResult = test::CliRun;

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    // A small 2D model of our own, so most tests do not depend on the shared data.
    Graph g;
    auto x = g.x(), y = g.y();
    circle_ = path("circle.vm");
    save_vm(circle_, g, (sqrt(square(x - 0.2f) + square(y + 0.1f)) - 0.6f).id());
  }

  std::string path(const std::string& name) const { return dir_.path(name); }

  RunResult run(const std::string& args, const std::string& stdin_text = "") {
    return test::run_frep(dir_, args, stdin_text);
  }

  void write(const std::string& name, const std::string& text) { test::write_text(path(name), text); }

  test::ScratchDir dir_;
  std::string circle_;
};

std::vector<std::string> lines_of(const std::string& s) {
  std::vector<std::string> v;
  std::istringstream in(s);
  for (std::string l; std::getline(in, l);) v.push_back(l);
  return v;
}

std::string fmt9(float v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(v));
  return buf;
}

TEST_F(Cli, HelpForEverySubcommandExitsZero) {
  for (const std::string sub : {"", "info ", "eval ", "render "}) {
    const RunResult r = run(sub + "--help");
    EXPECT_EQ(r.code, 0) << sub << r.err;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << sub;
  }
  EXPECT_EQ(run("--version").code, 0);
  const RunResult none = run("");
  EXPECT_NE(none.code, 0) << "a subcommand is required";
  const RunResult bogus = run("frobnicate");
  EXPECT_NE(bogus.code, 0);
  EXPECT_FALSE(bogus.err.empty());
}

TEST_F(Cli, InfoOnProspero) {
  FREP_REQUIRE_DATA("prospero.vm");
  const std::string file = test::data_file("prospero.vm");
  const RunResult r = run("info " + test::shell_quote(file));
  ASSERT_EQ(r.code, 0) << r.err;
  const Model m = read_vm(file);
  const Tape t = Tape::compile(*m.graph, m.root);
  const std::size_t nodes = reachable_nodes(*m.graph, m.root).size();
  EXPECT_NE(r.out.find("nodes: " + std::to_string(nodes)), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("variables: x y\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("tape: " + std::to_string(t.code().size()) + " instructions"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("max"), std::string::npos);
  EXPECT_TRUE(r.err.empty()) << r.err;
}

TEST_F(Cli, InfoOnA3DModelListsZ) {
  Graph g;
  save_vm(path("ball.vm"), g, (square(g.x()) + square(g.y()) + square(g.z()) - 1.0f).id());
  const RunResult r = run("info " + test::shell_quote(path("ball.vm")));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("variables: x y z"), std::string::npos) << r.out;
  // The evaluator it would run on: the JIT by default (where the CPU runs it), else the interpreter.
  EXPECT_NE(r.out.find("evaluator: "), std::string::npos) << r.out;
  // (The child inherits this process's environment.)
  ::setenv("FREP_BACKEND", "interp", 1);
  const RunResult i = run("info " + test::shell_quote(path("ball.vm")));
  ::setenv("FREP_BACKEND", "gpu", 1);
  const RunResult bad = run("info " + test::shell_quote(path("ball.vm")));
  ::unsetenv("FREP_BACKEND");
  ASSERT_EQ(i.code, 0) << i.err;
  EXPECT_NE(i.out.find("evaluator: interpreter"), std::string::npos) << i.out;
  EXPECT_EQ(bad.code, 1);
  EXPECT_NE(bad.err.find("unknown evaluator backend 'gpu' (this build has: interp, jit)"), std::string::npos) << bad.err;
}

TEST_F(Cli, EvalMatchesThePointEvaluator) {
  const std::string pts =
      "# points\n"
      "0 0 0\n"
      "0.5, -0.25, 0\n"
      "  1.5\t2.5  \n"  // two numbers: z = 0
      "\n"
      "-1e-3,7e2\n"
      "0.2 -0.1 3   # a comment\n"
      "1e30 -1e30 0\r\n";
  write("pts.txt", pts);
  const RunResult r = run("eval " + test::shell_quote(circle_) + " --points " + test::shell_quote(path("pts.txt")));
  ASSERT_EQ(r.code, 0) << r.err;
  const Model m = read_vm(circle_);
  const Tape t = Tape::compile(*m.graph, m.root);
  PointEvaluator pe;
  const float P[][3] = {{0, 0, 0}, {0.5f, -0.25f, 0}, {1.5f, 2.5f, 0}, {-1e-3f, 7e2f, 0}, {0.2f, -0.1f, 3}, {1e30f, -1e30f, 0}};
  const std::vector<std::string> got = lines_of(r.out);
  ASSERT_EQ(got.size(), 6u) << r.out;
  for (int i = 0; i < 6; ++i) EXPECT_EQ(got[i], fmt9(pe.eval(t, P[i][0], P[i][1], P[i][2]))) << "line " << i;

  // Gradients: value and d/dx d/dy d/dz.
  const RunResult g = run("eval " + test::shell_quote(circle_) + " --points " + test::shell_quote(path("pts.txt")) + " --grad");
  ASSERT_EQ(g.code, 0) << g.err;
  GradEvaluator ge;
  const std::vector<std::string> gl = lines_of(g.out);
  ASSERT_EQ(gl.size(), 6u);
  for (int i = 0; i < 6; ++i) {
    const Grad gr = ge.eval(t, P[i][0], P[i][1], P[i][2]);
    EXPECT_EQ(gl[i], fmt9(gr.v) + " " + fmt9(gr.dx) + " " + fmt9(gr.dy) + " " + fmt9(gr.dz)) << "line " << i;
  }

  // Points from stdin.
  const RunResult s = run("eval " + test::shell_quote(circle_) + " --points -", "0 0 0\n0.2 -0.1\n");
  ASSERT_EQ(s.code, 0) << s.err;
  EXPECT_EQ(s.out, fmt9(pe.eval(t, 0, 0, 0)) + "\n" + fmt9(pe.eval(t, 0.2f, -0.1f, 0)) + "\n");
}

TEST_F(Cli, EvalManyPointsOnProspero) {
  FREP_REQUIRE_DATA("prospero.vm");
  std::mt19937_64 rng(71);
  std::string pts;
  std::vector<std::array<float, 2>> P;
  for (int i = 0; i < 1000; ++i) {  // more than one SIMD chunk
    const float x = std::uniform_real_distribution<float>(-1, 1)(rng), y = std::uniform_real_distribution<float>(-1, 1)(rng);
    P.push_back({x, y});
    pts += fmt9(x) + " " + fmt9(y) + "\n";
  }
  write("pts.txt", pts);
  const RunResult r = run("eval " + test::shell_quote(test::data_file("prospero.vm")) + " -p " + test::shell_quote(path("pts.txt")));
  ASSERT_EQ(r.code, 0) << r.err;
  const Model m = read_vm(test::data_file("prospero.vm"));
  const Tape t = Tape::compile(*m.graph, m.root);
  PointEvaluator pe;
  const std::vector<std::string> got = lines_of(r.out);
  ASSERT_EQ(got.size(), P.size());
  for (std::size_t i = 0; i < P.size(); ++i) ASSERT_EQ(got[i], fmt9(pe.eval(t, P[i][0], P[i][1], 0))) << i;
}

TEST_F(Cli, EvalErrors) {
  // Missing expression file.
  write("pts.txt", "0 0 0\n");
  RunResult r = run("eval " + test::shell_quote(path("nope.vm")) + " --points " + test::shell_quote(path("pts.txt")));
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("nope.vm"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty());
  // Bad points file: the message names the file and line.
  write("bad.txt", "0 0 0\n# fine\n1 2 3\n1 zz 3\n");
  r = run("eval " + test::shell_quote(circle_) + " --points " + test::shell_quote(path("bad.txt")));
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("bad.txt:4"), std::string::npos) << r.err;
  write("bad2.txt", "0 0 0\n1\n");
  r = run("eval " + test::shell_quote(circle_) + " --points " + test::shell_quote(path("bad2.txt")));
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("bad2.txt:2"), std::string::npos) << r.err;
  write("bad3.txt", "1 2 3 4\n");
  r = run("eval " + test::shell_quote(circle_) + " --points " + test::shell_quote(path("bad3.txt")));
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("bad3.txt:1"), std::string::npos) << r.err;
  // Missing points file, missing --points.
  r = run("eval " + test::shell_quote(circle_) + " --points " + test::shell_quote(path("nope.txt")));
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("nope.txt"), std::string::npos) << r.err;
  r = run("eval " + test::shell_quote(circle_));
  EXPECT_NE(r.code, 0);
  EXPECT_FALSE(r.err.empty());
  // A bad expression file: file and line.
  write("broken.vm", "a var-x\nb nosuchop a\n");
  r = run("eval " + test::shell_quote(path("broken.vm")) + " --points " + test::shell_quote(path("pts.txt")));
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("broken.vm:2"), std::string::npos) << r.err;
  r = run("info " + test::shell_quote(path("broken.vm")));
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("broken.vm:2"), std::string::npos) << r.err;
}

// Reads a binary PGM written by frep.
bool read_pgm(const std::string& file, Image& img) {
  const std::string bytes = test::read_text(file);
  int w = 0, h = 0, maxv = 0, off = 0;
  if (std::sscanf(bytes.c_str(), "P5 %d %d %d%n", &w, &h, &maxv, &off) != 3 || maxv != 255) return false;
  ++off;  // the single whitespace after maxval
  if (bytes.size() != static_cast<std::size_t>(off) + static_cast<std::size_t>(w) * h) return false;
  img.width = w, img.height = h;
  img.pixels.assign(bytes.begin() + off, bytes.end());
  return true;
}

TEST_F(Cli, RenderPngAndPgm) {
  const std::string png = path("out.png"), pgm = path("out.pgm");
  RunResult r = run("render " + test::shell_quote(circle_) + " --size 64 -o " + test::shell_quote(png));
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_TRUE(fs::exists(png));
  const std::string bytes = test::read_text(png);
  ASSERT_GT(bytes.size(), 24u);
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  auto be32 = [&](std::size_t o) {
    return (static_cast<unsigned char>(bytes[o]) << 24) | (static_cast<unsigned char>(bytes[o + 1]) << 16) |
           (static_cast<unsigned char>(bytes[o + 2]) << 8) | static_cast<unsigned char>(bytes[o + 3]);
  };
  EXPECT_EQ(bytes.substr(12, 4), "IHDR");
  EXPECT_EQ(be32(16), 64u);
  EXPECT_EQ(be32(20), 64u);

  r = run("render " + test::shell_quote(circle_) + " -s 64 -q --output " + test::shell_quote(pgm));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.out.empty()) << "--quiet";
  Image img;
  ASSERT_TRUE(read_pgm(pgm, img));
  EXPECT_EQ(img.width, 64);
  EXPECT_EQ(img.height, 64);
  const Model m = read_vm(circle_);
  RenderOptions o;
  o.size = 64;
  const Image ref = render2d_brute_force(Tape::compile(*m.graph, m.root), o);
  EXPECT_EQ(img.pixels, ref.pixels);
  int white = 0;
  for (auto p : img.pixels) white += p == 255;
  EXPECT_GT(white, 64 * 64 / 20) << "the circle should be visible";
}

TEST_F(Cli, RenderProsperoPgmMatchesBruteForce) {
  FREP_REQUIRE_DATA("prospero.vm");
  const std::string pgm = path("p.pgm");
  const RunResult r = run("render " + test::shell_quote(test::data_file("prospero.vm")) + " --size 97 -j 2 -o " + test::shell_quote(pgm));
  ASSERT_EQ(r.code, 0) << r.err;
  Image img;
  ASSERT_TRUE(read_pgm(pgm, img));
  const Model m = read_vm(test::data_file("prospero.vm"));
  RenderOptions o;
  o.size = 97;
  EXPECT_EQ(img.pixels, render2d_brute_force(Tape::compile(*m.graph, m.root), o).pixels);
}

TEST_F(Cli, RenderErrorsLeaveNoOutputFile) {
  // Bad extension.
  RunResult r = run("render " + test::shell_quote(circle_) + " --size 16 -o " + test::shell_quote(path("out.jpg")));
  EXPECT_NE(r.code, 0);
  EXPECT_FALSE(r.err.empty());
  EXPECT_FALSE(fs::exists(path("out.jpg")));
  // --size 0 and a negative size.
  r = run("render " + test::shell_quote(circle_) + " --size 0 -o " + test::shell_quote(path("zero.png")));
  EXPECT_NE(r.code, 0);
  EXPECT_FALSE(r.err.empty());
  EXPECT_FALSE(fs::exists(path("zero.png")));
  r = run("render " + test::shell_quote(circle_) + " --size -5 -o " + test::shell_quote(path("neg.png")));
  EXPECT_NE(r.code, 0);
  EXPECT_FALSE(fs::exists(path("neg.png")));
  // Missing input.
  r = run("render " + test::shell_quote(path("nope.vm")) + " --size 16 -o " + test::shell_quote(path("x.png")));
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("nope.vm"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("x.png")));
  // Output in a directory that does not exist: fails cleanly, nothing is created.
  const std::string deep = path("no/such/dir/out.png");
  r = run("render " + test::shell_quote(circle_) + " --size 16 -o " + test::shell_quote(deep));
  EXPECT_NE(r.code, 0);
  EXPECT_FALSE(r.err.empty());
  EXPECT_FALSE(fs::exists(deep));
  EXPECT_FALSE(fs::exists(path("no")));
  // Output is a directory.
  fs::create_directories(path("adir.png"));
  r = run("render " + test::shell_quote(circle_) + " --size 16 -o " + test::shell_quote(path("adir.png")));
  EXPECT_NE(r.code, 0);
  EXPECT_TRUE(fs::is_directory(path("adir.png")));
  // Missing -o.
  r = run("render " + test::shell_quote(circle_) + " --size 16");
  EXPECT_NE(r.code, 0);
  // No temporary files left in the output directory.
  for (const auto& e : fs::directory_iterator(dir_.dir())) {
    const std::string n = e.path().filename().string();
    EXPECT_EQ(n.find(".tmp"), std::string::npos) << "leftover " << n;
  }
}

TEST_F(Cli, FailedRenderKeepsAnExistingOutputIntact) {
  const std::string png = path("keep.png");
  write("keep.png", "original");
  // An unknown input fails before writing; the old file is untouched.
  const RunResult r = run("render " + test::shell_quote(path("nope.vm")) + " --size 16 -o " + test::shell_quote(png));
  EXPECT_NE(r.code, 0);
  EXPECT_EQ(test::read_text(png), "original");
}

// An output that is the input file (under any name) is refused before any work, and the input
// stays as it was; so is an output in a directory that does not exist, before a long conversion.
TEST_F(Cli, OutputsNeverReplaceTheInputAndFailEarly) {
  const std::string vm = test::shell_quote(circle_), before = test::read_text(circle_);
  fs::create_symlink(circle_, path("alias.vm"));
  fs::create_symlink(circle_, path("alias.npy"));  // frep sample writes .npy files only
  for (const std::string& out : {circle_, path("alias.vm"), path("./circle.vm"), path("alias.npy")})
    for (const std::string& cmd : {"sample " + vm + " --grid 4", "export " + vm + " -f c", "offset " + vm + " 0.1"}) {
      if ((cmd.rfind("sample", 0) == 0) != (out == path("alias.npy"))) continue;
      const RunResult r = run(cmd + " -o " + test::shell_quote(out));
      EXPECT_EQ(r.code, 1) << cmd << " -o " << out << "\n" << r.err;
      EXPECT_NE(r.err.find("writing it would replace the input"), std::string::npos) << cmd << "\n" << r.err;
      EXPECT_EQ(test::read_text(circle_), before) << cmd;
    }
  const RunResult png = run("sample " + vm + " --grid 4 -o " + test::shell_quote(path("grid.png")));
  EXPECT_EQ(png.code, 2) << png.err;
  EXPECT_NE(png.err.find("writes NumPy .npy files"), std::string::npos) << png.err;
  for (const std::string& cmd : {"convert " + test::shell_quote(FREP_SOURCE_DIR "/examples/bracket.obj") + " -o " +
                                     test::shell_quote(path("nodir/out.frep")),
                                 "sample " + vm + " --grid 4 -o " + test::shell_quote(path("nodir/out.npy"))}) {
    const RunResult r = run(cmd);
    EXPECT_EQ(r.code, 1) << cmd;
    EXPECT_NE(r.err.find("directory"), std::string::npos) << cmd << "\n" << r.err;
    EXPECT_EQ(r.err.find("converted"), std::string::npos) << "work done before the check: " << r.err;
  }
}

// A field that is not an exact distance: 0.1 (|p| - 1), truthfully declared with L = 0.1.
// Meshing a region wholly inside gives the capped region (the cut has slope 1: it came out
// empty), and an offset does not carry a box grown by the distance (the result reaches 10x
// farther: later commands cut it there). An exact distance's offset keeps its grown box.
TEST_F(Cli, FieldsThatAreNotDistancesKeepTheirShape) {
  const std::string sphere = "_0 var-x\n_1 var-y\n_2 var-z\n_3 square _0\n_4 square _1\n_5 square _2\n_6 add _3 _4\n"
                             "_7 add _6 _5\n_8 sqrt _7\n_9 const 1\n_a sub _8 _9\n";
  write("slow.vm", "# frep: lipschitz 0.1\n# frep: bounds -1 -1 -1 1 1 1\n" + sphere + "_b const 0.1\n_c mul _a _b\n");
  write("exact.vm", "# frep: lipschitz 1\n# frep: bounds -1 -1 -1 1 1 1\n" + sphere);
  RunResult r = run("mesh " + test::shell_quote(path("slow.vm")) + " --bounds=-0.5,-0.5,-0.5,0.5,0.5,0.5 -r 8 -o " +
                    test::shell_quote(path("cube.stl")));
  EXPECT_EQ(r.code, 0) << r.err;
  r = run("offset " + test::shell_quote(path("slow.vm")) + " 0.5 -o " + test::shell_quote(path("grown.vm")));
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("does not say it is a distance field"), std::string::npos) << r.err;
  EXPECT_EQ(test::read_text(path("grown.vm")).find("frep: bounds"), std::string::npos) << test::read_text(path("grown.vm"));
  r = run("offset " + test::shell_quote(path("exact.vm")) + " 0.5 -o " + test::shell_quote(path("grown_exact.vm")));
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find("does not say it is a distance field"), std::string::npos) << r.err;
  EXPECT_NE(test::read_text(path("grown_exact.vm")).find("frep: bounds"), std::string::npos);
  // Meshed, the slow offset is whole: its radius is 6 (0.1 (r - 1) = 0.5). Its vertices lie on the
  // sphere, so the box of the mesh is within a fraction of a cell (0.5) of +-6.
  r = run("offset " + test::shell_quote(path("slow.vm")) + " 0.5 -r 24 -o " + test::shell_quote(path("grown.stl")));
  EXPECT_EQ(r.code, 0) << r.err;
  r = run("check " + test::shell_quote(path("grown.stl")));
  const std::size_t at = r.out.find("box: (");
  ASSERT_NE(at, std::string::npos) << r.out;
  EXPECT_NEAR(std::stod(r.out.substr(at + 6)), -6.0, 0.02) << r.out;
}

// --quiet: nothing but errors, including the line saying a mesh input was converted.
TEST_F(Cli, QuietMeansQuiet) {
  const std::string obj = test::shell_quote(FREP_SOURCE_DIR "/examples/bracket.obj");
  for (const std::string& cmd : {"mesh " + obj + " -r 8 -q -o " + test::shell_quote(path("q.stl")),
                                 "offset " + obj + " 0.5 -r 8 -q -o " + test::shell_quote(path("q2.stl")),
                                 "render " + obj + " --3d -s 32 -q -o " + test::shell_quote(path("q.png"))}) {
    const RunResult r = run(cmd);
    EXPECT_EQ(r.code, 0) << cmd << "\n" << r.err;
    EXPECT_EQ(r.out + r.err, "") << cmd;
  }
}

// An empty picture says which region it showed: usually the shape is elsewhere.
TEST_F(Cli, EmptyPicturesSayWhy) {
  write("far.vm", "_0 var-x\n_1 const 3\n_2 sub _0 _1\n_3 square _2\n_4 var-y\n_5 square _4\n_6 var-z\n"
                  "_7 square _6\n_8 add _3 _5\n_9 add _8 _7\n_a sqrt _9\n_b const 0.5\n_c sub _a _b\n");
  const std::string far = test::shell_quote(path("far.vm"));
  RunResult r = run("render " + far + " --3d --size 32 -o " + test::shell_quote(path("far.png")));
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("nothing of " + path("far.vm") + " is in view"), std::string::npos) << r.err;
  r = run("render " + far + " --size 32 -o " + test::shell_quote(path("far2d.png")));
  EXPECT_NE(r.err.find("is nowhere negative on z = 0 over [-1,1]^2"), std::string::npos) << r.err;
  r = run("render " + far + " --3d --size 32 --bounds 2,-1,-1,4,1,1 -o " + test::shell_quote(path("near.png")));
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
}

// What a mesh reader tolerates is said on stderr, naming the file, by every command that reads
// the mesh: here an ASCII STL cut between two facets (no 'endsolid').
TEST_F(Cli, MeshReaderWarningsReachTheUser) {
  std::string stl = "solid cut\n";
  const char* tris[4][3] = {{"0 0 0", "0 1 0", "1 0 0"}, {"0 0 0", "1 0 0", "0 0 1"},
                            {"0 0 0", "0 0 1", "0 1 0"}, {"1 0 0", "0 1 0", "0 0 1"}};
  for (const auto& t : tris) {
    stl += "facet normal 0 0 0\nouter loop\n";
    for (const char* v : t) stl += std::string("vertex ") + v + "\n";
    stl += "endloop\nendfacet\n";
  }
  write("cut.stl", stl);
  const std::string file = test::shell_quote(path("cut.stl"));
  const std::string warning = "frep: warning: " + path("cut.stl") + ": ASCII STL ends without 'endsolid' (truncated file?)";
  for (const std::string& cmd : {"check " + file, "info " + file, "sample " + file + " --grid 4 -o " + test::shell_quote(path("c.npy"))}) {
    const RunResult r = run(cmd);
    EXPECT_EQ(r.code, 0) << cmd << "\n" << r.err;
    EXPECT_NE(r.err.find(warning), std::string::npos) << cmd << "\n" << r.err;
  }
}

}  // namespace
}  // namespace frep

namespace frep {
namespace {

// Exit codes as the README documents them: 0 success, 1 bad input, 2 bad command line.
TEST_F(Cli, ExitCodesDistinguishInputErrorsFromUsageErrors) {
  EXPECT_EQ(run("").code, 2);                                   // no subcommand
  EXPECT_EQ(run("frobnicate").code, 2);                         // unknown subcommand
  EXPECT_EQ(run("render " + test::shell_quote(circle_)).code, 2);           // missing -o
  EXPECT_EQ(run("render " + test::shell_quote(circle_) + " -o x.png --size 0").code, 2);
  EXPECT_EQ(run("info " + test::shell_quote(path("missing.vm"))).code, 1);  // input error
  const RunResult bad_ext = run("render " + test::shell_quote(circle_) + " -o " + test::shell_quote(path("x.jpg")));
  EXPECT_EQ(bad_ext.code, 1);
  EXPECT_NE(bad_ext.err.find("x.jpg"), std::string::npos) << bad_ext.err;
  EXPECT_EQ(run("--version").code, 0);
}

}  // namespace
}  // namespace frep
