// The Rhai writer: random expressions over every opcode (with NaN, infinities, signed zeros and
// denormals among the constants) and every shared .vm model read back bit for bit; only Fidget's
// functions appear; `let` only for shared nodes and to bound lines; long and deep expressions
// stay within the line and nesting bounds.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

#include <unistd.h>

#include "frep/eval/evaluators.hpp"
#include "frep/io/vm.hpp"
#include "rhai_test_util.hpp"

namespace frep {
namespace {

namespace fs = std::filesystem;

std::string to_rhai(const Graph& g, NodeId root) {
  std::ostringstream os;
  write_rhai(os, g, root);
  return os.str();
}

// Points: special values on every axis and random ones.
::testing::AssertionResult same_everywhere(const Graph& ga, NodeId ra, const Graph& gb, NodeId rb, std::mt19937_64& rng) {
  const std::vector<float> sp = test::special_floats();
  for (int i = 0; i < 200; ++i) {
    float p[3];
    for (float& c : p) c = (i % 3 == 0) ? sp[rng() % sp.size()] : test::random_float(rng);
    const float a = test::eval_graph<float>(ga, ra, p[0], p[1], p[2]);
    const float b = test::eval_graph<float>(gb, rb, p[0], p[1], p[2]);
    if (!test::same_value(a, b))
      return ::testing::AssertionFailure() << "at (" << test::fstr(p[0]) << ", " << test::fstr(p[1]) << ", "
                                           << test::fstr(p[2]) << "): " << test::fstr(a) << " vs " << test::fstr(b);
  }
  return test::same_field(ga, ra, gb, rb, 3.0f, 100);
}

// Function names used in the text (an identifier followed by `(`).
std::set<std::string> called_functions(const std::string& text) {
  std::set<std::string> out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (!(std::isalpha(static_cast<unsigned char>(text[i])) || text[i] == '_')) continue;
    if (i > 0 && (std::isalnum(static_cast<unsigned char>(text[i - 1])) || text[i - 1] == '_' || text[i - 1] == '.')) continue;
    std::size_t j = i;
    while (j < text.size() && (std::isalnum(static_cast<unsigned char>(text[j])) || text[j] == '_')) ++j;
    if (j < text.size() && text[j] == '(') out.insert(text.substr(i, j - i));
    i = j;
  }
  return out;
}

const std::set<std::string> kFidgetFunctions = {
    "abs", "sqrt", "square", "floor", "ceil", "round", "sin", "cos", "tan", "asin", "acos", "atan", "exp", "ln", "not",
    "min", "max", "compare", "and", "or", "atan2", "parse_float"};

void check_round_trip(const Graph& g, NodeId root, std::mt19937_64& rng, const std::string& what) {
  const std::string text = to_rhai(g, root);
  for (const std::string& f : called_functions(text))
    EXPECT_TRUE(kFidgetFunctions.count(f)) << what << ": `" << f << "` is not one of Fidget's functions";
  Model back;
  try {
    back = parse_rhai(text, what);
  } catch (const InputError& e) {
    FAIL() << what << ": " << e.what() << "\n" << text.substr(0, 2000);
  }
  EXPECT_TRUE(same_everywhere(g, root, *back.graph, back.root, rng)) << what << "\n" << text.substr(0, 2000);
  // The same nodes come back, except that NaN constants with different payloads (which Rhai
  // cannot tell apart) merge.
  bool has_nan = false;
  for (NodeId id : reachable_nodes(g, root)) has_nan |= g.node(id).op == Op::Const && std::isnan(g.node(id).value);
  if (!has_nan) {
    EXPECT_EQ(reachable_nodes(*back.graph, back.root).size(), reachable_nodes(g, root).size()) << what;
  }
}

TEST(RhaiWrite, RandomExpressionsOverEveryOpcodeRoundTrip) {
  std::mt19937_64 rng(2024);
  for (int i = 0; i < 300; ++i) {
    Graph g;
    test::GenOptions opt;
    opt.max_depth = 4 + i % 5;
    opt.special_const_prob = 0.2;
    opt.reuse_prob = 0.15;
    test::ExprGen gen(g, rng, opt);
    const NodeId root = gen.gen();
    check_round_trip(g, root, rng, "random #" + std::to_string(i));
  }
}

TEST(RhaiWrite, EveryOpcodeAndConstantKind) {
  std::mt19937_64 rng(7);
  Graph g;
  const Expr x = g.x(), y = g.y(), z = g.z();
  std::vector<Expr> parts = {-x, abs(x), recip(x), sqrt(x), square(x), floor(x), ceil(x), round(x), sin(x), cos(x),
                             tan(x), asin(x), acos(x), atan(x), exp(x), ln(x), logical_not(x), x + y, x - y, x * y, x / y,
                             atan2(x, y), min(x, y), max(x, y), compare(x, y), mod(x, y), logical_and(x, y),
                             logical_or(x, y), 1.0f / (x + y), -(x * y), x - -2.5f, -0.0f - z, z * 1e-40f, z + 3e38f};
  for (float c : test::special_floats()) parts.push_back(z * c + c);
  for (Expr p : parts) check_round_trip(g, p.id(), rng, "part");
  NodeId all = parts[0].id();
  for (std::size_t i = 1; i < parts.size(); ++i) all = g.binary(i % 2 ? Op::Min : Op::Add, all, parts[i].id());
  check_round_trip(g, all, rng, "all parts");
  // recip is written as a division and mod as `%`.
  const std::string text = to_rhai(g, recip(mod(x, y)).id());
  EXPECT_NE(text.find("1.0 / (x % y)"), std::string::npos) << text;
}

TEST(RhaiWrite, SharedVmModelsRoundTrip) {
  if (!fs::is_directory(test::data_dir())) GTEST_SKIP() << "shared test data not found: " << test::data_dir();
  std::mt19937_64 rng(11);
  int files = 0;
  for (const auto& entry : fs::directory_iterator(test::data_dir())) {
    if (entry.path().extension() != ".vm") continue;
    ++files;
    const Model m = read_vm(entry.path().string());
    check_round_trip(*m.graph, m.root, rng, entry.path().filename().string());
  }
  EXPECT_GE(files, 5);
}

TEST(RhaiWrite, LetOnlyForSharedNodesAndLongLines) {
  Graph g;
  const Expr x = g.x(), y = g.y();
  // A small tree without sharing: one line, no variables. (add and mul print their arguments in
  // node order, so the nodes are made in a fixed order here.)
  const Expr sx = sin(x);
  const Expr cy = cos(y) * 2.0f;
  std::string text = to_rhai(g, (sx + cy).id());
  EXPECT_EQ(text.find("let "), std::string::npos) << text;
  EXPECT_NE(text.find("\nsin(x) + cos(y) * 2.0\n"), std::string::npos) << text;
  // One shared subexpression: exactly one variable, used twice.
  const Expr x2 = square(x);
  const Expr s = sqrt(x2 + square(y));
  text = to_rhai(g, max(s - 1.0f, 0.5f - s).id());
  EXPECT_NE(text.find("let v0 = sqrt(square(x) + square(y));"), std::string::npos) << text;
  EXPECT_EQ(text.find("let v1"), std::string::npos) << text;
  EXPECT_NE(text.find("\nmax(v0 - 1.0, 0.5 - v0)\n"), std::string::npos) << text;
}

TEST(RhaiWrite, DeepAndLongExpressionsStayWithinBounds) {
  std::mt19937_64 rng(3);
  Graph g;
  const Expr x = g.x(), y = g.y();
  // 30,000 nested unary ops, and a 30,000-long chain of min.
  Expr deep = x;
  for (int i = 0; i < 30000; ++i) deep = i % 2 ? sin(deep) : abs(deep + 1.0f);
  Expr chain = x;
  for (int i = 0; i < 30000; ++i) chain = min(chain, y + static_cast<float>(i));
  for (Expr e : {deep, chain}) {
    const std::string text = to_rhai(g, e.id());
    std::istringstream lines(text);
    std::string line;
    while (std::getline(lines, line)) {
      EXPECT_LE(line.size(), 110u) << line;
      int depth = 0, deepest = 0;
      for (char c : line) {
        depth += c == '(';
        depth -= c == ')';
        deepest = std::max(deepest, depth);
      }
      ASSERT_LE(deepest, 13) << line;
    }
    const Model back = parse_rhai(text, "deep");
    const Tape ta = Tape::compile(g, e.id()), tb = Tape::compile(*back.graph, back.root);
    PointEvaluator pe;
    for (int i = 0; i < 20; ++i) {
      const float px = test::random_float(rng), py = test::random_float(rng);
      ASSERT_TRUE(test::same_value(pe.eval(ta, px, py, 0), pe.eval(tb, px, py, 0)));
    }
  }
}

TEST(RhaiWrite, SaveRhaiWritesTheFile) {
  Graph g;
  const Expr e = max(abs(g.x()) - 1.0f, abs(g.y()) - 1.0f);
  const std::string path = (fs::temp_directory_path() / ("frep_rhai_save_" + std::to_string(::getpid()) + ".rhai")).string();
  save_rhai(path, g, e.id());
  const Model back = read_rhai(path);
  EXPECT_TRUE(test::same_field(g, e.id(), *back.graph, back.root));
  fs::remove(path);
}

}  // namespace
}  // namespace frep
