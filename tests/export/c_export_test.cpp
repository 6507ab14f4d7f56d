// Tests of the C exporter: the generated C99 compiles without warnings with the system compiler
// and gives exactly PointEvaluator's values, on random expressions over every opcode (special
// values included) and on the shared models; shared subexpressions are computed once.
#include <gtest/gtest.h>

#include <sstream>

#include "export_test_util.hpp"
#include "frep/error.hpp"
#include "frep/export/c_source.hpp"
#include "frep/expr/expr.hpp"
#include "frep/script/load.hpp"
#include "test_util.hpp"

namespace frep::test {
namespace {

// Writes the functions into one C file with a driver, compiles it, evaluates at `xyz`.
std::vector<float> compile_and_run(const ScratchDir& dir, const Graph& g, const std::vector<NodeId>& roots,
                                   const std::vector<float>& xyz, const std::string& compiler, const std::string& flags) {
  std::ostringstream src;
  std::vector<std::string> names;
  for (std::size_t i = 0; i < roots.size(); ++i) {
    CExportOptions opt;
    opt.function_name = "f" + std::to_string(i);
    names.push_back(opt.function_name);
    write_c(src, g, roots[i], opt);  // the helpers' include guard lets several share a file
  }
  src << driver_main(names, "", "p[0], p[1], p[2]");
  const std::string c = dir.path("exported.c"), exe = dir.path("exported");
  write_text(c, src.str());
  const CommandResult r = run_command(compiler + " " + flags + " -o " + shell_quote(exe) + " " + shell_quote(c) + " -lm",
                                      dir.path("cc.log"));
  EXPECT_EQ(r.code, 0) << compiler << " " << flags << " failed:\n" << r.output.substr(0, 4000);
  if (r.code != 0) return {};
  EXPECT_EQ(r.output, "") << "compiler warnings:\n" << r.output.substr(0, 4000);
  return run_driver(dir, exe, xyz, roots.size());
}

const char* kStrict = "-std=c99 -O2 -ffp-contract=off -Wall -Wextra -pedantic";

TEST(CExport, RandomExpressionsOverEveryOpcodeMatchBitForBit) {
  FREP_REQUIRE_PROGRAM("cc");
  ScratchDir dir;
  Graph g;
  const std::vector<NodeId> roots = random_expressions(g, 11, 120);
  const std::vector<bool> used = ops_used(g, roots);
  for (int op = 0; op < kOpCount; ++op) EXPECT_TRUE(used[op]) << "no random expression uses " << op_name(static_cast<Op>(op));
  const std::vector<float> xyz = random_points(12, 300);
  const std::vector<float> values = compile_and_run(dir, g, roots, xyz, "cc", kStrict);
  EXPECT_EQ(count_mismatches(g, roots, xyz, values, "C export"), 0);
}

// clang contracts a * b + c into an FMA by default; the generated pragma must stop it. Built for
// this CPU, so the check has teeth where the CPU has FMA.
TEST(CExport, ClangWithItsDefaultContractionStillMatches) {
  FREP_REQUIRE_PROGRAM("clang");
  ScratchDir dir;
  Graph g;
  const std::vector<NodeId> roots =
      random_expressions(g, 21, 60, {Op::Add, Op::Sub, Op::Mul, Op::Div, Op::Square, Op::Sqrt, Op::Neg, Op::Min});
  const std::vector<float> xyz = random_points(22, 300);
  const std::vector<float> values = compile_and_run(dir, g, roots, xyz, "clang", "-std=c99 -O2 -march=native -w");
  EXPECT_EQ(count_mismatches(g, roots, xyz, values, "C export (clang)"), 0);
}

TEST(CExport, SharedModelsMatchBitForBit) {
  FREP_REQUIRE_PROGRAM("cc");
  for (const char* name : {"bear.vm", "prospero.vm", "tanglecube.vm", "quarter.vm"}) {
    SCOPED_TRACE(name);
    if (!have_data(name)) {
      std::printf("[ SKIPPED  ] shared data not found: %s\n", data_file(name).c_str());
      continue;
    }
    ScratchDir dir;
    const Model m = load_expression(data_file(name));
    const std::vector<float> xyz = model_points(12, 500);
    // GCC -O2 takes over 10 s on Prospero's 7866-statement function; -O0 computes the same values.
    const std::string flags = std::string(name) == "prospero.vm" ? "-std=c99 -O0 -Wall -Wextra -pedantic" : kStrict;
    const std::vector<float> values = compile_and_run(dir, *m.graph, {m.root}, xyz, "cc", flags);
    EXPECT_EQ(count_mismatches(*m.graph, {m.root}, xyz, values, name), 0);
  }
}

std::string export_c(const Graph& g, NodeId root, const std::string& name = "frep_sdf") {
  std::ostringstream out;
  CExportOptions opt;
  opt.function_name = name;
  write_c(out, g, root, opt);
  return out.str();
}

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = s.find(what); at != std::string::npos; at = s.find(what, at + 1)) ++n;
  return n;
}

