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
#include "cli_test_util.hpp"
#include "rhai_test_util.hpp"

namespace frep {
namespace {

namespace fs = std::filesystem;

class RhaiCli : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return dir_.path(name); }
  void write(const std::string& name, const std::string& text) { test::write_text(path(name), text); }
  std::string slurp(const std::string& name) { return test::read_text(path(name)); }
  // Runs `frep args`; returns the exit code, with stdout and stderr in last_.
  int run(const std::string& args) {
    last_ = test::run_frep(dir_, args);
    return last_.code;
  }
  test::ScratchDir dir_;
  test::CliRun last_;
};

const char* kScript =
    "// a rounded square with a hole\n"
    "fn rounded(e, r) { e - r }\n"
    "let s = rectangle([-0.5, -0.5], [0.5, 0.5]);\n"
    "difference(rounded(s, 0.1), circle([0.1, 0], 0.2))\n";

TEST_F(RhaiCli, EvalPrintsTheScriptsValues) {
  write("m.rhai", kScript);
  write("pts.txt", "0 0\n0.1 0\n0.55 0.55\n-0.3 0.2\n");
  ASSERT_EQ(run("eval '" + path("m.rhai") + "' --points '" + path("pts.txt") + "'"), 0) << last_.err;
  const Model m = test::run_rhai(kScript);
  std::istringstream out(last_.out);
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
  ASSERT_EQ(run("render '" + path("m.rhai") + "' --size 64 -q -o '" + path("a.pgm") + "'"), 0) << last_.err;
  ASSERT_EQ(run("render '" + path("m.vm") + "' --size 64 -q -o '" + path("b.pgm") + "'"), 0) << last_.err;
  EXPECT_EQ(slurp("a.pgm"), slurp("b.pgm"));
  EXPECT_GT(slurp("a.pgm").size(), 64u * 64u);
  ASSERT_EQ(run("info '" + path("m.rhai") + "'"), 0);
  EXPECT_NE(last_.out.find("nodes: " + std::to_string(reachable_nodes(*m.graph, m.root).size())),
            std::string::npos)
      << last_.out;
}

TEST_F(RhaiCli, BadScriptExitsWithOneAndThePosition) {
  write("bad.rhai", "let a = circle();\nlet b = a +;\n");
  EXPECT_EQ(run("info '" + path("bad.rhai") + "'"), 1);
  EXPECT_NE(last_.err.find("bad.rhai:2: column 12: expected an expression"), std::string::npos) << last_.err;
  write("cmp.rhai", "if x < 0 { x } else { -x }\n");
  EXPECT_EQ(run("info '" + path("cmp.rhai") + "'"), 1);
  EXPECT_NE(last_.err.find("cmp.rhai:1: column 6: cannot compare expressions"), std::string::npos) << last_.err;
}

}  // namespace
}  // namespace frep
