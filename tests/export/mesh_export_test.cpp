// Tests of mesh oracles in the C and GLSL exports, written as data plus a loop
// (src/export/mesh_code.cpp). The C compiles without warnings and gives MeshOracle's values
// (the same computation in double) at random, near-surface, on-surface, far and special points,
// on generated meshes and on fandisk; moved meshes and mixed expressions call the mesh at the
// right point, and a mesh used twice is written once. Fandisk's C is small and compiles quickly.
// The GLSL is valid (glslangValidator) and, compiled as C++ over a shim of GLSL in float, within
// its documented accuracy with the same signs off the surface. closed_form gives the old output.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <random>
#include <regex>
#include <sstream>

#include "convert/convert_test_util.hpp"
#include "export_test_util.hpp"
#include "frep/convert/mesh_oracle.hpp"
#include "frep/error.hpp"
#include "frep/export/c_source.hpp"
#include "frep/export/glsl.hpp"
#include "frep/export/latex.hpp"
#include "frep/expr/copy.hpp"
#include "frep/expr/expr.hpp"
#include "frep/expr/oracle.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/topology.hpp"
#include "mesh_test_util.hpp"

namespace frep::test {
namespace {

const char* kStrict = "-std=c99 -O2 -ffp-contract=off -Wall -Wextra -pedantic";

struct TestMesh {
  std::string name;
  TriMesh mesh;
};

// Generated meshes, and shared ones where ../shared is: fandisk (13k triangles, sharp edges and
// corners) for C, plate_holes (1252 long thin triangles around holes) for both.
std::vector<TestMesh> test_meshes(bool glsl) {
  std::vector<TestMesh> v;
  v.push_back({"box", make_box({-1, -0.5, -0.25}, {1, 0.5, 0.25})});
  v.push_back({"sphere", make_sphere(3, 0.8)});
  for (const char* name : {"plate_holes.stl", "fandisk.obj"}) {
    if (glsl && std::string(name) == "fandisk.obj") continue;  // beyond GLSL's constant arrays
    const std::string path = shared_mesh_dir() + "/" + name;
    if (std::filesystem::exists(path)) v.push_back({name, read_mesh(path)});
    else std::printf("[ SKIPPED  ] shared mesh not found: %s\n", path.c_str());
  }
  return v;
}

double diagonal(const MeshOracle& o) { return length(o.field().box().size()); }

// Points as float triples: sample_around's (uniform in the grown box, near faces on both sides,
// on vertices and edges); off vertices and edge midpoints along their pseudonormals, on both
// sides, so that corners and edges decide the sign; far points; infinities and NaN. Not beyond
// about 1e15 times the size, where double cannot tell the triangles' distances apart and the
// library's sign depends on which one its search meets first.
std::vector<float> mesh_points(const MeshOracle& o, std::size_t uniform, std::size_t near, std::size_t features) {
  const TriMesh& w = o.field().welded();
  const MeshTopology& topo = o.field().topology();
  const Samples s = sample_around(w, uniform, near, features / 4);
  std::vector<float> xyz;
  auto add = [&](const Vec3& p) {
    for (int k = 0; k < 3; ++k) xyz.push_back(static_cast<float>(p[k]));
  };
  for (const Vec3& p : s.points) add(p);
  const double diag = diagonal(o);
  const double offsets[] = {1e-5, 1e-3, -1e-5, -1e-3};
  const std::size_t vstep = std::max<std::size_t>(1, w.vertices.size() / std::max<std::size_t>(features / 2, 1));
  for (std::uint32_t v = 0; v < w.vertices.size(); v += static_cast<std::uint32_t>(vstep)) {
    const Vec3 n = topo.vertex_pseudonormal(v);
    if (!(length(n) > 0)) continue;
    for (double off : offsets) add(w.vertices[v] + n * (off * diag / length(n)));
  }
  const std::size_t estep = std::max<std::size_t>(1, topo.num_edges() / std::max<std::size_t>(features / 2, 1));
  for (std::uint32_t e = 0; e < topo.num_edges(); e += static_cast<std::uint32_t>(estep)) {
    const auto [a, b] = topo.edge_vertices(e);
    const Vec3 n = topo.edge_pseudonormal(e);
    if (!(length(n) > 0)) continue;
    for (double off : offsets) add((w.vertices[a] + w.vertices[b]) * 0.5 + n * (off * diag / length(n)));
  }
  const Vec3 c = o.field().box().center();
  for (double far : {10.0, 1e3, 1e6}) add(c + Vec3{far * diag, -0.5 * far * diag, 0.25 * far * diag});
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  xyz.insert(xyz.end(), {inf, 0.0f, 0.0f, 0.0f, -inf, 0.0f, nan, 0.0f, 0.0f, -0.0f, -0.0f, -0.0f});
  return xyz;
}

// The graph's values at the points (the library's evaluator, oracles included).
std::vector<float> library_values(const Graph& g, NodeId root, const std::vector<float>& xyz) {
  const Tape tape = Tape::compile(g, root);
  PointEvaluator ev;
  std::vector<float> v;
  for (std::size_t i = 0; i < xyz.size(); i += 3) v.push_back(ev.eval(tape, xyz[i], xyz[i + 1], xyz[i + 2]));
  return v;
}

struct Agreement {
  std::size_t points = 0, identical = 0, farther = 0, signs = 0;
  double worst = 0;  // largest |exported - frep| where frep's value is within `near` of 0
};

// Compares exported values with frep's: NaN where frep gives NaN, within `tol` plus `rel` times
// frep's value elsewhere, and the same sign wherever frep's value is beyond `sign_tol` from 0.
// Reports the first few failures.
Agreement compare(const std::vector<float>& xyz, const std::vector<float>& want, const std::vector<float>& got,
                  double tol, double sign_tol, const std::string& what, double rel = 0, double near = INFINITY) {
  Agreement a;
  EXPECT_EQ(got.size(), want.size()) << what;
  int reported = 0;
  for (std::size_t i = 0; i < std::min(got.size(), want.size()); ++i) {
    ++a.points;
    const float w = want[i], g = got[i];
    const std::string at = "(" + fstr(xyz[3 * i]) + ", " + fstr(xyz[3 * i + 1]) + ", " + fstr(xyz[3 * i + 2]) + ")";
    if (same_bits(w, g) || (std::isnan(w) && std::isnan(g))) {
      ++a.identical;
      continue;
    }
    const double d = std::fabs(double(w) - double(g));
    if (std::isfinite(d) && std::fabs(w) <= near) a.worst = std::max(a.worst, d);
    const bool far = !(d <= tol + rel * std::fabs(w)), sign = std::fabs(w) > sign_tol && (w < 0) != (g < 0);
    a.farther += far;
    a.signs += sign;
    if ((far || sign) && ++reported <= 5)
      ADD_FAILURE() << what << " at " << at << ": exported " << fstr(g) << ", frep " << fstr(w);
  }
  return a;
}

void print(const std::string& what, const Agreement& a) {
  std::printf("  %s: %zu points, %zu identical to frep's, largest difference near the mesh %.3g\n", what.c_str(), a.points,
              a.identical, a.worst);
}

// Writes the C export with a driver, compiles it (no warnings allowed) and evaluates at `xyz`.
std::vector<float> run_c(const ScratchDir& dir, const std::string& c_source, const std::vector<float>& xyz,
                         const std::string& flags = kStrict) {
  const std::string c = dir.path("mesh.c"), exe = dir.path("mesh_c");
  write_text(c, c_source + driver_main({"frep_sdf"}, "", "p[0], p[1], p[2]"));
  const CommandResult r =
      run_command("cc " + flags + " -o " + shell_quote(exe) + " " + shell_quote(c) + " -lm", dir.path("cc.log"));
  EXPECT_EQ(r.code, 0) << r.output.substr(0, 4000);
  if (r.code != 0) return {};
  EXPECT_EQ(r.output, "") << "compiler warnings:\n" << r.output.substr(0, 4000);
  return run_driver(dir, exe, xyz, 1);
}

std::string export_c(const Graph& g, NodeId root, CExportOptions opt = {}) {
  std::ostringstream out;
  write_c(out, g, root, opt);
  return out.str();
}

std::string export_glsl(const Graph& g, NodeId root, GlslOptions opt = {}) {
  std::ostringstream out;
  write_glsl(out, g, root, opt);
  return out.str();
}

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = s.find(what); at != std::string::npos; at = s.find(what, at + 1)) ++n;
  return n;
}