std::string body(const std::string& c) { return c.substr(c.find("float frep_sdf(")); }

// Names of <math.h> are refused (the code would not compile), GLSL's built-ins are fine in C.
TEST(CExport, MathNamesAreReservedGlslOnesAreNot) {
  Graph g;
  const NodeId f = (g.x() - 1.0f).id();
  EXPECT_THROW(export_c(g, f, "sqrtf"), InputError);
  EXPECT_THROW(export_c(g, f, "hypot"), InputError);
  EXPECT_NE(export_c(g, f, "distance").find("float distance(float x, float y, float z)"), std::string::npos);
  EXPECT_NE(export_c(g, f, "smoothstep").find("float smoothstep("), std::string::npos);
}

TEST(CExport, SharedSubexpressionsAreComputedOnce) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  auto r = sqrt(square(x) + square(y));  // used three times
  auto f = max(r - 1.0f, min(r * 2.0f, z - r));
  const std::string b = body(export_c(g, f.id()));
  EXPECT_EQ(count(b, "sqrtf("), 1u) << b;
  EXPECT_EQ(count(b, "const float t"), 1u) << b;
  // Single-use nodes stay inline, with only the parentheses C needs.
  EXPECT_NE(b.find("frep_max(t0 - 1.0f, frep_min(t0 * 2.0f, z - t0))"), std::string::npos) << b;
}

TEST(CExport, ParenthesesFollowF32EvaluationOrder) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  // f32 arithmetic is not associative: x - (y - z) and x / (y * z) must keep their parentheses.
  const std::string b = body(export_c(g, (x - (y - z) + x / (y * z) - (-x) * (y + z) - (x - y) * -2.5f).id()));
  EXPECT_NE(b.find("x - (y - z)"), std::string::npos) << b;
  EXPECT_NE(b.find("x / (y * z)"), std::string::npos) << b;
  EXPECT_NE(b.find("(y + z) * (-x)"), std::string::npos) << b;  // add/mul operands are in canonical order
  EXPECT_NE(b.find("(x - y) * (-2.5f)"), std::string::npos) << b;
}

TEST(CExport, LiteralsRoundTripAndSpecialValuesUseMathH) {
  Graph g;
  auto x = g.x();
  const float inf = std::numeric_limits<float>::infinity();
  auto f = min(min(x + 0.1f, x * 3.0f), min(max(x, -inf), max(x - 1e-40f, min(x * 16777216.0f, x + inf))));
  const std::string b = body(export_c(g, f.id()));
  for (const char* lit : {"0.1f", "3.0f", "-INFINITY", "1e-40f", "16777216.0f", "+ INFINITY"})
    EXPECT_NE(b.find(lit), std::string::npos) << lit << " in " << b;
  EXPECT_NE(body(export_c(g, (x + std::numeric_limits<float>::quiet_NaN()).id())).find("NAN"), std::string::npos);
}

TEST(CExport, LongSingleUseChainsAreSplitIntoLocals) {
  Graph g;
  auto x = g.x();
  Expr e = x;
  for (int i = 0; i < 2000; ++i) e = sqrt(abs(e) + 0.5f);  // nothing shared: one 4000-deep expression
  const std::string b = body(export_c(g, e.id()));
  std::istringstream lines(b);
  std::size_t longest = 0;
  for (std::string line; std::getline(lines, line);) longest = std::max(longest, line.size());
  EXPECT_LT(longest, 300u);
  EXPECT_GT(count(b, "const float t"), 20u);
}

TEST(CExport, BadFunctionNamesAreInputErrors) {
  Graph g;
  const NodeId x = g.var_x();
  for (const char* bad : {"", "2d", "my sdf", "x", "a-b", "f()"}) EXPECT_THROW(export_c(g, x, bad), InputError) << bad;
  EXPECT_NE(export_c(g, x, "shape_2").find("float shape_2(float x, float y, float z)"), std::string::npos);
}

TEST(CExport, SourceNamesCannotBreakTheComment) {
  Graph g;
  CExportOptions opt;
  opt.source = "evil*/\nint x;/*.vm";
  std::ostringstream out;
  write_c(out, g, g.var_x(), opt);
  const std::string first = out.str().substr(0, out.str().find('\n'));
  EXPECT_NE(first.find("evil* / int x;/*.vm"), std::string::npos) << first;
  EXPECT_EQ(out.str().find("*/\nint x;"), std::string::npos);
}

TEST(CExport, ConstantAndVariableRoots) {
  Graph g;
  const std::string c = export_c(g, g.constant(-2.5f));
  EXPECT_NE(c.find("return -2.5f;"), std::string::npos) << c;
  EXPECT_NE(c.find("(void)x;"), std::string::npos);
  EXPECT_NE(export_c(g, g.var_y()).find("return y;"), std::string::npos);
}

}  // namespace
}  // namespace frep::test
