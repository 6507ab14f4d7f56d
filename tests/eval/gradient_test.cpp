// Gradients: the forward-mode GradEvaluator against central differences of the expression
// evaluated in double precision, per op and on random smooth expressions, plus the documented
// conventions where the derivative does not exist.
#include <gtest/gtest.h>

#include <array>

#include "frep/expr/expr.hpp"
#include "test_util.hpp"

namespace frep {
namespace {

using test::fstr;

// My own derivative table in double (independent of grad_eval.cpp): (dv/da, dv/db).
void dpartials(Op op, double a, double b, double v, double& pa, double& pb) {
  pa = pb = 0;
  switch (op) {
    case Op::Neg: pa = -1; break;
    case Op::Abs: pa = a < 0 ? -1 : 1; break;
    case Op::Recip: pa = -1 / (a * a); break;
    case Op::Sqrt: pa = 0.5 / v; break;
    case Op::Square: pa = 2 * a; break;
    case Op::Sin: pa = std::cos(a); break;
    case Op::Cos: pa = -std::sin(a); break;
    case Op::Tan: pa = 1 / (std::cos(a) * std::cos(a)); break;
    case Op::Asin: pa = 1 / std::sqrt(1 - a * a); break;
    case Op::Acos: pa = -1 / std::sqrt(1 - a * a); break;
    case Op::Atan: pa = 1 / (1 + a * a); break;
    case Op::Exp: pa = std::exp(a); break;
    case Op::Ln: pa = 1 / a; break;
    case Op::Add: pa = 1, pb = 1; break;
    case Op::Sub: pa = 1, pb = -1; break;
    case Op::Mul: pa = b, pb = a; break;
    case Op::Div: pa = 1 / b, pb = -a / (b * b); break;
    case Op::Atan2: pa = b / (a * a + b * b), pb = -a / (a * a + b * b); break;
    case Op::Min: (a < b ? pa : pb) = 1; break;
    case Op::Max: (a > b ? pa : pb) = 1; break;
    default: break;
  }
}

// Is the double-precision evaluation at this point far from every kink, pole and domain edge?
bool well_conditioned(std::span<const SsaInstr> ssa, const std::vector<double>& v) {
  for (std::size_t i = 0; i < ssa.size(); ++i) {
    if (!std::isfinite(v[i]) || std::fabs(v[i]) > 1e5) return false;
    const SsaInstr& s = ssa[i];
    if (op_arity(s.op) == 0) continue;
    const double a = v[s.a], b = op_arity(s.op) == 2 ? v[s.b] : 0;
    const double scale = 1e-2 * (1 + std::fabs(a) + std::fabs(b));
    switch (s.op) {
      case Op::Sqrt:
      case Op::Ln:
      case Op::Recip:
      case Op::Abs:
        if (std::fabs(a) < 1e-2) return false;
        break;
      case Op::Div:
        if (std::fabs(b) < 1e-2) return false;
        break;
      case Op::Atan2:
        if (a * a + b * b < 1e-3) return false;
        break;
      case Op::Asin:
      case Op::Acos:
        if (std::fabs(a) > 0.98) return false;
        break;
      case Op::Tan:
        if (std::fabs(std::cos(a)) < 0.05) return false;
        break;
      case Op::Min:
      case Op::Max:
        if (std::fabs(a - b) < scale) return false;
        break;
      default:
        break;
    }
  }
  return true;
}

// d/d(axis) by central differences in double; nullopt-like NaN if h and h/2 disagree.
double central_difference(std::span<const SsaInstr> ssa, double p[3], int axis) {
  auto f = [&](double delta) {
    double q[3] = {p[0], p[1], p[2]};
    q[axis] += delta;
    return test::eval_ssa<double>(ssa, q[0], q[1], q[2]);
  };
  const double h = 1e-5 * std::max(1.0, std::fabs(p[axis]));
  const double d1 = (f(h) - f(-h)) / (2 * h);
  const double d2 = (f(h / 2) - f(-h / 2)) / h;
  if (!(std::fabs(d1 - d2) <= 1e-6 * (1 + std::fabs(d1)))) return std::numeric_limits<double>::quiet_NaN();
  return d2;
}

// Sum over paths of |partial products|: how large cancellation can make float rounding errors.
std::array<double, 3> abs_gradient(std::span<const SsaInstr> ssa, const std::vector<double>& v) {
  std::vector<std::array<double, 3>> m(ssa.size());
  for (std::size_t i = 0; i < ssa.size(); ++i) {
    const SsaInstr& s = ssa[i];
    m[i] = {0, 0, 0};
    if (s.op == Op::VarX) m[i][0] = 1;
    if (s.op == Op::VarY) m[i][1] = 1;
    if (s.op == Op::VarZ) m[i][2] = 1;
    if (op_arity(s.op) == 0) continue;
    double pa, pb;
    const bool bin = op_arity(s.op) == 2;
    dpartials(s.op, v[s.a], bin ? v[s.b] : 0, v[i], pa, pb);
    for (int k = 0; k < 3; ++k) m[i][k] = std::fabs(pa) * m[s.a][k] + (bin ? std::fabs(pb) * m[s.b][k] : 0);
  }
  return m.back();
}

struct Stats {
  int compared = 0, skipped = 0;
};

// Compares the gradient evaluator with central differences at one point; returns false on failure.
bool check_point(const Tape& t, GradEvaluator& ge, float x, float y, float z, Stats& st, const std::string& what) {
  std::vector<double> v;
  test::eval_ssa_all<double>(t.ssa(), x, y, z, v);
  if (!well_conditioned(t.ssa(), v)) {
    ++st.skipped;
    return true;
  }
  double p[3] = {x, y, z};
  const Grad g = ge.eval(t, x, y, z);
  const float gd[3] = {g.dx, g.dy, g.dz};
  const std::array<double, 3> mag = abs_gradient(t.ssa(), v);
  double fd[3];
  for (int k = 0; k < 3; ++k) {
    fd[k] = central_difference(t.ssa(), p, k);
    if (std::isnan(fd[k])) {
      ++st.skipped;
      return true;
    }
  }
  ++st.compared;
  for (int k = 0; k < 3; ++k) {
    const double tol = 1e-3 * std::fabs(fd[k]) + 1e-4 * mag[k] + 1e-6;
    if (!(std::fabs(gd[k] - fd[k]) <= tol)) {
      ADD_FAILURE() << what << ": d/d" << "xyz"[k] << " at (" << fstr(x) << ", " << fstr(y) << ", " << fstr(z)
                    << ") is " << fstr(gd[k]) << ", central difference " << fd[k] << " (tolerance " << tol << ")";
      return false;
    }
  }
  return true;
}

TEST(Gradient, EveryDifferentiableUnaryOpAgainstCentralDifferences) {
  std::mt19937_64 rng(51);
  GradEvaluator ge;
  for (Op op : {Op::Neg, Op::Abs, Op::Recip, Op::Sqrt, Op::Square, Op::Sin, Op::Cos, Op::Tan, Op::Asin, Op::Acos,
                Op::Atan, Op::Exp, Op::Ln}) {
    Graph g;
    auto x = g.x(), y = g.y(), z = g.z();
    // The argument mixes all three variables so every component of the chain rule is exercised.
    const Tape t = Tape::compile(g, g.unary(op, (x * 0.7f + y * 0.2f - z * 0.1f).id()));
    const Tape plain = Tape::compile(g, g.unary(op, x.id()));
    Stats st;
    for (int i = 0; i < 400; ++i) {
      const float range = (op == Op::Asin || op == Op::Acos) ? 1.0f : 4.0f;
      const float px = std::uniform_real_distribution<float>(-range, range)(rng);
      const float py = std::uniform_real_distribution<float>(-range, range)(rng);
      const float pz = std::uniform_real_distribution<float>(-range, range)(rng);
      if (!check_point(t, ge, px, py, pz, st, std::string(op_name(op)))) break;
      if (!check_point(plain, ge, px, py, pz, st, std::string(op_name(op)) + "(x)")) break;
      // The analytic derivative, directly.
      std::vector<double> v;
      test::eval_ssa_all<double>(plain.ssa(), px, py, pz, v);
      if (well_conditioned(plain.ssa(), v)) {
        double pa, pb;
        dpartials(op, px, 0, v.back(), pa, pb);
        const Grad gr = ge.eval(plain, px, py, pz);
        EXPECT_NEAR(gr.dx, pa, 1e-5 * (1 + std::fabs(pa))) << op_name(op) << "'(" << fstr(px) << ")";
        EXPECT_EQ(gr.dy, 0.0f);
        EXPECT_EQ(gr.dz, 0.0f);
      }
    }
    EXPECT_GT(st.compared, 300) << op_name(op) << ": too many points skipped";
  }
}

TEST(Gradient, EveryDifferentiableBinaryOpAgainstCentralDifferences) {
  std::mt19937_64 rng(52);
  GradEvaluator ge;
  for (Op op : {Op::Add, Op::Sub, Op::Mul, Op::Div, Op::Atan2, Op::Min, Op::Max}) {
    Graph g;
    auto x = g.x(), y = g.y(), z = g.z();
    const Tape t1 = Tape::compile(g, g.binary(op, x.id(), y.id()));
    const Tape t2 = Tape::compile(g, g.binary(op, (x - z * 0.5f).id(), (y * 1.5f + z).id()));
    const Tape t3 = Tape::compile(g, g.binary(op, g.constant(1.25f), (x + y).id()));
    const Tape t4 = Tape::compile(g, g.binary(op, (z - x).id(), g.constant(-0.75f)));
    Stats st;
    for (int i = 0; i < 400; ++i) {
      const float px = std::uniform_real_distribution<float>(-4, 4)(rng);
      const float py = std::uniform_real_distribution<float>(-4, 4)(rng);
      const float pz = std::uniform_real_distribution<float>(-4, 4)(rng);
      bool ok = check_point(t1, ge, px, py, pz, st, std::string(op_name(op)) + "(x, y)") &&
                check_point(t2, ge, px, py, pz, st, std::string(op_name(op)) + "(x - z/2, 1.5y + z)") &&
                check_point(t3, ge, px, py, pz, st, std::string(op_name(op)) + "(1.25, x + y)") &&
                check_point(t4, ge, px, py, pz, st, std::string(op_name(op)) + "(z - x, -0.75)");
      if (!ok) break;
    }
    EXPECT_GT(st.compared, 1200) << op_name(op) << ": too many points skipped";
  }
}

TEST(Gradient, RandomSmoothExpressionsAgainstCentralDifferences) {
  std::mt19937_64 rng(53);
  GradEvaluator ge;
  Stats st;
  for (int e = 0; e < 500; ++e) {
    Graph g;
    test::GenOptions opt;
    opt.max_depth = 3 + e % 4;
    opt.special_const_prob = 0;
    opt.const_range = 2;
    opt.ops = {Op::Neg, Op::Abs, Op::Square, Op::Sqrt, Op::Sin, Op::Cos, Op::Atan, Op::Exp, Op::Add, Op::Sub,
               Op::Mul, Op::Div, Op::Min, Op::Max, Op::Recip, Op::Atan2, Op::Add, Op::Mul, Op::Sub, Op::Ln};
    test::ExprGen gen(g, rng, opt);
    const Tape t = Tape::compile(g, gen.gen());
    for (int i = 0; i < 40; ++i) {
      const float px = std::uniform_real_distribution<float>(-2, 2)(rng);
      const float py = std::uniform_real_distribution<float>(-2, 2)(rng);
      const float pz = std::uniform_real_distribution<float>(-2, 2)(rng);
      if (!check_point(t, ge, px, py, pz, st, "random expression #" + std::to_string(e))) return;
    }
  }
  EXPECT_GT(st.compared, 2000) << "skipped " << st.skipped;
  RecordProperty("compared", st.compared);
  RecordProperty("skipped", st.skipped);
}

TEST(Gradient, BatchedEqualsSinglePointBitForBit) {
  test::for_each_simd_target([&] {
    std::mt19937_64 rng(54);
    Graph g;
    auto x = g.x(), y = g.y(), z = g.z();
    const Tape t = Tape::compile(g, (sin(x * y) + sqrt(square(x) + square(z)) * atan2(y, z) - min(x, exp(z))).id());
    const std::size_t n = 300;
    std::vector<float> xs(n), ys(n), zs(n);
    for (std::size_t i = 0; i < n; ++i) xs[i] = test::random_float(rng), ys[i] = test::random_float(rng), zs[i] = test::random_float(rng);
    GradEvaluator ge;
    std::vector<Grad> all(n);
    ge.eval(t, xs.data(), ys.data(), zs.data(), all.data(), n);
    for (std::size_t i = 0; i < n; ++i) {
      const Grad one = ge.eval(t, xs[i], ys[i], zs[i]);
      ASSERT_TRUE(test::same_value(one.v, all[i].v) && test::same_value(one.dx, all[i].dx) &&
                  test::same_value(one.dy, all[i].dy) && test::same_value(one.dz, all[i].dz))
          << "point " << i;
    }
  });
}

// Values and all three partials are bit-identical on every SIMD target (AVX-512, AVX2, SSE4...).
TEST(Gradient, EverySimdTargetGivesTheSameBits) {
  std::mt19937_64 rng(2026);
  for (int trial = 0; trial < 40; ++trial) {
    Graph g;
    test::ExprGen gen(g, rng, {});
    const Tape t = Tape::compile(g, gen.gen());
    const std::size_t n = 100;
    std::vector<float> xs(n), ys(n), zs(n);
    for (std::size_t i = 0; i < n; ++i) xs[i] = test::random_float(rng), ys[i] = test::random_float(rng), zs[i] = test::random_float(rng);
    std::vector<Grad> ref;
    test::for_each_simd_target([&] {
      GradEvaluator ge;
      std::vector<Grad> got(n);
      ge.eval(t, xs.data(), ys.data(), zs.data(), got.data(), n);
      if (ref.empty()) return ref = got, void();
      for (std::size_t i = 0; i < n; ++i)
        ASSERT_TRUE(test::same_value(ref[i].v, got[i].v) && test::same_value(ref[i].dx, got[i].dx) &&
                    test::same_value(ref[i].dy, got[i].dy) && test::same_value(ref[i].dz, got[i].dz))
            << "trial " << trial << " point " << i << ": " << test::fstr(ref[i].v) << " " << test::fstr(ref[i].dx) << " "
            << test::fstr(ref[i].dy) << " " << test::fstr(ref[i].dz) << " vs " << test::fstr(got[i].v) << " "
            << test::fstr(got[i].dx) << " " << test::fstr(got[i].dy) << " " << test::fstr(got[i].dz) << "\n"
            << [&] {
                 std::string d;
                 for (const SsaInstr& ins : t.ssa())
                   d += std::string(op_name(ins.op)) + " " + std::to_string(ins.a) + " " + std::to_string(ins.b) + "; ";
                 return d;
               }();
    });
  }
}

// Documented conventions (evaluators.hpp): sqrt'(0) = 0, abs'(0) = +1, min/max/and/or take the
// gradient of the side they return, floor/ceil/round/compare/not have gradient 0.
TEST(GradientConventions, SqrtOfZeroHasZeroGradientSoDistancesAreFiniteOnTheirZeroSet) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  GradEvaluator ge;
  const Tape r = Tape::compile(g, sqrt(square(x) + square(y)).id());
  const Grad o = ge.eval(r, 0, 0, 0);
  EXPECT_EQ(o.v, 0.0f);
  EXPECT_EQ(o.dx, 0.0f);
  EXPECT_EQ(o.dy, 0.0f);
  EXPECT_EQ(o.dz, 0.0f);
  const Grad o3 = ge.eval(Tape::compile(g, sqrt(square(x - 1) + square(y) + square(z)).id()), 1, 0, 0);
  EXPECT_TRUE(std::isfinite(o3.dx) && std::isfinite(o3.dy) && std::isfinite(o3.dz));
  EXPECT_EQ(o3.dx, 0.0f);
  // On a distance-to-edge curve (a segment along x) the gradient is finite everywhere.
  auto t = min(max(x, 0.0f), 1.0f);
  const Tape seg = Tape::compile(g, sqrt(square(x - t) + square(y) + square(z)).id());
  for (float px : {-0.5f, 0.0f, 0.25f, 0.5f, 1.0f, 1.5f}) {
    const Grad gr = ge.eval(seg, px, 0, 0);
    EXPECT_TRUE(std::isfinite(gr.dx) && std::isfinite(gr.dy) && std::isfinite(gr.dz)) << "x = " << px;
  }
  // sqrt itself at 0 and -0.
  const Tape s = Tape::compile(g, sqrt(x).id());
  EXPECT_EQ(ge.eval(s, 0.0f, 0, 0).dx, 0.0f);
  EXPECT_EQ(ge.eval(s, -0.0f, 0, 0).dx, 0.0f);
}

TEST(GradientConventions, AbsAtZeroIsPlusOne) {
  Graph g;
  GradEvaluator ge;
  const Tape t = Tape::compile(g, abs(g.x()).id());
  EXPECT_EQ(ge.eval(t, 0.0f, 0, 0).dx, 1.0f);
  EXPECT_EQ(ge.eval(t, -0.0f, 0, 0).dx, 1.0f);
  EXPECT_EQ(ge.eval(t, -2.0f, 0, 0).dx, -1.0f);
  EXPECT_EQ(ge.eval(t, 3.0f, 0, 0).dx, 1.0f);
}

// Gradient of the side op_eval returns (for min/max on a tie that is the second argument as
// stored in the tape, whatever order the graph chose).
TEST(GradientConventions, ChoicesTakeTheGradientOfTheReturnedSide) {
  Graph g;
  auto x = g.x(), y = g.y();
  GradEvaluator ge;
  auto grad_of = [&](const Tape& t, float px, float py) { return ge.eval(t, px, py, 0); };
  for (Op op : {Op::Min, Op::Max}) {
    const NodeId lhs = (x * 3.0f).id(), rhs = (y * 2.0f).id();
    const Tape t = Tape::compile(g, g.binary(op, lhs, rhs));
    // Strict cases.
    Grad a = grad_of(t, 1, 1);  // 3 vs 2
    Grad b = grad_of(t, -1, 1);  // -3 vs 2
    const bool max = op == Op::Max;
    EXPECT_EQ(a.dx, max ? 3.0f : 0.0f);
    EXPECT_EQ(a.dy, max ? 0.0f : 2.0f);
    EXPECT_EQ(b.dx, max ? 0.0f : 3.0f);
    EXPECT_EQ(b.dy, max ? 2.0f : 0.0f);
    // Tie at 3x = 2y: the returned side is the tape's second argument.
    const SsaInstr& root = t.ssa().back();
    const bool second_is_y = t.ssa()[root.b].op == Op::Mul && t.ssa()[t.ssa()[root.b].a].op == Op::VarY;
    const Grad tie = grad_of(t, 2, 3);
    EXPECT_EQ(tie.v, 6.0f);
    EXPECT_EQ(tie.dx, second_is_y ? 0.0f : 3.0f) << op_name(op);
    EXPECT_EQ(tie.dy, second_is_y ? 2.0f : 0.0f) << op_name(op);
  }
  // and(c, b) = c == 0 ? c : b; or(c, b) = c != 0 ? c : b.
  const Tape ta = Tape::compile(g, logical_and(x, y * 5.0f).id());
  EXPECT_EQ(grad_of(ta, 0, 1).dx, 1.0f);
  EXPECT_EQ(grad_of(ta, 0, 1).dy, 0.0f);
  EXPECT_EQ(grad_of(ta, 2, 1).dx, 0.0f);
  EXPECT_EQ(grad_of(ta, 2, 1).dy, 5.0f);
  const Tape to = Tape::compile(g, logical_or(x, y * 5.0f).id());
  EXPECT_EQ(grad_of(to, 2, 1).dx, 1.0f);
  EXPECT_EQ(grad_of(to, 2, 1).dy, 0.0f);
  EXPECT_EQ(grad_of(to, 0, 1).dx, 0.0f);
  EXPECT_EQ(grad_of(to, 0, 1).dy, 5.0f);
  // Select: if_nonzero_else(x, 2y, 3y).
  const Tape sel = Tape::compile(g, if_nonzero_else(x, y * 2.0f, y * 3.0f).id());
  EXPECT_EQ(grad_of(sel, 1, 1).dy, 2.0f);
  EXPECT_EQ(grad_of(sel, 0, 1).dy, 3.0f);
}

TEST(GradientConventions, PiecewiseConstantOpsHaveZeroGradient) {
  Graph g;
  auto x = g.x(), y = g.y();
  GradEvaluator ge;
  for (NodeId id : {floor(x * 2.0f).id(), ceil(x * 2.0f).id(), round(x * 2.0f).id(), compare(x, y).id(),
                    logical_not(x - 0.5f).id()}) {
    const Tape t = Tape::compile(g, id);
    for (float px : {-1.3f, 0.0f, 0.5f, 0.7f, 2.0f}) {
      const Grad gr = ge.eval(t, px, 0.25f, 0);
      EXPECT_EQ(gr.dx, 0.0f);
      EXPECT_EQ(gr.dy, 0.0f);
      EXPECT_EQ(gr.dz, 0.0f);
    }
  }
  // A zero partial does not turn an infinite argument gradient into NaN: recip'(0) = -inf, and
  // floor of it has gradient 0.
  const Tape t = Tape::compile(g, floor(recip(x)).id());
  const Grad gr = ge.eval(t, 0.0f, 0, 0);
  EXPECT_EQ(gr.dx, 0.0f);
}

TEST(Gradient, ModAndRoundingOpsAwayFromDiscontinuities) {
  Graph g;
  auto x = g.x(), y = g.y();
  GradEvaluator ge;
  const Tape t = Tape::compile(g, mod(x * 3.0f, y + 5.0f).id());
  std::mt19937_64 rng(55);
  Stats st;
  for (int i = 0; i < 300; ++i) {
    const float px = std::uniform_real_distribution<float>(-6, 6)(rng);
    const float py = std::uniform_real_distribution<float>(-8, 8)(rng);
    std::vector<double> v;
    test::eval_ssa_all<double>(t.ssa(), px, py, 0, v);
    const double b = std::fabs(py + 5.0), r = v.back();
    if (b < 0.1 || r < 1e-2 || r > b - 1e-2) continue;  // near a jump
    if (!check_point(t, ge, px, py, 0, st, "mod(3x, y + 5)")) break;
  }
  EXPECT_GT(st.compared, 150);
}

}  // namespace
}  // namespace frep