// A rotation about z by 30 degrees, a uniform scale of 1.25 and a translation: f(a(p)).
Affine3 test_map() {
  Affine3 a;
  const double c = std::cos(0.5236) * 1.25, s = std::sin(0.5236) * 1.25;
  a.m[0][0] = c, a.m[0][1] = -s, a.m[1][0] = s, a.m[1][1] = c, a.m[2][2] = 1.25;
  a.m[0][3] = 0.3, a.m[1][3] = -0.2, a.m[2][3] = 0.1;
  return a;
}

// A mesh used twice (as it is and moved by test_map) inside a mixed expression: an offset, a
// difference with a ball, a union with the moved copy plus a linear term.
struct MixedMeshExpression {
  std::shared_ptr<const MeshOracle> oracle = std::make_shared<const MeshOracle>(make_sphere(2, 0.6));
  Graph g;
  NodeId root = kNoNode;
  MixedMeshExpression() {
    Expr x = g.x(), y = g.y(), z = g.z();
    const Expr solid(g, g.oracle(oracle)), moved(g, g.oracle(oracle->transformed(test_map())));
    const Expr ball = sqrt(square(x - 0.5f) + square(y) + square(z)) - 0.4f;
    root = min(max(solid - 0.05f, -ball), moved + 0.01f * x).id();
  }
};

