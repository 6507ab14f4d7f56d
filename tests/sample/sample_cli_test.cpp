// End-to-end tests of `frep sample`: run the built binary on the shipped bracket (mesh and its
// converted expression), read back what it writes (with frep's reader and, when python3 has
// NumPy, numpy.load), and check exit codes, messages and atomic replacement for bad arguments
// and inputs.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "frep/io/npy.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/sample/grid.hpp"
#include "frep/mesh/mesh_field.hpp"

#include "cli_test_util.hpp"

namespace frep {
namespace {

using test::CliRun;

namespace fs = std::filesystem;

const std::string kBracket = FREP_SOURCE_DIR "/examples/bracket.obj";

int shell(const std::string& cmd) {
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class SampleCommand : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return dir_.path(name); }

  CliRun run(const std::string& args) { return test::run_frep(dir_, args); }
  // Files in the work directory other than the logs (no temporary file may be left behind).
  std::vector<std::string> files() const {
    std::vector<std::string> v;
    for (const auto& e : fs::directory_iterator(dir_.dir()))
      if (e.path().filename() != "log") v.push_back(e.path().filename().string());
    std::sort(v.begin(), v.end());
    return v;
  }

  test::ScratchDir dir_;
};

// The mesh grid at the default bounds, then the converted expression over the printed bounds:
// the same field within 1e-5 of the diagonal.
TEST_F(SampleCommand, MeshAndExpressionGrids) {
  const std::string mesh_npy = path("mesh.npy"), expr = path("bracket.frep"), expr_npy = path("expr.npy");
  CliRun r = run("sample '" + kBracket + "' --grid 20 -o '" + mesh_npy + "'");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("20 x 20 x 20"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("closest point transform"), std::string::npos) << r.out;
  const std::size_t at = r.out.find("bounds ");
  ASSERT_NE(at, std::string::npos) << r.out;
  std::string bounds = r.out.substr(at + 7);
  bounds = bounds.substr(0, bounds.find('\n'));

  const MeshField field(read_mesh(kBracket));
  const GridSpec grid = cube_grid(default_mesh_bounds(field.box()), 20);
  const NpyArray m = read_npy(mesh_npy);
  ASSERT_EQ(m.shape, (std::vector<std::size_t>{20, 20, 20}));
  for (int i = 0; i < 20; i += 3)
    for (int j = 0; j < 20; j += 2)
      for (int k = 0; k < 20; ++k)
        ASSERT_EQ(m.data[grid.index(i, j, k)],
                  static_cast<float>(field.signed_distance({grid.coord(0, i), grid.coord(1, j), grid.coord(2, k)})))
            << i << " " << j << " " << k;

  ASSERT_EQ(run("convert '" + kBracket + "' -o '" + expr + "'").code, 0);
  r = run("sample '" + expr + "' --grid 20 --bounds=" + bounds + " -o '" + expr_npy + "' -q");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, "");
  const NpyArray e = read_npy(expr_npy);
  ASSERT_EQ(e.shape, m.shape);
  double worst = 0;
  for (std::size_t i = 0; i < e.data.size(); ++i) worst = std::max(worst, std::fabs(double(e.data[i]) - m.data[i]));
  EXPECT_LE(worst, 1e-5 * length(field.box().size()));
}

TEST_F(SampleCommand, PointsShape) {
  const std::string out = path("pts.npy");
  CliRun r = run("sample '" + kBracket + "' --points 100 --near-surface 50 --sigma 0.01 --seed 3 -o '" + out + "'");
  ASSERT_EQ(r.code, 0) << r.err;
  const NpyArray a = read_npy(out);
  EXPECT_EQ(a.shape, (std::vector<std::size_t>{150, 4}));
  const std::string again = path("again.npy");
  ASSERT_EQ(run("sample '" + kBracket + "' --points 100 --near-surface 50 --sigma 0.01 --seed 3 -q -o '" + again + "'").code, 0);
  EXPECT_EQ(test::read_text(out), test::read_text(again));  // the seed fixes the file
}

