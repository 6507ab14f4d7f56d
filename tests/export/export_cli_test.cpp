// End-to-end tests of `frep export`: every format through the built binary equals the library's
// output, the format follows the extension, '-' writes to standard output, and bad input or bad
// options give the documented exit codes without leaving a file behind.
#include <gtest/gtest.h>

#include <sstream>

#include "export_test_util.hpp"
#include "frep/export/c_source.hpp"
#include "frep/export/glsl.hpp"
#include "frep/export/latex.hpp"
#include "frep/expr/expr.hpp"
#include "frep/script/load.hpp"
#include "frep/io/vm.hpp"

namespace frep::test {
namespace {

class ExportCli : public ::testing::Test {
 protected:
  void SetUp() override {
    Graph g;
    auto x = g.x(), y = g.y(), z = g.z();
    auto ball = sqrt(square(x) + square(y) + square(z)) - 0.5f;
    model_ = dir_.path("ball.vm");
    save_vm(model_, g, if_nonzero_else(compare(z, 0.0f), ball, max(ball, -z)).id());
  }

  CliRun run(const std::string& args) { return run_frep(dir_, "export " + args); }

  // What the library writes for the model, as the CLI calls it.
  std::string library(const std::string& format) {
    const Model m = load_expression(model_);
    std::ostringstream out;
    if (format == "c") {
      CExportOptions o;
      o.source = "ball.vm";
      write_c(out, *m.graph, m.root, o);
    } else if (format == "glsl") {
      GlslOptions o;
      o.source = "ball.vm";
      write_glsl(out, *m.graph, m.root, o);
    } else if (format == "shadertoy") {
      ShadertoyOptions o;
      o.glsl.source = "ball.vm";
      write_shadertoy(out, *m.graph, m.root, o);
    } else {
      LatexOptions o;
      o.source = "ball.vm";
      write_latex(out, *m.graph, m.root, o);
    }
    return out.str();
  }

  ScratchDir dir_;
  std::string model_;
};

TEST_F(ExportCli, EveryFormatWritesWhatTheLibraryWrites) {
  for (const char* format : {"c", "glsl", "shadertoy", "latex"}) {
    const std::string out = dir_.path(std::string("out_") + format);
    const CliRun r = run(shell_quote(model_) + " --format " + format + " -o " + shell_quote(out));
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("wrote " + out), std::string::npos) << r.out;
    EXPECT_EQ(read_text(out), library(format)) << format;
  }
}

TEST_F(ExportCli, ExtensionChoosesTheFormatAndDashIsStandardOutput) {
  for (auto [ext, format] : {std::pair{".c", "c"}, {".h", "c"}, {".glsl", "glsl"}, {".tex", "latex"}}) {
    const std::string out = dir_.path(std::string("shape") + ext);
    EXPECT_EQ(run(shell_quote(model_) + " -q -o " + shell_quote(out)).code, 0) << ext;
    EXPECT_EQ(read_text(out), library(format)) << ext;
  }
  const CliRun r = run(shell_quote(model_) + " -f c -o -");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, library("c"));
}

TEST_F(ExportCli, OptionsReachTheExporters) {
  CliRun r = run(shell_quote(model_) + " -f c --name ball_sdf -o -");
  EXPECT_NE(r.out.find("float ball_sdf(float x, float y, float z)"), std::string::npos) << r.out;
  r = run(shell_quote(model_) + " -f latex --fragment --digits 2 -o -");
  EXPECT_EQ(r.out.find("\\documentclass"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\\begin{align*}"), std::string::npos) << r.out;
  r = run(shell_quote(model_) + " -f shadertoy --radius 2 --step-scale 0.5 --max-steps 99 -o -");
  for (const char* want : {"#define FREP_RADIUS 2.0", "#define FREP_STEP_SCALE 0.5", "#define FREP_MAX_STEPS 99"})
    EXPECT_NE(r.out.find(want), std::string::npos) << want;
  const char* checked = "return (isnan(a) || isnan(b)) ? a + b : (a > b ? a : b);";
  EXPECT_EQ(r.out.find(checked), std::string::npos) << "shadertoy: GLSL's max by default";
  EXPECT_NE(run(shell_quote(model_) + " -f shadertoy --nan-checks -o -").out.find(checked), std::string::npos);
  EXPECT_NE(run(shell_quote(model_) + " -f glsl -o -").out.find(checked), std::string::npos) << "glsl: exact by default";
  EXPECT_EQ(run(shell_quote(model_) + " -f glsl --no-nan-checks -o -").out.find(checked), std::string::npos);
}

TEST_F(ExportCli, ErrorsHaveTheDocumentedExitCodesAndLeaveNoFile) {
  const std::string out = dir_.path("never.c");
  struct Case {
    std::string args;
    int code;
    const char* message;
  };
  const Case cases[] = {
      {shell_quote(dir_.path("missing.vm")) + " -o " + shell_quote(out), 1, "missing.vm"},
      {shell_quote(model_) + " -o " + shell_quote(dir_.path("never.txt")), 2, "--format"},
      {shell_quote(model_) + " -f fortran -o " + shell_quote(out), 2, "fortran"},
      {shell_quote(model_) + " -f c --name 'my sdf' -o " + shell_quote(out), 2, "not a C identifier"},
      {shell_quote(model_) + " -f glsl --name gl_sdf -o " + shell_quote(out), 2, "GLSL"},
      // Names that would not compile: keywords, types, the exports' own helpers.
      {shell_quote(model_) + " -f c --name int -o " + shell_quote(out), 2, "is reserved"},
      {shell_quote(model_) + " -f c --name frep_min -o " + shell_quote(out), 2, "is reserved"},
      {shell_quote(model_) + " -f glsl --name float -o " + shell_quote(out), 2, "is reserved"},
      {shell_quote(model_) + " -f shadertoy --name mainImage -o " + shell_quote(out), 2, "is reserved"},
      {shell_quote(model_) + " -f c --name sqrtf -o " + shell_quote(out), 2, "is reserved"},
      {shell_quote(model_) + " -f glsl --name mod -o " + shell_quote(out), 2, "is reserved"},
      {shell_quote(model_) + " -f glsl --name distance -o " + shell_quote(out), 2, "is reserved"},
      {shell_quote(model_) + " -f c --fragment -o " + shell_quote(out), 2, "--fragment"},
      {shell_quote(model_) + " -f latex --no-nan-checks -o " + shell_quote(out), 2, "--nan-checks"},
      {shell_quote(model_) + " -f shadertoy --step-scale 2 -o " + shell_quote(out), 2, "step-scale"},
      {shell_quote(model_) + " -f c -o " + shell_quote(dir_.path("no/such/dir/x.c")), 1, "no/such/dir"},
  };
  for (const Case& c : cases) {
    const CliRun r = run(c.args);
    EXPECT_EQ(r.code, c.code) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_FALSE(fs::exists(out)) << c.args;
  }
  write_text(dir_.path("bad.vm"), "_0 var-x\n_1 frobnicate _0\n");
  const CliRun r = run(shell_quote(dir_.path("bad.vm")) + " -f c -o " + shell_quote(out));
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("bad.vm:2"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace frep::test