// `near` points around the mesh (mesh_points) and 3000 uniform in [-1.5, 1.5]^3.
std::vector<float> mixed_points(const MeshOracle& oracle, std::size_t near, unsigned seed) {
  std::vector<float> xyz = mesh_points(oracle, near, 500, 100);
  std::mt19937_64 rng(seed);
  for (int i = 0; i < 3000; ++i) xyz.push_back(std::uniform_real_distribution<float>(-1.5f, 1.5f)(rng));
  return xyz;
}

// A field given by code that is not a mesh: the exports write its closed form.
class BallOracle final : public Oracle {
 public:
  void values(const float* x, const float* y, const float* z, float* out, std::size_t n) const override {
    for (std::size_t i = 0; i < n; ++i) out[i] = std::sqrt(x[i] * x[i] + y[i] * y[i] + z[i] * z[i]) - 0.5f;
  }
  void gradients(const float* x, const float* y, const float* z, Grad* out, std::size_t n) const override {
    for (std::size_t i = 0; i < n; ++i) {
      const float r = std::sqrt(x[i] * x[i] + y[i] * y[i] + z[i] * z[i]);
      out[i] = {r - 0.5f, x[i] / r, y[i] / r, z[i] / r};
    }
  }
  double lipschitz() const override { return 1; }
  std::string describe() const override { return "a ball"; }
  NodeId closed_form(Graph& g) const override {
    Expr x = g.x(), y = g.y(), z = g.z();
    return (sqrt(square(x) + square(y) + square(z)) - 0.5f).id();
  }
};

// ---------------------------------------------------------------------------------------------
// C

TEST(MeshExport, CGivesTheOraclesValues) {
  FREP_REQUIRE_PROGRAM("cc");
  for (const TestMesh& t : test_meshes(false)) {
    SCOPED_TRACE(t.name);
    ScratchDir dir;
    const auto oracle = std::make_shared<const MeshOracle>(t.mesh);
    const Model m = mesh_model(oracle);
    const std::string c = export_c(*m.graph, m.root);
    EXPECT_NE(c.find("static double frep_sdf_mesh(int mesh"), std::string::npos);
    const std::vector<float> xyz = mesh_points(*oracle, 1500, 1500, 400);
    const std::vector<float> want = library_values(*m.graph, m.root, xyz);
    // The same double computation as the library's, rounded once: bit for bit, but where two
    // triangles are equally near up to rounding, either may be found; their closest points then
    // differ in the last bits of double, which float rounding nearly always hides.
    const double diag = diagonal(*oracle);
    const Agreement a = compare(xyz, want, run_c(dir, c, xyz), 1e-12 * diag, 0, "C", 2e-7);
    print("C, " + t.name, a);
    EXPECT_EQ(a.farther, 0u);
    EXPECT_EQ(a.signs, 0u);
    EXPECT_GE(a.identical, a.points * 99 / 100);
  }
}