// numpy.load reads the grid with the documented shape, dtype and order.
TEST_F(SampleCommand, NumpyLoadsIt) {
  std::string python;
  for (const char* p : {"python3", "/usr/bin/python3"})
    if (shell(std::string(p) + " -c 'import numpy' >/dev/null 2>&1") == 0) {
      python = p;
      break;
    }
  if (python.empty()) GTEST_SKIP() << "no python3 with numpy (python3-numpy) found";
  const std::string out = path("g.npy");
  ASSERT_EQ(run("sample '" + kBracket + "' --grid 6 -q -o '" + out + "'").code, 0);
  const NpyArray a = read_npy(out);
  // Python checks the shape, the dtype and every value (written here with round-trip precision),
  // indexed as a[i][j][k].
  std::ostringstream want;
  want.precision(9);
  want << "[";
  for (float v : a.data) want << v << ",";
  want << "]";
  std::ofstream(path("check.py")) << "import numpy, sys\n"
                                  << "a = numpy.load(sys.argv[1])\n"
                                  << "assert a.shape == (6, 6, 6), a.shape\n"
                                  << "assert a.dtype == numpy.float32, a.dtype\n"
                                  << "w = numpy.array(" << want.str() << ", dtype=numpy.float32).reshape(6, 6, 6)\n"
                                  << "assert (a == w).all()\n"
                                  << "assert a[1][2][3] == w.flat[(1 * 6 + 2) * 6 + 3]\n"
                                  << "numpy.save(sys.argv[2], numpy.arange(12, dtype=numpy.float32).reshape(3, 4))\n";
  ASSERT_EQ(shell(python + " '" + path("check.py") + "' '" + out + "' '" + path("np.npy") + "'"), 0);
  // And frep reads what NumPy writes.
  const NpyArray b = read_npy(path("np.npy"));
  EXPECT_EQ(b.shape, (std::vector<std::size_t>{3, 4}));
  for (std::size_t i = 0; i < 12; ++i) EXPECT_EQ(b.data[i], static_cast<float>(i));
}

TEST_F(SampleCommand, Errors) {
  const std::string out = path("out.npy");
  const std::string b = "'" + kBracket + "'";
  // Bad command lines: exit 2, naming the option.
  CliRun r = run("sample " + b + " -o '" + out + "'");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--grid"), std::string::npos) << r.err;
  r = run("sample " + b + " --grid 1 -o '" + out + "'");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--grid"), std::string::npos) << r.err;
  EXPECT_EQ(run("sample " + b + " --grid 5000 -o '" + out + "'").code, 2);
  EXPECT_EQ(run("sample " + b + " --grid 4 --points 5 -o '" + out + "'").code, 2);
  r = run("sample " + b + " --grid 4 --bounds 1,1,1,0,0,0 -o '" + out + "'");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--bounds"), std::string::npos) << r.err;
  EXPECT_EQ(run("sample " + b + " --grid 4 --bounds 0,0,0,1,1 -o '" + out + "'").code, 2);
  EXPECT_EQ(run("sample " + b + " --grid 4 --bounds 0,0,0,1,1,nan -o '" + out + "'").code, 2);
  r = run("sample " + b + " --near-surface 10 -o '" + out + "'");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--sigma"), std::string::npos) << r.err;
  EXPECT_EQ(run("sample " + b + " --near-surface 10 --sigma -1 -o '" + out + "'").code, 2);
  EXPECT_EQ(run("sample " + b + " --grid 4 --method fast -o '" + out + "'").code, 2);
  EXPECT_TRUE(files().empty());

  // Bad inputs: exit 1, naming the file.
  const std::string missing = path("missing.obj");
  r = run("sample '" + missing + "' --grid 4 -o '" + out + "'");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find(missing), std::string::npos) << r.err;
  const std::string open = path("open.obj");
  std::ofstream(open) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n";  // a tetrahedron without its fourth face
  r = run("sample '" + open + "' --grid 4 --method cpt -o '" + out + "'");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find(open + ": the closest point transform needs a valid solid"), std::string::npos) << r.err;
  const std::string ball = path("ball.vm");
  std::ofstream(ball) << "_0 var-x\n_1 var-y\n_2 var-z\n_3 square _0\n_4 square _1\n_5 square _2\n_6 add _3 _4\n"
                         "_7 add _6 _5\n_8 sqrt _7\n_9 const 0.5\n_a sub _8 _9\n";
  r = run("sample '" + ball + "' --near-surface 10 --sigma 0.01 --bounds 2,2,2,3,3,3 -o '" + out + "'");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find(ball + ": found only 0 of 10 surface points"), std::string::npos) << r.err;
  const std::string garbage = path("garbage.vm");
  std::ofstream(garbage) << "_0 var-x\n_1 frobnicate _0\n";
  r = run("sample '" + garbage + "' --grid 4 -o '" + out + "'");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find(garbage), std::string::npos) << r.err;
  // Sizes no machine holds are refused before any work, saying how much memory they need.
  for (const char* big : {"--grid 4096", "--points 4000000000000", "--points 1 --near-surface 4000000000000 --sigma 0.1"}) {
    r = run("sample " + b + " " + big + " -o '" + out + "'");
    EXPECT_EQ(r.code, 1) << big << ": " << r.err;
    EXPECT_NE(r.err.find("GB of memory, more than this machine's"), std::string::npos) << big << ": " << r.err;
  }
  r = run("sample '" + ball + "' --grid 4096 -o '" + out + "'");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find(ball + ": a grid of 4096 x 4096 x 4096 samples needs about 274.9 GB"), std::string::npos) << r.err;
  r = run("sample " + b + " --grid 4 -o '" + path("no/such/dir/out.npy") + "'");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("no/such/dir/out.npy"), std::string::npos) << r.err;
  // No output appeared for any failure.
  EXPECT_EQ(files(), (std::vector<std::string>{"ball.vm", "garbage.vm", "open.obj"}));
}

