// Tests of the GLSL and Shadertoy exporters: the output is valid GLSL (glslangValidator, ES 3.00
// and desktop 3.30, where installed), and it computes frep's values: the same text, compiled as
// C++ over a small GLSL shim (IEEE-754 f32, like a GPU that honours the standard), must match
// PointEvaluator bit for bit on random expressions over every opcode but mod, which GLSL can
// only approximate and which is checked against its documented error bound.
#include <gtest/gtest.h>

#include <sstream>

#include "export_test_util.hpp"
#include "frep/error.hpp"
#include "frep/export/glsl.hpp"
#include "frep/expr/expr.hpp"
#include "frep/script/load.hpp"
#include "test_util.hpp"

namespace frep::test {
namespace {

// Writes the expressions as GLSL functions f0, f1, ... sharing one set of helpers.
std::string glsl_functions(const Graph& g, const std::vector<NodeId>& roots, std::vector<std::string>& names) {
  std::ostringstream out;
  write_glsl_helpers(out);
  for (std::size_t i = 0; i < roots.size(); ++i) {
    GlslOptions opt;
    opt.function_name = "f" + std::to_string(i);
    opt.helpers = false;
    names.push_back(opt.function_name);
    write_glsl(out, g, roots[i], opt);
  }
  return out.str();
}

// A fragment shader that calls every function, so that none is dead code.
std::string fragment_shader(const std::string& version, const std::string& functions,
                            const std::vector<std::string>& names) {
  std::string s = version + "\nprecision highp float;\nout vec4 frep_color;\n" + functions +
                  "\nvoid main() {\n  vec3 p = vec3(gl_FragCoord.xy, 0.5);\n  float acc = 0.0;\n";
  for (const std::string& n : names) s += "  acc += " + n + "(p);\n";
  return s + "  frep_color = vec4(acc);\n}\n";
}

// Shadertoy supplies these uniforms and calls mainImage itself.
std::string shadertoy_wrapper(const std::string& image_shader) {
  return "#version 300 es\nprecision highp float;\nprecision highp int;\nuniform vec3 iResolution;\n"
         "uniform float iTime;\nuniform vec4 iMouse;\nuniform int iFrame;\nout vec4 frep_color;\n" +
         image_shader + "\nvoid main() { mainImage(frep_color, gl_FragCoord.xy); }\n";
}

void expect_valid_glsl(const ScratchDir& dir, const std::string& name, const std::string& shader) {
  const std::string path = dir.path(name + ".frag");
  write_text(path, shader);
  const CommandResult r = run_command("glslangValidator " + shell_quote(path), dir.path(name + ".log"));
  EXPECT_EQ(r.code, 0) << name << ":\n" << r.output.substr(0, 3000);
}

// ---------------------------------------------------------------------------------------------
// GLSL as C++: float literals get an f suffix (suffix_float_literals), and the GLSL built-ins
// the exporter uses map to <cmath> in f32.

constexpr const char* kShim = R"(#include <cmath>
#include <cstdint>
#include <cstring>
namespace glsl {
struct vec3 { float x, y, z; };
inline float abs(float a) { return std::fabs(a); }
inline float sqrt(float a) { return std::sqrt(a); }
inline float floor(float a) { return std::floor(a); }
inline float ceil(float a) { return std::ceil(a); }
inline float trunc(float a) { return std::trunc(a); }
// GLSL lets round() take halves either way; model the way that differs from frep's.
inline float round(float a) { return std::nearbyint(a); }
inline float sign(float a) { return a > 0.0f ? 1.0f : (a < 0.0f ? -1.0f : 0.0f); }
inline float sin(float a) { return std::sin(a); }
inline float cos(float a) { return std::cos(a); }
inline float tan(float a) { return std::tan(a); }
inline float asin(float a) { return std::asin(a); }
inline float acos(float a) { return std::acos(a); }
inline float atan(float a) { return std::atan(a); }
inline float atan(float y, float x) { return std::atan2(y, x); }
inline float exp(float a) { return std::exp(a); }
inline float log(float a) { return std::log(a); }
inline bool isnan(float a) { return std::isnan(a); }
inline bool isinf(float a) { return std::isinf(a); }
inline float uintBitsToFloat(std::uint32_t u) { float f; std::memcpy(&f, &u, sizeof f); return f; }
)";

std::vector<float> run_as_cpp(const ScratchDir& dir, const std::string& functions, const std::vector<std::string>& names,
                              const std::vector<float>& xyz) {
  const std::string src = std::string(kShim) + suffix_float_literals(functions) + "}  // namespace glsl\n" +
                          driver_main(names, "glsl::", "glsl::vec3{p[0], p[1], p[2]}");
  const std::string cpp = dir.path("glsl.cpp"), exe = dir.path("glsl_as_cpp");
  write_text(cpp, src);
  // -O0: the same values, and Prospero's 7866-line function compiles in a second.
  const CommandResult r = run_command("c++ -std=c++17 -O0 -ffp-contract=off -o " + shell_quote(exe) + " " + shell_quote(cpp),
                                      dir.path("cxx.log"));
  EXPECT_EQ(r.code, 0) << r.output.substr(0, 4000);
  if (r.code != 0) return {};
  return run_driver(dir, exe, xyz, names.size());
}

std::vector<Op> every_op_but_mod() {
  std::vector<Op> ops;
  for (int i = 0; i < kOpCount; ++i) {
    const Op op = static_cast<Op>(i);
    if (op_arity(op) > 0 && op != Op::Mod) ops.push_back(op);
  }
  return ops;
}

TEST(GlslExport, RandomExpressionsAreValidGlsl) {
  FREP_REQUIRE_PROGRAM("glslangValidator");
  ScratchDir dir;
  Graph g;
  const std::vector<NodeId> roots = random_expressions(g, 31, 80);
  std::vector<std::string> names;
  const std::string functions = glsl_functions(g, roots, names);
  expect_valid_glsl(dir, "es300", fragment_shader("#version 300 es", functions, names));
  expect_valid_glsl(dir, "core330", fragment_shader("#version 330", functions, names));
}

TEST(GlslExport, InvalidGlslIsNoticed) {  // the check above can fail
  FREP_REQUIRE_PROGRAM("glslangValidator");
  ScratchDir dir;
  const std::string path = dir.path("bad.frag");
  write_text(path, "#version 300 es\nprecision highp float;\nout vec4 c;\nvoid main() { c = vec4(frep_min(1.0, 2.0)); }\n");
  EXPECT_NE(run_command("glslangValidator " + shell_quote(path), dir.path("bad.log")).code, 0);
}

TEST(GlslExport, RandomExpressionsComputeFrepsValuesOnIeeeFloats) {
  FREP_REQUIRE_PROGRAM("c++");
  ScratchDir dir;
  Graph g;
  const std::vector<NodeId> roots = random_expressions(g, 41, 120, every_op_but_mod());
  const std::vector<bool> used = ops_used(g, roots);
  for (Op op : every_op_but_mod()) EXPECT_TRUE(used[static_cast<int>(op)]) << "not covered: " << op_name(op);
  std::vector<std::string> names;
  const std::string functions = glsl_functions(g, roots, names);
  const std::vector<float> xyz = random_points(42, 300);
  EXPECT_EQ(count_mismatches(g, roots, xyz, run_as_cpp(dir, functions, names, xyz), "GLSL"), 0);
}

// GLSL has no exact fmod: frep_mod is a - |b| floor(a / |b|), corrected into [0, |b|). Within an
// ulp or two of max(|a|, |b|) of the exact Euclidean remainder (modulo |b|) while |a / b| < 2^22.
TEST(GlslExport, ModIsTheEuclideanRemainderUpToRounding) {
  FREP_REQUIRE_PROGRAM("c++");
  ScratchDir dir;
  Graph g;
  auto x = g.x(), y = g.y();
  const std::vector<NodeId> roots = {mod(x, y).id()};
  std::vector<std::string> names;
  const std::string functions = glsl_functions(g, roots, names);
  std::mt19937_64 rng(5);
  std::vector<float> xyz;
  for (int i = 0; i < 3000; ++i) {
    float a = std::uniform_real_distribution<float>(-1000.0f, 1000.0f)(rng);
    float b = std::pow(10.0f, std::uniform_real_distribution<float>(-1.0f, 2.0f)(rng)) * ((rng() & 1) ? 1.0f : -1.0f);
    if (i % 10 == 0) a = std::round(a / b) * b;  // near multiples, where the correction steps matter
    xyz.insert(xyz.end(), {a, b, 0.0f});
  }
  const float inf = std::numeric_limits<float>::infinity();
  const float special[][2] = {{5.0f, 0.0f}, {inf, 2.0f}, {-3.0f, inf}, {3.0f, -inf}, {-0.0f, inf}, {2.0f, 2.0f}, {-2.0f, 2.0f}};
  for (auto& s : special) xyz.insert(xyz.end(), {s[0], s[1], 0.0f});
  const std::vector<float> got = run_as_cpp(dir, functions, names, xyz);
  ASSERT_EQ(got.size(), xyz.size() / 3);
  for (std::size_t i = 0; i < got.size(); ++i) {
    const float a = xyz[3 * i], b = xyz[3 * i + 1], want = op_mod(a, b), r = got[i];
    if (std::isnan(want) || std::isinf(b) || std::isinf(a)) {
      EXPECT_TRUE(same_value(want, r)) << fstr(a) << " mod " << fstr(b) << ": " << fstr(r) << " vs " << fstr(want);
      continue;
    }
    const float m = std::fabs(b);
    EXPECT_TRUE(r >= 0.0f && r <= m) << fstr(a) << " mod " << fstr(b) << " = " << fstr(r);
    const double d = std::fabs(static_cast<double>(r) - want), tol = 2.0 * std::ldexp(1.0, std::ilogb(std::max(std::fabs(a), m)) - 23);
    EXPECT_LE(std::min(d, std::fabs(d - m)), tol) << fstr(a) << " mod " << fstr(b) << ": " << fstr(r) << " vs " << fstr(want);
  }
}

TEST(GlslExport, SharedModelsAreValidAndExact) {
  for (const char* name : {"bear.vm", "prospero.vm", "tanglecube.vm", "hi.vm"}) {
    SCOPED_TRACE(name);
    if (!have_data(name)) {
      std::printf("[ SKIPPED  ] shared data not found: %s\n", data_file(name).c_str());
      continue;
    }
    ScratchDir dir;
    const Model m = load_expression(data_file(name));
    std::ostringstream fn, toy;
    write_glsl(fn, *m.graph, m.root);
    write_shadertoy(toy, *m.graph, m.root);
    if (have_program("glslangValidator")) {
      expect_valid_glsl(dir, "function", fragment_shader("#version 300 es", fn.str(), {"sdf"}));
      expect_valid_glsl(dir, "shadertoy", shadertoy_wrapper(toy.str()));
    }
    // Prospero's values are checked through C (c_export_test.cpp, same emitter); compiling its
    // 7576-line function as C++ once more would add seconds and no coverage.
    if (have_program("c++") && std::string(name) != "prospero.vm") {
      const std::vector<float> xyz = model_points(10, 300);
      EXPECT_EQ(count_mismatches(*m.graph, {m.root}, xyz, run_as_cpp(dir, fn.str(), {"sdf"}, xyz), name), 0);
    }
  }
}

TEST(GlslExport, FunctionShape) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  auto r = sqrt(square(x) + square(y) + square(z));
  std::ostringstream out;
  GlslOptions opt;
  opt.function_name = "ball";
  write_glsl(out, g, (max(r - 1.0f, -r) + round(x)).id(), opt);
  const std::string s = out.str();
  EXPECT_NE(s.find("float ball(vec3 p) {"), std::string::npos) << s;
  const std::size_t local = s.find("float t0 = sqrt(");  // r is shared: computed once
  ASSERT_NE(local, std::string::npos) << s;
  EXPECT_EQ(s.find("sqrt(", local + 16), std::string::npos) << s;
  EXPECT_NE(s.find("frep_round("), std::string::npos) << s;  // GLSL's round() may round halves to even
  EXPECT_EQ(s.find("frep_min"), std::string::npos) << "helpers that are not needed are left out";
  EXPECT_EQ(s.find("#version"), std::string::npos);
  for (const char* bad : {"p", "gl_sdf", "a__b", "1x", ""}) {
    opt.function_name = bad;
    std::ostringstream o;
    EXPECT_THROW(write_glsl(o, g, r.id(), opt), InputError) << bad;
  }
}

TEST(GlslExport, ShadertoyExtrudes2DShapesAndChecksOptions) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  std::ostringstream flat, solid;
  ShadertoyOptions opt;
  opt.radius = 2.0f;
  opt.step_scale = 0.5f;
  write_shadertoy(flat, g, (square(x) + square(y) - 1.0f).id(), opt);
  write_shadertoy(solid, g, (square(x) + square(y) + square(z) - 1.0f).id(), opt);
  EXPECT_NE(flat.str().find("max(sdf(p), abs(p.z) - FREP_SLAB)"), std::string::npos);
  EXPECT_EQ(solid.str().find("FREP_SLAB"), std::string::npos);
  for (const std::string& s : {flat.str(), solid.str()}) {
    EXPECT_NE(s.find("void mainImage(out vec4 fragColor, in vec2 fragCoord)"), std::string::npos);
    EXPECT_NE(s.find("#define FREP_RADIUS 2.0"), std::string::npos);
    EXPECT_NE(s.find("#define FREP_STEP_SCALE 0.5"), std::string::npos);
  }
  for (auto bad : {std::make_pair(0.0f, 0.8f), std::make_pair(-1.0f, 0.8f), std::make_pair(1.0f, -0.5f),
                   std::make_pair(1.0f, 1.5f), std::make_pair(std::numeric_limits<float>::infinity(), 0.8f)}) {
    ShadertoyOptions o;
    o.radius = bad.first;
    o.step_scale = bad.second;
    std::ostringstream s;
    EXPECT_THROW(write_shadertoy(s, g, x.id(), o), InputError) << bad.first << " " << bad.second;
  }
}

// The automatic step follows the field's gradient: 0.8 / |grad f|, at most 1.
TEST(GlslExport, ShadertoyStepScaleFollowsTheGradient) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  auto ball = sqrt(square(x) + square(y) + square(z)) - 0.5f;
  for (auto [scale, want] : {std::pair{1.0f, "0.8"}, {10.0f, "0.08"}, {0.5f, "1.0"}}) {
    std::ostringstream out;
    write_shadertoy(out, g, (ball * scale).id());
    EXPECT_NE(out.str().find(std::string("#define FREP_STEP_SCALE ") + want), std::string::npos)
        << scale << ":\n" << out.str().substr(0, 800);
  }
}

}  // namespace
}  // namespace frep::test