// Offsets, booleans with other shapes and moved copies are the expression around the oracle
// calls; a mesh used twice is written once.
TEST(MeshExport, CMixedExpressionsAndMovedMeshes) {
  FREP_REQUIRE_PROGRAM("cc");
  ScratchDir dir;
  const MixedMeshExpression mixed;
  const Graph& g = mixed.g;
  const std::string c = export_c(g, mixed.root);
  EXPECT_EQ(count(c, "static const double frep_sdf_vertices["), 1u) << "the mesh is written once";
  EXPECT_EQ(count(c, "static float frep_sdf_oracle"), 2u);
  EXPECT_NE(c.find("(float)(1.0825"), std::string::npos) << "the moved copy's map, in double";
  const std::vector<float> xyz = mixed_points(*mixed.oracle, 1000, 3);
  const std::vector<float> want = library_values(g, mixed.root, xyz);
  const Agreement a = compare(xyz, want, run_c(dir, c, xyz), 0, 0, "C, mixed", 2e-7);
  print("C, mixed", a);
  EXPECT_GE(a.identical, a.points * 99 / 100);
}

// Oracles that are not meshes have no data form: their closed form is written.
TEST(MeshExport, OtherOraclesAreWrittenAsTheirClosedForm) {
  FREP_REQUIRE_PROGRAM("cc");
  ScratchDir dir;
  const auto mesh = std::make_shared<const MeshOracle>(make_box({-0.3, -0.3, -0.3}, {0.3, 0.3, 0.3}));
  Graph g;
  const Expr ball(g, g.oracle(std::make_shared<const BallOracle>()));
  const Expr e = max(ball, -Expr(g, g.oracle(mesh)));
  const std::string c = export_c(g, e.id());
  EXPECT_EQ(count(c, "static float frep_sdf_oracle"), 1u) << "the mesh only";
  EXPECT_NE(c.find("sqrtf("), std::string::npos) << "the ball's closed form";
  std::vector<float> xyz;
  std::mt19937_64 rng(4);
  for (int i = 0; i < 3000; ++i) xyz.push_back(std::uniform_real_distribution<float>(-0.8f, 0.8f)(rng));
  const Agreement a = compare(xyz, library_values(g, e.id(), xyz), run_c(dir, c, xyz), 1e-6, 1e-6, "C, ball oracle");
  EXPECT_EQ(a.farther + a.signs, 0u);
}

// Why the data form exists: fandisk's closed form is 9.4 MB of C on which gcc -O2 runs out of
// memory (6 GB, after 140 s; docs/export.md). Its data form must stay small and quick.
TEST(MeshExport, FandiskCIsSmallAndCompilesQuickly) {
  FREP_REQUIRE_PROGRAM("cc");
  const std::string path = shared_mesh_dir() + "/fandisk.obj";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared mesh not found: " << path;
  ScratchDir dir;
  const auto oracle = std::make_shared<const MeshOracle>(read_mesh(path));
  const Model m = mesh_model(oracle);
  const auto t0 = std::chrono::steady_clock::now();
  const std::string c = export_c(*m.graph, m.root);
  const auto t1 = std::chrono::steady_clock::now();
  EXPECT_LT(c.size(), 2'000'000u);
  const std::string file = dir.path("fandisk.c");
  write_text(file, c);
  const CommandResult r = run_command("cc " + std::string(kStrict) + " -c -o " + shell_quote(dir.path("fandisk.o")) + " " +
                                          shell_quote(file),
                                      dir.path("cc.log"));
  const auto t2 = std::chrono::steady_clock::now();
  EXPECT_EQ(r.code, 0) << r.output.substr(0, 4000);
  EXPECT_EQ(r.output, "");
  const double compile = std::chrono::duration<double>(t2 - t1).count();
  std::printf("  fandisk (%zu triangles): %.2f MB of C, written in %.2f s, cc -O2 in %.2f s\n",
              oracle->field().distance().num_triangles(), c.size() / 1e6, std::chrono::duration<double>(t1 - t0).count(),
              compile);
  EXPECT_LT(compile, 30.0) << "about 0.5 s on an idle machine";
}