// --truncate D: the untruncated grid clamped to [-D, D], bit for bit, for a mesh (the closest
// point transform) and an expression (the pruned evaluator); the summary says it is truncated.
TEST_F(SampleCommand, Truncated) {
  const std::string full = path("full.npy"), cut = path("cut.npy");
  const std::string ball = path("ball.vm");
  std::ofstream(ball) << "_0 var-x\n_1 var-y\n_2 var-z\n_3 square _0\n_4 square _1\n_5 square _2\n_6 add _3 _4\n"
                         "_7 add _6 _5\n_8 sqrt _7\n_9 const 0.5\n_a sub _8 _9\n";
  for (const std::string& input : {kBracket, ball}) {
    for (const char* d : {"0.01", "0.05", "0.2"}) {
      ASSERT_EQ(run("sample '" + input + "' --grid 24 -q -o '" + full + "'").code, 0);
      const CliRun r = run("sample '" + input + "' --grid 24 --truncate " + d + " -o '" + cut + "'");
      ASSERT_EQ(r.code, 0) << r.err;
      EXPECT_NE(r.out.find(std::string("truncated at +-") + d), std::string::npos) << r.out;
      const NpyArray a = read_npy(full), b = read_npy(cut);
      ASSERT_EQ(a.shape, b.shape);
      const double dv = std::stod(d);
      std::size_t clamped = 0;
      for (std::size_t i = 0; i < a.data.size(); ++i) {
        const float want = static_cast<float>(std::clamp(static_cast<double>(a.data[i]), -dv, dv));
        ASSERT_EQ(std::bit_cast<std::uint32_t>(b.data[i]), std::bit_cast<std::uint32_t>(want))
            << input << " --truncate " << d << ": sample " << i << " = " << b.data[i] << ", want " << want;
        clamped += std::fabs(a.data[i]) > dv;
      }
      EXPECT_GT(clamped, 0u) << input << " " << d;
    }
  }
  // In the help text.
  const CliRun h = run("sample --help");
  EXPECT_EQ(h.code, 0);
  EXPECT_NE(h.out.find("--truncate"), std::string::npos) << h.out;
}

// --truncate needs a grid and a finite distance > 0: anything else is a bad command line.
TEST_F(SampleCommand, TruncateErrors) {
  const std::string out = path("out.npy");
  const std::string b = "'" + kBracket + "' -o '" + out + "'";
  for (const char* bad : {"--points 10 --truncate 0.1", "--near-surface 10 --sigma 0.01 --truncate 0.1",
                          "--truncate 0.1", "--grid 8 --truncate 0", "--grid 8 --truncate -0.1",
                          "--grid 8 --truncate nan", "--grid 8 --truncate inf", "--grid 8 --truncate x"}) {
    const CliRun r = run("sample " + b + " " + bad);
    EXPECT_EQ(r.code, 2) << bad << ": " << r.err;
    EXPECT_NE(r.err.find("--truncate"), std::string::npos) << bad << ": " << r.err;
  }
  EXPECT_TRUE(files().empty());
}

// Outputs are replaced whole or not at all: a failing run leaves the old file, a good run
// replaces it, and neither leaves a temporary file beside it.
TEST_F(SampleCommand, AtomicOutput) {
  const std::string out = path("out.npy");
  std::ofstream(out) << "old contents";
  const std::string open = path("open.obj");
  std::ofstream(open) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 3 2\n";
  EXPECT_EQ(run("sample '" + open + "' --grid 4 --method cpt -o '" + out + "'").code, 1);
  EXPECT_EQ(test::read_text(out), "old contents");
  ASSERT_EQ(run("sample '" + kBracket + "' --grid 4 -q -o '" + out + "'").code, 0);
  EXPECT_EQ(read_npy(out).shape, (std::vector<std::size_t>{4, 4, 4}));
  EXPECT_EQ(files(), (std::vector<std::string>{"open.obj", "out.npy"}));
}

}  // namespace
}  // namespace frep
