// Symbolic gradients (derivative.hpp) against the forward-mode GradEvaluator: compiled and run by
// the point and batch evaluators at sampled points, for every opcode, random expressions over
// all opcodes, and the shared 3D models. Also the documented conventions, simplification, linear
// cost on shared DAGs, deep graphs without recursion, and .vm round trips.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <sstream>

#include "frep/expr/derivative.hpp"
#include "frep/io/vm.hpp"
#include "test_util.hpp"

namespace frep {
namespace {

using test::fstr;

// The three derivative expressions, compiled.
struct SymGrad {
  Tape t[3];
  SymGrad(Graph& g, const Gradient& gr)
      : t{Tape::compile(g, gr.x.id()), Tape::compile(g, gr.y.id()), Tape::compile(g, gr.z.id())} {}
};

// Equal as values: NaN matches NaN, +0 matches -0.
bool same(float a, float b) { return a == b || (std::isnan(a) && std::isnan(b)); }

// How a comparison went over a set of points.
struct Tally {
  long exact_points = 0;    // intermediates and gradient finite: must match bit for bit
  long special_points = 0;  // some intermediate or derivative infinite or NaN, value finite
  long special_mismatch = 0;
  long both_finite_differ = 0;   // of those: both gradients finite but different
  long only_symbolic_finite = 0;  // the evaluator's NaN/inf where the symbolic one is finite
  long only_evaluator_finite = 0;  // (at finite points)
  double max_rel = 0;       // worst relative difference anywhere the value is finite
};

// Compares symbolic and evaluator gradients of `root` at the given points with the point and the
// batch evaluators; fails on any difference where all intermediates are finite.
void compare_at(Graph& g, NodeId root, const std::vector<test::Point3>& pts, Tally& tally, const std::string& what) {
  const Tape tape = Tape::compile(g, root);
  const Gradient gr = grad(g.expr(root));
  const SymGrad sym(g, gr);
  GradEvaluator ge;
  PointEvaluator pe;
  BatchEvaluator be;
  const std::size_t n = pts.size();
  std::vector<float> xs(n), ys(n), zs(n), batch[3];
  for (std::size_t i = 0; i < n; ++i) xs[i] = pts[i].x, ys[i] = pts[i].y, zs[i] = pts[i].z;
  std::vector<Grad> ref(n);
  ge.eval(tape, xs.data(), ys.data(), zs.data(), ref.data(), n);
  for (int k = 0; k < 3; ++k) {
    batch[k].resize(n);
    be.eval(sym.t[k], xs.data(), ys.data(), zs.data(), batch[k].data(), n);
  }
  std::vector<float> inter;
  int failures = 0;
  for (std::size_t i = 0; i < n && failures < 5; ++i) {
    const float want[3] = {ref[i].dx, ref[i].dy, ref[i].dz};
    float got[3];
    for (int k = 0; k < 3; ++k) {
      got[k] = pe.eval(sym.t[k], xs[i], ys[i], zs[i]);
      ASSERT_TRUE(test::same_value(got[k], batch[k][i])) << what << ": point and batch evaluators disagree";
    }
    test::eval_ssa_all<float>(tape.ssa(), xs[i], ys[i], zs[i], inter);
    // Where an intermediate value or the evaluator's gradient is infinite or NaN, the evaluator
    // may have multiplied an infinite partial by a zero derivative (NaN) where the symbolic
    // gradient dropped the zero term: those points are counted, not required to match.
    const bool all_finite = std::all_of(inter.begin(), inter.end(), [](float v) { return std::isfinite(v); }) &&
                            std::isfinite(want[0]) && std::isfinite(want[1]) && std::isfinite(want[2]);
    bool match = true;
    for (int k = 0; k < 3; ++k) match = match && same(got[k], want[k]);
    if (std::isfinite(ref[i].v)) {
      for (int k = 0; k < 3; ++k)
        if (std::isfinite(want[k]) && std::isfinite(got[k]))
          tally.max_rel = std::max(tally.max_rel, std::fabs(double(got[k]) - want[k]) / (1 + std::fabs(double(want[k]))));
    }
    if (all_finite) {
      ++tally.exact_points;
      if (!match) {
        ++failures;
        ADD_FAILURE() << what << " at (" << fstr(xs[i]) << ", " << fstr(ys[i]) << ", " << fstr(zs[i]) << "): symbolic ("
                      << fstr(got[0]) << ", " << fstr(got[1]) << ", " << fstr(got[2]) << "), evaluator ("
                      << fstr(want[0]) << ", " << fstr(want[1]) << ", " << fstr(want[2]) << ")";
      }
    } else if (std::isfinite(ref[i].v)) {
      ++tally.special_points;
      if (!match) {
        ++tally.special_mismatch;
        bool fg = true, fw = true;
        for (int k = 0; k < 3; ++k) fg = fg && std::isfinite(got[k]), fw = fw && std::isfinite(want[k]);
        if (fg && fw) ++tally.both_finite_differ;
        else if (fg) ++tally.only_symbolic_finite;
        // With an infinite coordinate, a derivative can be inf with no singular op in sight, and
        // a zero partial times it is NaN symbolically but 0 in the evaluator (atan(x * inf)).
        else if (fw && std::isfinite(xs[i]) && std::isfinite(ys[i]) && std::isfinite(zs[i]))
          ++tally.only_evaluator_finite;
      }
    }
  }
}

std::vector<test::Point3> random_points(std::mt19937_64& rng, int n, float range, bool specials) {
  std::vector<test::Point3> pts;
  auto coord = [&] {
    if (specials && rng() % 5 == 0) return test::random_float(rng);
    return std::uniform_real_distribution<float>(-range, range)(rng);
  };
  for (int i = 0; i < n; ++i) pts.push_back({coord(), coord(), coord()});
  // Exact zeros, ties and integers hit the conventions (abs'(0), sqrt'(0), min/max ties).
  for (float a : {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, 2.0f})
    for (float b : {0.0f, 1.0f, -0.5f}) pts.push_back({a, b, a});
  return pts;
}

TEST(Derivative, EveryOpMatchesTheGradientEvaluator) {
  std::mt19937_64 rng(61);
  for (Op op : test::all_ops()) {
    if (op_arity(op) == 0) continue;
    Graph g;
    auto x = g.x(), y = g.y(), z = g.z();
    const Expr u = x * 0.7f + y * 0.2f - z * 0.1f, v = y * 1.5f + z;
    std::vector<NodeId> roots;
    if (op_arity(op) == 1) {
      roots = {g.unary(op, x.id()), g.unary(op, u.id()), g.unary(op, (x * y).id())};
    } else {
      roots = {g.binary(op, x.id(), y.id()), g.binary(op, u.id(), v.id()), g.binary(op, g.constant(1.25f), (x + y).id()),
               g.binary(op, (z - x).id(), g.constant(-0.75f)), g.binary(op, x.id(), x.id()),
               g.binary(op, (x * 3.0f).id(), (y * 2.0f).id())};
    }
    const float range = (op == Op::Asin || op == Op::Acos) ? 1.2f : 4.0f;
    const auto pts = random_points(rng, 300, range, true);
    Tally tally;
    for (NodeId r : roots) compare_at(g, r, pts, tally, std::string(op_name(op)));
    EXPECT_GT(tally.exact_points, 400) << op_name(op);
    EXPECT_EQ(tally.both_finite_differ, 0) << op_name(op);
    EXPECT_EQ(tally.only_evaluator_finite, 0) << op_name(op);
  }
}

TEST(Derivative, RandomExpressionsOverAllOpsMatchTheGradientEvaluator) {
  std::mt19937_64 rng(62);
  Tally tally;
  for (int e = 0; e < 300; ++e) {
    Graph g;
    test::GenOptions opt;
    opt.max_depth = 3 + e % 5;
    test::ExprGen gen(g, rng, opt);
    const NodeId root = gen.gen();
    compare_at(g, root, random_points(rng, 40, 3.0f, e % 3 == 0), tally, "random expression #" + std::to_string(e));
    if (HasFailure()) break;
  }
  EXPECT_GT(tally.exact_points, 4000);
  // Where some intermediate is infinite or NaN the two may differ (derivative.hpp says how), but
  // only by the symbolic gradient being finite where the evaluator's is not (a dropped inf * 0),
  // or by one non-finite value for another (NaN for inf): never two different finite numbers.
  EXPECT_GT(tally.special_points, 500);
  EXPECT_EQ(tally.both_finite_differ, 0);
  EXPECT_EQ(tally.only_evaluator_finite, 0);
  EXPECT_EQ(tally.max_rel, 0.0);
  std::printf("[derivative] random: %ld exact points identical; %ld of %ld points with non-finite intermediates "
              "differ (%ld both finite, %ld only symbolic finite, %ld only evaluator finite); max relative difference %g\n",
              tally.exact_points, tally.special_mismatch, tally.special_points, tally.both_finite_differ,
              tally.only_symbolic_finite, tally.only_evaluator_finite, tally.max_rel);
}

TEST(Derivative, SharedModelsMatchTheGradientEvaluator) {
  for (const char* name : {"bear.vm", "tanglecube.vm"}) {
    if (!test::have_data(name)) GTEST_SKIP() << "shared test data not found: " << test::data_file(name);
    Model m = read_vm(test::data_file(name));
    std::mt19937_64 rng(63);
    std::vector<test::Point3> pts;
    const float range = std::string(name) == "bear.vm" ? 1.2f : 3.5f;
    for (int i = 0; i < 3000; ++i) {
      auto c = [&] { return std::uniform_real_distribution<float>(-range, range)(rng); };
      pts.push_back({c(), c(), c()});
    }
    Tally tally;
    const std::size_t before = m.graph->size();
    compare_at(*m.graph, m.root, pts, tally, name);
    // The bear's exp() overflows to inf over half of this box (its value stays finite).
    EXPECT_GT(tally.exact_points, 1000) << name;
    EXPECT_EQ(tally.both_finite_differ, 0) << name;
    EXPECT_EQ(tally.only_evaluator_finite, 0) << name;
    std::printf("[derivative] %s: %zu nodes, gradient adds %zu; %ld points identical, %ld with non-finite "
                "intermediates (%ld differ, %ld of them with a finite symbolic gradient)\n",
                name, before, m.graph->size() - before, tally.exact_points, tally.special_points,
                tally.special_mismatch, tally.only_symbolic_finite);
  }
}

// Gradients at the points where derivatives do not exist follow evaluators.hpp.
TEST(Derivative, ConventionsWhereTheDerivativeDoesNotExist) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  PointEvaluator pe;
  auto at = [&](Expr e, float px, float py, float pz) {
    const Gradient gr = grad(e);
    std::array<float, 3> r;
    const Expr c[3] = {gr.x, gr.y, gr.z};
    for (int k = 0; k < 3; ++k) r[k] = pe.eval(Tape::compile(g, c[k].id()), px, py, pz);
    return r;
  };
  using A = std::array<float, 3>;
  EXPECT_EQ(at(sqrt(square(x) + square(y) + square(z)), 0, 0, 0), (A{0, 0, 0}));  // sqrt'(0) = 0
  EXPECT_EQ(at(abs(x), 0.0f, 0, 0), (A{1, 0, 0}));                                // abs'(0) = +1
  EXPECT_EQ(at(abs(x), -0.0f, 0, 0), (A{1, 0, 0}));
  EXPECT_EQ(at(abs(x), -2.0f, 0, 0), (A{-1, 0, 0}));
  EXPECT_EQ(at(min(x * 3.0f, y * 2.0f), 2, 3, 0), (A{0, 2, 0}));  // a tie returns the second side
  EXPECT_EQ(at(max(x * 3.0f, y * 2.0f), 2, 3, 0), (A{0, 2, 0}));
  EXPECT_EQ(at(min(x * 3.0f, y * 2.0f), 1, 3, 0), (A{3, 0, 0}));
  EXPECT_EQ(at(max(x * 3.0f, y * 2.0f), 1, 3, 0), (A{0, 2, 0}));
  EXPECT_EQ(at(logical_and(x, y * 5.0f), 0, 1, 0), (A{1, 0, 0}));
  EXPECT_EQ(at(logical_and(x, y * 5.0f), 2, 1, 0), (A{0, 5, 0}));
  EXPECT_EQ(at(logical_or(x, y * 5.0f), 2, 1, 0), (A{1, 0, 0}));
  EXPECT_EQ(at(logical_or(x, y * 5.0f), 0, 1, 0), (A{0, 5, 0}));
  for (Expr e : {floor(x * 2.0f), ceil(x), round(y), compare(x, y), logical_not(x - 0.5f), floor(recip(x))})
    EXPECT_EQ(at(e, 0.0f, 0.25f, 0), (A{0, 0, 0}));
  // The right-angle corner length(max(A, 0), max(B, 0)) has a finite gradient at the corner.
  const A corner = at(sqrt(square(max(x, 0.0f)) + square(max(y, 0.0f))), 0, 0, 0.5f);
  for (float c : corner) EXPECT_TRUE(std::isfinite(c));
  // A zero partial does not multiply an infinite derivative into NaN: d/dx (0 * recip(x)) at 0,
  // where recip' is -inf, is 0 in the evaluator, and so symbolically.
  const A guarded = at(y * recip(x), 0.0f, 0.0f, 0);
  EXPECT_EQ(guarded[0], 0.0f);
  EXPECT_EQ(at(sqrt(square(y) + (asin(x) - asin(g.c(1.0f)))), 1.0f, 0.0f, 0)[0], 0.0f);  // sqrt'(0) * asin'(1)
}

TEST(Derivative, SimplifiedConstantsFoldedZeroTermsDropped) {
  Graph g;
  auto x = g.x(), y = g.y();
  const Gradient a = grad(2.0f * x + y * 3.0f);
  EXPECT_TRUE(g.is_const(a.x.id()) && a.x.node().value == 2.0f);
  EXPECT_TRUE(g.is_const(a.y.id()) && a.y.node().value == 3.0f);
  EXPECT_TRUE(g.is_const(a.z.id()) && a.z.node().value == 0.0f);
  // d/dx (x*y) = y exactly: the node y itself, no "y*1 + x*0".
  const Gradient b = grad(x * y);
  EXPECT_EQ(b.x.id(), y.id());
  EXPECT_EQ(b.y.id(), x.id());
  EXPECT_TRUE(g.is_const(b.z.id()));
  // Only the z-free part: d/dz of a function of x and y is the constant 0.
  EXPECT_TRUE(g.is_const(grad(sin(x) * exp(y) + max(x, y)).z.id()));
  // Shared subexpressions are built once: differentiating twice adds nothing.
  const Expr f = sqrt(square(x - 1.0f) + square(y)) - 0.5f;
  const Gradient g1 = grad(f);
  const std::size_t size = g.size();
  const Gradient g2 = grad(f);
  EXPECT_EQ(g1.x.id(), g2.x.id());
  EXPECT_EQ(g.size(), size);
  // dot() drops zero components: dot(grad x, grad y) is the constant 0.
  EXPECT_TRUE(g.is_const(dot(grad(x), grad(y)).id()));
  EXPECT_EQ(dot(grad(x), grad(x + y)).node().value, 1.0f);
  EXPECT_EQ(grad_dot(3.0f * x, y * 2.0f + x).node().value, 3.0f);
}

// f_{k+1} = f_k * f_k + sin(f_k): a tree expansion would have 2^n terms; the DAG costs O(n).
TEST(Derivative, SharedDagCostsLinearTime) {
  Graph g;
  Expr f = g.x() * 0.5f + g.y();
  const std::size_t before = g.size();
  for (int i = 0; i < 2000; ++i) f = f * f * 0.25f + sin(f);
  const std::size_t nodes = g.size() - before;
  const Gradient gr = grad(f);
  EXPECT_LT(g.size() - before - nodes, 8 * nodes) << "gradient nodes per expression node";
  // Spot-check the value at one point against the evaluator.
  GradEvaluator ge;
  PointEvaluator pe;
  const Grad ref = ge.eval(Tape::compile(g, f.id()), 0.01f, 0.02f, 0);
  EXPECT_TRUE(same(pe.eval(Tape::compile(g, gr.x.id()), 0.01f, 0.02f, 0), ref.dx));
  EXPECT_TRUE(same(pe.eval(Tape::compile(g, gr.y.id()), 0.01f, 0.02f, 0), ref.dy));
}

// A chain 100000 deep (a recursive walk would need a frame per level): nothing recursive, in the differentiator or in the graph code it calls.
TEST(Derivative, DeepChainWithoutRecursion) {
  Graph g;
  Expr f = g.x();
  for (int i = 0; i < 100000; ++i) f = sin(f) + g.y() * 1e-6f;
  const auto t0 = std::chrono::steady_clock::now();
  const Gradient gr = grad(f);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(s, 5.0);
  GradEvaluator ge;
  PointEvaluator pe;
  const Grad ref = ge.eval(Tape::compile(g, f.id()), 0.3f, 0.1f, 0);
  EXPECT_TRUE(same(pe.eval(Tape::compile(g, gr.x.id()), 0.3f, 0.1f, 0), ref.dx));
  EXPECT_TRUE(same(pe.eval(Tape::compile(g, gr.y.id()), 0.3f, 0.1f, 0), ref.dy));
}

// The gradient is made of Fidget opcodes only, so it survives a .vm round trip unchanged.
TEST(Derivative, GradientsWriteToVm) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  const Expr f = max(abs(x) - 1.0f, sqrt(square(y) + square(z)) - 0.5f) / (1.0f + square(x));
  const Gradient gr = grad(f);
  std::mt19937_64 rng(64);
  PointEvaluator pe;
  for (const Expr& c : {gr.x, gr.y, gr.z}) {
    std::ostringstream os;
    write_vm(os, g, c.id());
    const Model m = parse_vm(os.str(), "gradient");
    const Tape a = Tape::compile(g, c.id()), b = Tape::compile(*m.graph, m.root);
    for (int i = 0; i < 200; ++i) {
      const float px = std::uniform_real_distribution<float>(-2, 2)(rng);
      const float py = std::uniform_real_distribution<float>(-2, 2)(rng);
      const float pz = std::uniform_real_distribution<float>(-2, 2)(rng);
      ASSERT_TRUE(test::same_value(pe.eval(a, px, py, pz), pe.eval(b, px, py, pz)));
    }
  }
}