// closed_form keeps the old output: the closed form of every oracle (expand_oracles).
TEST(MeshExport, ClosedFormIsTheOldOutput) {
  const auto oracle = std::make_shared<const MeshOracle>(make_box({-1, -0.5, -0.25}, {1, 0.5, 0.25}));
  Graph g;
  Expr x = g.x();
  const Expr e = max(Expr(g, g.oracle(oracle)), x - 0.5f);
  const Model expanded = expand_oracles(g, e.id());
  CExportOptions c;
  c.closed_form = true;
  EXPECT_EQ(export_c(g, e.id(), c), export_c(*expanded.graph, expanded.root));
  EXPECT_EQ(export_c(g, e.id(), c).find("frep_sdf_mesh"), std::string::npos);
  GlslOptions gl;
  gl.closed_form = true;
  EXPECT_EQ(export_glsl(g, e.id(), gl), export_glsl(*expanded.graph, expanded.root));
  ShadertoyOptions st;
  st.glsl.closed_form = true;
  std::ostringstream a, b;
  write_shadertoy(a, g, e.id(), st);
  write_shadertoy(b, *expanded.graph, expanded.root, ShadertoyOptions{});
  EXPECT_EQ(a.str(), b.str());
  // LaTeX is always the closed form.
  std::ostringstream la, lb;
  write_latex(la, g, e.id());
  write_latex(lb, *expanded.graph, expanded.root);
  EXPECT_EQ(la.str(), lb.str());
}

// ---------------------------------------------------------------------------------------------
// GLSL

// GLSL's built-ins the mesh code and the frep_* helpers use, in float.
constexpr const char* kShim = R"(#include <cmath>
#include <cstdint>
#include <cstring>
namespace glsl {
// constexpr constructors: the data arrays are constants, not code run at start-up.
struct vec3 {
  float x, y, z;
  constexpr vec3() : x(0), y(0), z(0) {}
  constexpr explicit vec3(float s) : x(s), y(s), z(s) {}
  constexpr vec3(float a, float b, float c) : x(a), y(b), z(c) {}
};
struct ivec2 { int x, y; constexpr ivec2(int a, int b) : x(a), y(b) {} };
struct uvec3 { unsigned x, y, z; constexpr uvec3(unsigned a, unsigned b, unsigned c) : x(a), y(b), z(c) {} };
struct ivec3 {
  int x, y, z;
  constexpr ivec3(int a, int b, int c) : x(a), y(b), z(c) {}
  constexpr explicit ivec3(uvec3 u) : x(int(u.x)), y(int(u.y)), z(int(u.z)) {}
};
inline uvec3 operator&(uvec3 a, unsigned m) { return uvec3(a.x & m, a.y & m, a.z & m); }
inline uvec3 operator>>(uvec3 a, unsigned s) { return uvec3(a.x >> s, a.y >> s, a.z >> s); }
inline vec3 operator+(vec3 a, vec3 b) { return vec3(a.x + b.x, a.y + b.y, a.z + b.z); }
inline vec3 operator-(vec3 a, vec3 b) { return vec3(a.x - b.x, a.y - b.y, a.z - b.z); }
inline vec3 operator*(vec3 a, float s) { return vec3(a.x * s, a.y * s, a.z * s); }
inline vec3 operator/(vec3 a, float s) { return vec3(a.x / s, a.y / s, a.z / s); }
inline vec3& operator+=(vec3& a, vec3 b) { return a = a + b; }
inline vec3& operator*=(vec3& a, float s) { return a = a * s; }
inline float dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline vec3 cross(vec3 a, vec3 b) { return vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x); }
inline float sqrt(float a) { return std::sqrt(a); }
inline float length(vec3 a) { return std::sqrt(dot(a, a)); }
inline float inversesqrt(float a) { return 1.0f / std::sqrt(a); }
inline float abs(float a) { return std::fabs(a); }
inline float min(float a, float b) { return b < a ? b : a; }
inline float max(float a, float b) { return a < b ? b : a; }
inline vec3 max(vec3 a, vec3 b) { return vec3(max(a.x, b.x), max(a.y, b.y), max(a.z, b.z)); }
inline float clamp(float a, float lo, float hi) { return min(max(a, lo), hi); }
inline bool isnan(float a) { return std::isnan(a); }
inline float uintBitsToFloat(std::uint32_t u) { float f; std::memcpy(&f, &u, sizeof f); return f; }
)";

// The exported GLSL as C++ inside namespace glsl: array constructors `T[N](` ... `);` become
// brace lists, `out T` parameters references, float literals float.
std::string glsl_as_cpp(const std::string& glsl) {
  static const std::regex open(R"(^const (\w+) (\w+)\[(\d+)\] = \w+\[\d+\]\((.*)$)"), out_param(R"(\bout (\w+) )");
  std::istringstream in(glsl);
  std::string out;
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (std::regex_match(line, m, open)) line = "const " + m[1].str() + " " + m[2].str() + "[" + m[3].str() + "] = {" + m[4].str();
    else if (line == ");") line = "};";
    out += std::regex_replace(line, out_param, "$1& ") + "\n";
  }
  return std::string(kShim) + suffix_float_literals(out) + "}  // namespace glsl\n";
}

