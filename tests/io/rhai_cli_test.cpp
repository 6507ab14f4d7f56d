// The command-line tool takes `.rhai` wherever it takes an expression (through load_expression):
// `eval` prints the script's values, `render` draws the same image as for the equivalent `.vm`,
// `info` counts its nodes, and a bad script exits with code 1 naming the line and column.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "frep/io/vm.hpp"
#include "rhai_test_util.hpp"

namespace frep {
namespace {

namespace fs = std::filesystem;

class RhaiCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("frep_rhai_cli_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  void write(const std::string& name, const std::string& text) { std::ofstream(path(name)) << text; }
  std::string slurp(const std::string& name) {
    std::ifstream in(path(name), std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  // Runs `frep args`; returns the exit code, with stdout and stderr in out.txt and err.txt.
  int run(const std::string& args) {
    const std::string cmd = std::string(FREP_CLI_PATH) + " " + args + " > '" + path("out.txt") + "' 2> '" + path("err.txt") + "'";
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  fs::path dir_;
};

const char* kScript =
    "// a rounded square with a hole\n"
    "fn rounded(e, r) { e - r }\n"
    "let s = rectangle([-0.5, -0.5], [0.5, 0.5]);\n"
    "difference(rounded(s, 0.1), circle([0.1, 0], 0.2))\n";

TEST_F(RhaiCli, EvalPrintsTheScriptsValues) {
  write("m.rhai", kScript);
  write("pts.txt", "0 0\n0.1 0\n0.55 0.55\n-0.3 0.2\n");
  ASSERT_EQ(run("eval '" + path("m.rhai") + "' --points '" + path("pts.txt") + "'"), 0) << slurp("err.txt");
  const Model m = test::run_rhai(kScript);
  std::istringstream out(slurp("out.txt"));
  const float pts[4][2] = {{0, 0}, {0.1f, 0}, {0.55f, 0.55f}, {-0.3f, 0.2f}};
  for (const auto& p : pts) {
    float v = 0;
    ASSERT_TRUE(out >> v);
    EXPECT_EQ(v, test::eval_graph<float>(*m.graph, m.root, p[0], p[1], 0)) << p[0] << " " << p[1];
  }
}

TEST_F(RhaiCli, RenderEqualsTheVmRenderAndInfoCounts) {
  write("m.rhai", kScript);
  const Model m = test::run_rhai(kScript);
  save_vm(path("m.vm"), *m.graph, m.root);
  ASSERT_EQ(run("render '" + path("m.rhai") + "' --size 64 -q -o '" + path("a.pgm") + "'"), 0) << slurp("err.txt");
  ASSERT_EQ(run("render '" + path("m.vm") + "' --size 64 -q -o '" + path("b.pgm") + "'"), 0) << slurp("err.txt");
  EXPECT_EQ(slurp("a.pgm"), slurp("b.pgm"));
  EXPECT_GT(slurp("a.pgm").size(), 64u * 64u);
  ASSERT_EQ(run("info '" + path("m.rhai") + "'"), 0);
  EXPECT_NE(slurp("out.txt").find("nodes: " + std::to_string(reachable_nodes(*m.graph, m.root).size())),
            std::string::npos)
      << slurp("out.txt");
}

TEST_F(RhaiCli, BadScriptExitsWithOneAndThePosition) {
  write("bad.rhai", "let a = circle();\nlet b = a +;\n");
  EXPECT_EQ(run("info '" + path("bad.rhai") + "'"), 1);
  EXPECT_NE(slurp("err.txt").find("bad.rhai:2: column 12: expected an expression"), std::string::npos) << slurp("err.txt");
  write("cmp.rhai", "if x < 0 { x } else { -x }\n");
  EXPECT_EQ(run("info '" + path("cmp.rhai") + "'"), 1);
  EXPECT_NE(slurp("err.txt").find("cmp.rhai:1: column 6: cannot compare expressions"), std::string::npos) << slurp("err.txt");
}

}  // namespace
}  // namespace frep