// A choice's derivative is the chosen side's also where that side is exactly 0, so second
// derivatives are right there too: d/dx max(x*y, x*z) = y where x*y wins, and at y = 0 its
// d/dy is 1 (a select falling through to a constant 0 would give 0).
TEST(Derivative, SelectedZeroKeepsItsGradient) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  const Gradient first = grad(max(x * y, x * z));
  const Gradient second = grad(first.x);
  PointEvaluator pe;
  GradEvaluator ge;
  EXPECT_EQ(pe.eval(Tape::compile(g, first.x.id()), 1.0f, 0.0f, -1.0f), 0.0f);
  EXPECT_EQ(pe.eval(Tape::compile(g, second.y.id()), 1.0f, 0.0f, -1.0f), 1.0f);
  EXPECT_EQ(pe.eval(Tape::compile(g, second.z.id()), 1.0f, 0.0f, -1.0f), 0.0f);
  EXPECT_EQ(ge.eval(Tape::compile(g, first.x.id()), 1.0f, 0.0f, -1.0f).dy, 1.0f);
}

// Second derivatives come for free: grad of a gradient component.
TEST(Derivative, SecondDerivatives) {
  Graph g;
  auto x = g.x(), y = g.y();
  const Gradient first = grad(square(x) * y + sin(y));
  Differentiator d(g);
  const Gradient hx = d.grad(first.x);  // (2y, 2x, 0)
  const Gradient hy = d.grad(first.y);  // (2x, -sin y, 0)
  PointEvaluator pe;
  auto ev = [&](Expr e) { return pe.eval(Tape::compile(g, e.id()), 1.5f, 0.5f, 0); };
  EXPECT_FLOAT_EQ(ev(hx.x), 1.0f);
  EXPECT_FLOAT_EQ(ev(hx.y), 3.0f);
  EXPECT_FLOAT_EQ(ev(hy.x), 3.0f);
  EXPECT_FLOAT_EQ(ev(hy.y), -std::sin(0.5f));
}

}  // namespace
}  // namespace frep