std::vector<float> run_glsl_as_cpp(const ScratchDir& dir, const std::string& glsl, const std::vector<float>& xyz) {
  const std::string cpp = dir.path("glsl.cpp"), exe = dir.path("glsl_as_cpp");
  write_text(cpp, glsl_as_cpp(glsl) + driver_main({"sdf"}, "glsl::", "glsl::vec3(p[0], p[1], p[2])"));
  const CommandResult r = run_command("c++ -std=c++17 -O0 -ffp-contract=off -o " + shell_quote(exe) + " " + shell_quote(cpp),
                                      dir.path("cxx.log"));
  EXPECT_EQ(r.code, 0) << r.output.substr(0, 4000);
  if (r.code != 0) return {};
  return run_driver(dir, exe, xyz, 1);
}

void expect_valid_glsl(const ScratchDir& dir, const std::string& name, const std::string& shader) {
  const std::string path = dir.path(name + ".frag");
  write_text(path, shader);
  const CommandResult r = run_command("glslangValidator " + shell_quote(path), dir.path(name + ".log"));
  EXPECT_EQ(r.code, 0) << name << ":\n" << r.output.substr(0, 3000);
}

void expect_valid_function(const ScratchDir& dir, const std::string& function) {
  for (const char* version : {"#version 300 es", "#version 330"})
    expect_valid_glsl(dir, version[10] == '0' ? "es300" : "core330",
                      std::string(version) + "\nprecision highp float;\nout vec4 frep_color;\n" + function +
                          "\nvoid main() { frep_color = vec4(sdf(vec3(gl_FragCoord.xy, 0.5))); }\n");
}

void expect_valid_shadertoy(const ScratchDir& dir, const std::string& image_shader) {
  expect_valid_glsl(dir, "shadertoy",
                    "#version 300 es\nprecision highp float;\nprecision highp int;\nuniform vec3 iResolution;\n"
                    "uniform float iTime;\nuniform vec4 iMouse;\nout vec4 frep_color;\n" +
                        image_shader + "\nvoid main() { mainImage(frep_color, gl_FragCoord.xy); }\n");
}

// In float: within 1e-6 of the size plus the coordinates' magnitude (docs/export.md), the same
// sign beyond that from the surface.
TEST(MeshExport, GlslIsValidAndWithinFloatAccuracy) {
  const bool validator = have_program("glslangValidator"), cxx = have_program("c++");
  if (!validator && !cxx) GTEST_SKIP() << "neither glslangValidator nor c++ is installed";
  if (!validator) std::printf("[ SKIPPED  ] glslangValidator is not installed: GLSL validity not checked\n");
  for (const TestMesh& t : test_meshes(true)) {
    SCOPED_TRACE(t.name);
    ScratchDir dir;
    const auto oracle = std::make_shared<const MeshOracle>(t.mesh);
    const Model m = mesh_model(oracle);
    const std::string glsl = export_glsl(*m.graph, m.root);
    EXPECT_NE(glsl.find("float sdf_mesh(int mesh, vec3 p)"), std::string::npos);
    if (validator) {
      expect_valid_function(dir, glsl);
      std::ostringstream toy;
      write_shadertoy(toy, *m.graph, m.root);
      expect_valid_shadertoy(dir, toy.str());
    }
    if (!cxx) continue;
    const std::vector<float> xyz = mesh_points(*oracle, 1500, 1500, 400);
    const Box3 box = oracle->field().box();
    const double scale = diagonal(*oracle) + std::max({std::fabs(box.lo.x), std::fabs(box.lo.y), std::fabs(box.lo.z),
                                                       std::fabs(box.hi.x), std::fabs(box.hi.y), std::fabs(box.hi.z)});
    const std::vector<float> want = library_values(*m.graph, m.root, xyz);
    // Far points: float's rounding of their distance, relative to it.
    const Agreement a =
        compare(xyz, want, run_glsl_as_cpp(dir, glsl, xyz), 1e-6 * scale, 1e-6 * scale, "GLSL", 1e-6, diagonal(*oracle));
    print("GLSL as C++, " + t.name, a);
    std::printf("    largest difference / (size + coordinates) = %.3g\n", a.worst / scale);
    EXPECT_EQ(a.farther, 0u);
    EXPECT_EQ(a.signs, 0u);
  }
}

