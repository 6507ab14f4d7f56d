// Fidget's example models (../shared/data/rhai): every script loads and evaluates, and sponge,
// cabin and gyroid-sphere equal the same models written in C++ with frep::Expr, bit for bit.
// load_expression picks the Rhai reader by extension and by content.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "frep/eval/evaluators.hpp"
#include "frep/script/load.hpp"
#include "rhai_test_util.hpp"

namespace frep {
namespace {

namespace fs = std::filesystem;
using test::same_field;

float F(double v) { return static_cast<float>(v); }  // a script's number, as the reader rounds it

#define FREP_REQUIRE_RHAI(name)                                                                    \
  do {                                                                                             \
    if (!fs::exists(test::shared_rhai_dir() + "/" name))                                           \
      GTEST_SKIP() << "shared test data not found: " << test::shared_rhai_dir() << "/" name;     \
  } while (0)

TEST(RhaiModels, EverySharedScriptLoadsAndEvaluates) {
  if (!fs::is_directory(test::shared_rhai_dir())) GTEST_SKIP() << "shared test data not found: " << test::shared_rhai_dir();
  int files = 0;
  for (const auto& entry : fs::directory_iterator(test::shared_rhai_dir())) {
    if (entry.path().extension() != ".rhai") continue;
    ++files;
    SCOPED_TRACE(entry.path().string());
    const Model m = load_expression(entry.path().string());
    const Tape t = Tape::compile(*m.graph, m.root);
    EXPECT_EQ(t.vars_used(), 7) << "Fidget's examples are 3D";
    // The tape agrees with the graph, and the field is finite somewhere and changes sign.
    PointEvaluator pe;
    int negative = 0, positive = 0;
    for (const test::Point3& p : test::sample_points(1.0f, 300, 5)) {
      for (float s : {1.0f, 20.0f}) {  // cabin is 20 units across, the others 1
        const float v = pe.eval(t, s * p.x, s * p.y, s * p.z);
        ASSERT_TRUE(test::same_value(v, test::eval_graph<float>(*m.graph, m.root, s * p.x, s * p.y, s * p.z)));
        negative += v < 0;
        positive += v > 0;
      }
    }
    EXPECT_GT(negative, 10);
    EXPECT_GT(positive, 10);
  }
  EXPECT_GE(files, 3);
}

// sponge.rhai in C++: remap(x, y, z -> X, Y, Z) is the same formula built from X, Y, Z.
Expr sponge_recurse(Expr X, Expr Y, Expr Z, int depth) {
  auto r = [](Expr t) { return abs(mod(t + 1.0f, 2.0f) - 1.0f); };
  auto base = [&](Expr a, Expr b) { return max(r(a), r(b)) - F(1 / 3.); };
  // out_k(X, Y) = min(base(X, Y), out_{k-1}(3X, 3Y))
  if (depth == 0) return base(X, Y);
  return min(base(X, Y), sponge_recurse(X * 3.0f, Y * 3.0f, Z, depth - 1));
}

Expr sponge_xy(Expr X, Expr Y, Expr Z) {
  const Expr square = max(abs(X) - 1.0f, abs(Y) - 1.0f);
  return max(square, -sponge_recurse(X, Y, Z, 3));
}

TEST(RhaiModels, SpongeEqualsTheSameModelInCpp) {
  FREP_REQUIRE_RHAI("sponge.rhai");
  const Model m = load_expression(test::shared_rhai_dir() + "/sponge.rhai");
  Graph g;
  const Expr x = g.x(), y = g.y(), z = g.z();
  const Expr radius = sqrt(square(x) + square(y) + square(z));
  const Expr manhattan = max(abs(x), max(abs(y), abs(z)));
  const Expr rescale = manhattan / radius;
  const Expr r = rescale * 1.0f + 0.0f;  // blend = 1.0: (rescale * blend) + (1.0 - blend)
  const Expr A = x / r, B = y / r, C = z / r;
  const Expr sponge = max(max(sponge_xy(A, B, C), sponge_xy(B, C, A)), sponge_xy(C, A, B));
  EXPECT_TRUE(same_field(*m.graph, m.root, g, sponge.id(), 1.2f, 500));
  // And it is a sphere-ified Menger sponge: (0.95, 0.95, 0.95) is solid at every level of the
  // cube sponge and maps to 0.95 / sqrt(3) on the diagonal; the central hole along z is empty;
  // far outside is empty.
  const float d = 0.95f / std::sqrt(3.0f);
  EXPECT_LT(test::eval_graph<float>(*m.graph, m.root, d, d, d), 0.0f);
  EXPECT_GT(test::eval_graph<float>(*m.graph, m.root, 0.0f, 0.0f, 0.5f), 0.0f);
  EXPECT_GT(test::eval_graph<float>(*m.graph, m.root, 2.0f, 2.0f, 2.0f), 0.0f);
}

TEST(RhaiModels, CabinEqualsTheSameModelInCpp) {
  FREP_REQUIRE_RHAI("cabin.rhai");
  const Model m = load_expression(test::shared_rhai_dir() + "/cabin.rhai");
  Graph g;
  const Expr x = g.x(), y = g.y(), z = g.z();
  auto logs = [](Expr X, Expr Y) {
    return abs(X) - 10.0f - sqrt(max(F(0.05), 1.0f - square(mod(Y, 2.0f) - 1.0f)));
  };
  Expr cabin = max(logs(x, z), logs(y, z));  // logs.remap(x, z, y), logs.remap(y, z, x)
  Expr roof = z / 2.0f + abs(y) / 2.0f - 15.0f;
  const Expr lower_roof = -roof;
  const Expr upper_roof = roof - 1.0f + abs(mod(-abs(y) / 2.0f + z / 2.0f, 1.0f) - F(0.5)) / 4.0f;
  cabin = max(cabin, upper_roof);
  roof = max(lower_roof, upper_roof);
  const Expr x_clamp = abs(x) - 13.0f;
  roof = max(max(x_clamp, roof), 18.0f - z);
  Expr door_frame = max(abs(y) - 5.0f, z - 14.0f);
  const Expr door_frame_inner = -(door_frame + F(1.5));
  const Expr door_width = max(10.0f - x, x - 11.0f);
  door_frame = max(max(door_frame, door_frame_inner), door_width);
  auto doorknob = [](Expr X, Expr Y, Expr Z) { return sqrt(square(X) + square(Y) + square(Z)) - F(0.6); };
  const Expr door = min(door_frame, doorknob(x - F(10.5), y - 2.0f, z - 6.0f));
  cabin = max(cabin, -max(-door_frame_inner, door_width));
  cabin = min(cabin, door);
  const Expr window_root = max(abs(x), abs(z - 9.0f));
  cabin = max(cabin, -max(window_root - 4.0f, 10.0f - abs(y)));
  const Expr window_cross = max(window_root - 4.0f, min(abs(x) - F(0.2), abs(z - 9.0f) - F(0.2)));
  const Expr window_frame = max(window_root - 4.0f, 3.0f - window_root);
  cabin = min(cabin, max(min(window_frame, window_cross), abs(y) - 11.0f));
  cabin = min(cabin, max(window_root - 3.0f, abs(y) - F(10.6)));
  cabin = min(max(-z, cabin), roof);
  EXPECT_TRUE(same_field(*m.graph, m.root, g, cabin.id(), 20.0f, 500));
}

TEST(RhaiModels, GyroidSphereEqualsTheSameModelInCpp) {
  FREP_REQUIRE_RHAI("gyroid-sphere.rhai");
  const Model m = load_expression(test::shared_rhai_dir() + "/gyroid-sphere.rhai");
  Graph g;
  const Expr x = g.x() * 30.0f, y = g.y() * 30.0f, z = g.z() * 30.0f;
  const Expr gyroid = sin(x) * cos(y) + sin(y) * cos(z) + sin(z) * cos(x);
  const Expr fill = abs(gyroid) - F(0.2);
  const Expr sphere = sqrt(square(x) + square(y) + square(z)) - 25.0f;
  EXPECT_TRUE(same_field(*m.graph, m.root, g, max(sphere, fill).id(), 1.0f, 500));
}

// load_expression: `.rhai` by extension; without a known extension, by content.
TEST(RhaiModels, LoadExpressionPicksTheReaderByExtensionAndContent) {
  const fs::path dir = fs::temp_directory_path() / ("frep_rhai_load_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  };
  const std::string script = "let sqrt = 0.5;\nsqrt(x * x + y * y) - sqrt\n";  // `let sqrt` is not `<id> <opcode>`
  const std::string vm = "# a circle\n_0 var-x\n_1 var-y\n_2 square _0\n_3 square _1\n_4 add _2 _3\n_5 sqrt _4\n"
                         "_6 const 0.5\n_7 sub _5 _6\n";
  for (const std::string& name : {std::string("c.rhai"), std::string("c.txt"), std::string("c")}) {
    const Model m = load_expression(write(name, script));
    EXPECT_FLOAT_EQ(test::eval_graph<float>(*m.graph, m.root, 1, 0, 0), 0.5f) << name;
  }
  for (const std::string& name : {std::string("v.vm"), std::string("v.txt"), std::string("v")}) {
    const Model m = load_expression(write(name, vm));
    EXPECT_FLOAT_EQ(test::eval_graph<float>(*m.graph, m.root, 1, 0, 0), 0.5f) << name;
  }
  // A .rhai file is never read as .vm, and errors name the file and line.
  try {
    load_expression(write("bad.rhai", "let a = 1;\nlet b = ;\n"));
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2u);
    EXPECT_NE(std::string(e.what()).find("bad.rhai:2: column 9:"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace frep