TEST(MeshExport, GlslMixedExpressionsAndMovedMeshes) {
  const bool validator = have_program("glslangValidator"), cxx = have_program("c++");
  if (!validator && !cxx) GTEST_SKIP() << "neither glslangValidator nor c++ is installed";
  ScratchDir dir;
  const MixedMeshExpression mixed;
  const Graph& g = mixed.g;
  const std::string glsl = export_glsl(g, mixed.root);
  EXPECT_EQ(count(glsl, "const vec3 sdf_vertices["), 1u) << "the mesh is written once";
  EXPECT_EQ(count(glsl, "float sdf_oracle"), 2u);
  if (validator) {
    expect_valid_function(dir, glsl);
    std::ostringstream toy;
    write_shadertoy(toy, g, mixed.root);
    expect_valid_shadertoy(dir, toy.str());
  }
  if (!cxx) return;
  const std::vector<float> xyz = mixed_points(*mixed.oracle, 500, 5);
  const Agreement a = compare(xyz, library_values(g, mixed.root, xyz), run_glsl_as_cpp(dir, glsl, xyz), 1e-5, 1e-5, "GLSL, mixed", 1e-6, 2.0);
  print("GLSL as C++, mixed", a);
  EXPECT_EQ(a.farther + a.signs, 0u);
}

// Constant arrays have a documented limit; beyond it, the error says what to do.
TEST(MeshExport, GlslRefusesMeshesBeyondItsLimit) {
  const auto oracle = std::make_shared<const MeshOracle>(make_sphere(4));  // 5,120 triangles
  const Model m = mesh_model(oracle);
  for (int shadertoy = 0; shadertoy < 2; ++shadertoy) {
    std::ostringstream out;
    try {
      if (shadertoy) write_shadertoy(out, *m.graph, m.root);
      else write_glsl(out, *m.graph, m.root);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("more than the 65,536"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("--closed-form"), std::string::npos) << e.what();
    }
    EXPECT_EQ(out.str(), "") << "nothing written before the error";
  }
  // Just below: a sphere of 1,280 triangles (and the C export has no limit).
  const auto small = std::make_shared<const MeshOracle>(make_sphere(3));
  const Model s = mesh_model(small);
  EXPECT_NE(export_glsl(*s.graph, s.root).find("sdf_mesh"), std::string::npos);
  EXPECT_NE(export_c(*m.graph, m.root).find("frep_sdf_mesh"), std::string::npos);
}

// ---------------------------------------------------------------------------------------------
// Command line

TEST(MeshExport, CliWritesDataByDefaultAndTheClosedFormOnRequest) {
  ScratchDir dir;
  const TriMesh box = make_box({-1, -0.5, -0.25}, {1, 0.5, 0.25});
  write_text(dir.path("box.stl"), write_mesh_to_string(box, MeshFormat::Stl));
  const CliRun data = run_frep(dir, "export " + shell_quote(dir.path("box.stl")) + " -o " + shell_quote(dir.path("box.c")));
  ASSERT_EQ(data.code, 0) << data.err;
  EXPECT_NE(read_text(dir.path("box.c")).find("frep_sdf_mesh("), std::string::npos);
  for (const char* format : {"c", "glsl", "shadertoy", "latex"}) {
    SCOPED_TRACE(format);
    const CliRun closed = run_frep(dir, "export " + shell_quote(dir.path("box.stl")) + " -f " + format + " --closed-form -o -");
    ASSERT_EQ(closed.code, 0) << closed.err;
    EXPECT_EQ(closed.out.find("_mesh("), std::string::npos);
    EXPECT_GT(closed.out.size(), 500u);
  }
}

// A mesh too big for GLSL's constant arrays is bad input: exit 1, the file named, no output left.
TEST(MeshExport, CliRefusesMeshesTooBigForGlsl) {
  ScratchDir dir;
  write_text(dir.path("ball.stl"), write_mesh_to_string(make_sphere(4), MeshFormat::Stl));  // 5,120 triangles
  const CliRun r = run_frep(dir, "export " + shell_quote(dir.path("ball.stl")) + " -o " + shell_quote(dir.path("ball.glsl")));
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("ball.stl"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--closed-form"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir.path("ball.glsl")));
}

}  // namespace
}  // namespace frep::test
