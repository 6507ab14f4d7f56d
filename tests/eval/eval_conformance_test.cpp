// One conformance suite, written once and run against every evaluator: the point evaluator, the
// batch evaluator at several batch sizes, the gradient evaluator's value output (several batch
// sizes) and the interval evaluator on degenerate boxes [v, v] (which must contain the point
// value). Exact evaluators must be bit-identical to op_eval<float> (or NaN where it is NaN).
#include <gtest/gtest.h>

#include <optional>

#include <algorithm>
#include <cstring>
#include <functional>
#include <memory>
#include <string>

#include "frep/convert/mesh_oracle.hpp"
#include "frep/eval/interval_batch.hpp"
#include "frep/eval/jit.hpp"
#include "frep/eval/point_cloud.hpp"
#include "frep/expr/expr.hpp"
#include "mesh_test_util.hpp"
#include "test_util.hpp"

namespace frep {
namespace {

using test::fstr;
using test::same_value;

// ---------------------------------------------------------------------------------------------
// The reference semantics themselves, against the rules docs/engine.md lists ("Expressions"), in
// float and double.

template <class T>
void check_semantics_rules() {
  const T nan = std::numeric_limits<T>::quiet_NaN();
  const T inf = std::numeric_limits<T>::infinity();
  const std::vector<T> vals = {T(0), -T(0), T(1), T(-1), T(0.5), T(-0.5), T(1.5), T(-1.5), T(2.5), T(-2.5),
                               T(3), T(-7), inf, -inf, nan, T(1e-40), T(-1e-40), T(1e30), T(-1e30)};
  for (T a : vals) {
    // not(a) = a == 0 ? 1 : 0, NaN non-zero.
    EXPECT_TRUE(same_value(static_cast<double>(op_eval<T>(Op::Not, a, 0)), std::isnan(a) ? 0.0 : (a == 0 ? 1.0 : 0.0)));
    // round halves away from zero.
    if (std::isfinite(a) && std::fabs(a) < T(1e6)) {
      const T r = op_eval<T>(Op::Round, a, 0);
      const T frac = std::fabs(a - std::trunc(a));
      const T expect = frac >= T(0.5) ? std::trunc(a) + std::copysign(T(1), a) : std::trunc(a);
      EXPECT_EQ(r, expect) << "round(" << a << ")";
    }
    for (T b : vals) {
      const T cmp = op_eval<T>(Op::Compare, a, b);
      if (std::isnan(a) || std::isnan(b)) {
        EXPECT_TRUE(std::isnan(cmp));
        EXPECT_TRUE(std::isnan(op_eval<T>(Op::Min, a, b)));
        EXPECT_TRUE(std::isnan(op_eval<T>(Op::Max, a, b)));
      } else {
        EXPECT_EQ(cmp, a < b ? T(-1) : (a > b ? T(1) : T(0)));
        EXPECT_EQ(op_eval<T>(Op::Min, a, b), std::min(a, b));
        EXPECT_EQ(op_eval<T>(Op::Max, a, b), std::max(a, b));
      }
      // and(a,b) = a == 0 ? a : b; or(a,b) = a != 0 ? a : b (bit for bit: -0 stays -0).
      EXPECT_TRUE(same_value(op_eval<T>(Op::And, a, b), a == 0 ? a : b));
      EXPECT_TRUE(same_value(op_eval<T>(Op::Or, a, b), a != 0 ? a : b));
      // Euclidean mod: in [0, |b|] for finite a and non-zero finite b.
      if (std::isfinite(a) && std::isfinite(b) && b != 0) {
        const T m = op_eval<T>(Op::Mod, a, b);
        EXPECT_GE(m, T(0)) << "mod(" << a << ", " << b << ")";
        EXPECT_LE(m, std::fabs(b)) << "mod(" << a << ", " << b << ")";
      }
      if (b == 0) {
        EXPECT_TRUE(std::isnan(op_eval<T>(Op::Mod, a, b))) << "mod by zero";
      }
    }
  }
  EXPECT_EQ(op_eval<T>(Op::Mod, T(-1), T(3)), T(2));
  EXPECT_EQ(op_eval<T>(Op::Mod, T(-1), T(-3)), T(2));
  EXPECT_EQ(op_eval<T>(Op::Mod, T(5), T(-3)), T(2));
  EXPECT_EQ(op_eval<T>(Op::Mod, T(7.5), T(2)), T(1.5));
  EXPECT_EQ(op_eval<T>(Op::Round, T(0.5), 0), T(1));
  EXPECT_EQ(op_eval<T>(Op::Round, T(-0.5), 0), T(-1));
  EXPECT_EQ(op_eval<T>(Op::Round, T(2.5), 0), T(3));
  EXPECT_EQ(op_eval<T>(Op::Round, T(-2.5), 0), T(-3));
  EXPECT_EQ(op_eval<T>(Op::Compare, T(-0.0), T(0.0)), T(0));
  EXPECT_EQ(op_eval<T>(Op::Not, T(-0.0), 0), T(1));
}

TEST(Semantics, RulesHoldInFloat) { check_semantics_rules<float>(); }
TEST(Semantics, RulesHoldInDouble) { check_semantics_rules<double>(); }

// Correctly rounded ops agree between precisions: float(op<double>(a, b)) == op<float>(a, b).
TEST(Semantics, FloatAndDoubleAgreeOnCorrectlyRoundedOps) {
  std::mt19937_64 rng(11);
  const std::vector<Op> ops = {Op::Neg, Op::Abs,  Op::Sqrt, Op::Square, Op::Floor, Op::Ceil,
                               Op::Round, Op::Not, Op::Add, Op::Sub, Op::Mul, Op::Div, Op::Recip,
                               Op::Min, Op::Max, Op::Compare, Op::Mod, Op::And, Op::Or};
  for (int i = 0; i < 20000; ++i) {
    const float a = test::random_float(rng), b = test::random_float(rng);
    for (Op op : ops) {
      const float f = op_eval<float>(op, a, b);
      const float d = static_cast<float>(op_eval<double>(op, a, b));
      ASSERT_TRUE(same_value(f, d)) << op_name(op) << "(" << fstr(a) << ", " << fstr(b) << "): float " << fstr(f)
                                    << " double " << fstr(d);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Evaluator backends. Each turns (tape, points) into one interval per point; exact backends
// return [v, v] and are compared bit for bit, the interval backend must contain the value.

struct Backend {
  virtual ~Backend() = default;
  virtual bool exact() const { return true; }
  virtual void run(const Tape& t, const std::vector<float>& xs, const std::vector<float>& ys,
                   const std::vector<float>& zs, std::vector<Interval>& out) = 0;
};

struct PointBackend : Backend {
  PointEvaluator ev;
  void run(const Tape& t, const std::vector<float>& xs, const std::vector<float>& ys, const std::vector<float>& zs,
           std::vector<Interval>& out) override {
    out.resize(xs.size());
    for (std::size_t i = 0; i < xs.size(); ++i) out[i] = Interval::point(ev.eval(t, xs[i], ys[i], zs[i]));
  }
};

struct BatchBackend : Backend {
  explicit BatchBackend(std::size_t b, std::unique_ptr<frep::Backend> on = nullptr)
      : batch(b), backend(std::move(on)), ev(backend ? *backend : default_backend()) {}
  std::size_t batch;
  std::unique_ptr<frep::Backend> backend;  // null: the default
  BatchEvaluator ev;
  std::vector<float> tmp;
  void run(const Tape& t, const std::vector<float>& xs, const std::vector<float>& ys, const std::vector<float>& zs,
           std::vector<Interval>& out) override {
    const std::size_t n = xs.size();
    tmp.assign(n + 1, -12345.0f);
    for (std::size_t i = 0; i < n; i += batch) {
      const std::size_t m = std::min(batch, n - i);
      ev.eval(t, xs.data() + i, ys.data() + i, zs.data() + i, tmp.data() + i, m);
    }
    // The evaluator must not write past n.
    EXPECT_EQ(tmp[n], -12345.0f) << "batch evaluator wrote past the end of its output";
    out.resize(n);
    for (std::size_t i = 0; i < n; ++i) out[i] = Interval::point(tmp[i]);
  }
};

// The batch evaluator on the JIT backend, compiling every tape on first use (normally only tapes
// asked for enough points are), in one instruction set.
struct JitBatchBackend : BatchBackend {
  JitBatchBackend(std::size_t b, JitIsa isa) : BatchBackend(b, make_jit_backend({.isa = isa, .compile_after_points = 0})) {}
};

// The point cloud evaluator, made to simplify for every group of points (normally it only does
// for big tapes and small boxes): results must still equal the full tape's bit for bit.
struct PointCloudBackend : Backend {
  PointCloudEvaluator ev{{2, 0, 1e9}};
  std::vector<float> tmp;
  void run(const Tape& t, const std::vector<float>& xs, const std::vector<float>& ys, const std::vector<float>& zs,
           std::vector<Interval>& out) override {
    const std::size_t n = xs.size();
    tmp.assign(n, -12345.0f);
    ev.eval(t, xs.data(), ys.data(), zs.data(), tmp.data(), n);
    out.resize(n);
    for (std::size_t i = 0; i < n; ++i) out[i] = Interval::point(tmp[i]);
  }
};

struct GradBackend : Backend {
  explicit GradBackend(std::size_t b, std::unique_ptr<frep::Backend> on = nullptr)
      : batch(b), backend(std::move(on)), ev(backend ? *backend : default_backend()) {}
  std::size_t batch;
  std::unique_ptr<frep::Backend> backend;  // null: the default
  GradEvaluator ev;
  std::vector<Grad> tmp;
  void run(const Tape& t, const std::vector<float>& xs, const std::vector<float>& ys, const std::vector<float>& zs,
           std::vector<Interval>& out) override {
    const std::size_t n = xs.size();
    tmp.assign(n, Grad{});
    for (std::size_t i = 0; i < n; i += batch) {
      const std::size_t m = std::min(batch, n - i);
      if (m == 1 && batch == 1) {
        tmp[i] = ev.eval(t, xs[i], ys[i], zs[i]);
      } else {
        ev.eval(t, xs.data() + i, ys.data() + i, zs.data() + i, tmp.data() + i, m);
      }
    }
    out.resize(n);
    for (std::size_t i = 0; i < n; ++i) out[i] = Interval::point(tmp[i].v);
  }
};

struct IntervalBackend : Backend {
  IntervalEvaluator ev;
  bool exact() const override { return false; }
  void run(const Tape& t, const std::vector<float>& xs, const std::vector<float>& ys, const std::vector<float>& zs,
           std::vector<Interval>& out) override {
    out.resize(xs.size());
    for (std::size_t i = 0; i < xs.size(); ++i)
      out[i] = ev.eval(t, Interval::point(xs[i]), Interval::point(ys[i]), Interval::point(zs[i]));
  }
};

// The 16-box interval evaluator, 16 degenerate boxes at a time.
struct IntervalBatchBackend : Backend {
  explicit IntervalBatchBackend(std::unique_ptr<frep::Backend> on = nullptr)
      : backend(std::move(on)), ev(backend ? *backend : default_backend()) {}
  std::unique_ptr<frep::Backend> backend;  // null: the default
  IntervalBatchEvaluator ev;
  bool exact() const override { return false; }
  void run(const Tape& t, const std::vector<float>& xs, const std::vector<float>& ys, const std::vector<float>& zs,
           std::vector<Interval>& out) override {
    constexpr int L = IntervalBatchEvaluator::kLanes;
    out.resize(xs.size());
    for (std::size_t i = 0; i < xs.size(); i += L) {
      const int count = static_cast<int>(std::min<std::size_t>(L, xs.size() - i));
      Interval bx[L], by[L], bz[L];
      for (int k = 0; k < count; ++k) {
        bx[k] = Interval::point(xs[i + k]);
        by[k] = Interval::point(ys[i + k]);
        bz[k] = Interval::point(zs[i + k]);
      }
      ev.eval(t, bx, by, bz, count);
      for (int k = 0; k < count; ++k) out[i + k] = ev.result(k);
    }
  }
};

std::unique_ptr<Backend> make_backend(const std::string& name) {
  if (name == "Point") return std::make_unique<PointBackend>();
  if (name == "Interval") return std::make_unique<IntervalBackend>();
  if (name == "IntervalBatch") return std::make_unique<IntervalBatchBackend>();
  if (name == "PointCloud") return std::make_unique<PointCloudBackend>();
  for (const auto& [prefix, isa] : {std::pair{"JitAvx2Batch", JitIsa::Avx2}, std::pair{"JitAvx512Batch", JitIsa::Avx512}})
    if (name.rfind(prefix, 0) == 0) return std::make_unique<JitBatchBackend>(std::stoul(name.substr(std::strlen(prefix))), isa);
  for (const auto& [prefix, isa] : {std::pair{"JitAvx2Grad", JitIsa::Avx2}, std::pair{"JitAvx512Grad", JitIsa::Avx512}})
    if (name.rfind(prefix, 0) == 0)
      return std::make_unique<GradBackend>(std::stoul(name.substr(std::strlen(prefix))),
                                           make_jit_backend({.isa = isa, .compile_after_points = 0}));
  for (const auto& [full, isa] : {std::pair{"JitAvx2IntervalBatch", JitIsa::Avx2}, std::pair{"JitAvx512IntervalBatch", JitIsa::Avx512}})
    if (name == full)
      return std::make_unique<IntervalBatchBackend>(make_jit_backend({.isa = isa, .compile_after_interval_passes = 0}));
  if (name.rfind("Batch", 0) == 0) return std::make_unique<BatchBackend>(std::stoul(name.substr(5)));
  if (name.rfind("Grad", 0) == 0) return std::make_unique<GradBackend>(std::stoul(name.substr(4)));
  return nullptr;
}

// Parameters: "<backend>" or, for SIMD backends, "<backend>_<target>" (e.g. "Batch8_AVX2"), so
// that every compiled instruction set passes the suite, not only the CPU's best.
class Conformance : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    std::string name = GetParam();
    if (const auto us = name.find('_'); us != std::string::npos) {
      const std::int64_t t = test::simd_target_by_name(name.substr(us + 1));
      ASSERT_NE(t, 0) << "SIMD target not available: " << name;
      target_.emplace(t);
      name = name.substr(0, us);
    }
    backend_ = make_backend(name);
    ASSERT_TRUE(backend_) << name;
  }
  void TearDown() override { target_.reset(); }

  // Runs the backend on `t` at the points and compares with `expected`; stops after a few
  // failures per call so a broken op does not flood the log.
  void check(const Tape& t, const std::vector<float>& xs, const std::vector<float>& ys, const std::vector<float>& zs,
             const std::vector<float>& expected, const std::string& what) {
    backend_->run(t, xs, ys, zs, got_);
    int failures = 0;
    for (std::size_t i = 0; i < xs.size() && failures < 5; ++i) {
      const bool ok = backend_->exact() ? same_value(got_[i].lo, expected[i]) : got_[i].contains(expected[i]);
      if (!ok) {
        ++failures;
        ADD_FAILURE() << GetParam() << ": " << what << " at (" << fstr(xs[i]) << ", " << fstr(ys[i]) << ", "
                      << fstr(zs[i]) << "): expected " << fstr(expected[i]) << ", got "
                      << (backend_->exact() ? fstr(got_[i].lo) : test::istr(got_[i]));
      }
    }
  }

  std::optional<test::ScopedSimdTarget> target_;
  std::unique_ptr<Backend> backend_;
  std::vector<Interval> got_;
};

std::vector<float> value_set(std::mt19937_64& rng, int random_count) {
  std::vector<float> v = test::special_floats();
  for (int i = 0; i < random_count; ++i) v.push_back(test::random_float(rng));
  return v;
}

TEST_P(Conformance, LeavesAndConstantRoots) {
  Graph g;
  std::mt19937_64 rng(1);
  std::vector<float> xs = value_set(rng, 40), ys(xs.rbegin(), xs.rend()), zs(xs.size());
  for (std::size_t i = 0; i < zs.size(); ++i) zs[i] = test::random_float(rng);
  check(Tape::compile(g, g.var_x()), xs, ys, zs, xs, "var-x");
  check(Tape::compile(g, g.var_y()), xs, ys, zs, ys, "var-y");
  check(Tape::compile(g, g.var_z()), xs, ys, zs, zs, "var-z");
  for (float c : test::special_floats()) {
    const Tape t = Tape::compile(g, g.constant(c));
    check(t, xs, ys, zs, std::vector<float>(xs.size(), c), "const " + fstr(c));
  }
}

TEST_P(Conformance, EveryUnaryOpOnSpecialAndRandomValues) {
  std::mt19937_64 rng(2);
  const std::vector<float> xs = value_set(rng, 600);
  std::vector<float> ys(xs.size()), zs(xs.size());
  for (std::size_t i = 0; i < xs.size(); ++i) ys[i] = test::random_float(rng), zs[i] = test::random_float(rng);
  for (Op op : test::ops_of_arity(1)) {
    for (int var = 0; var < 3; ++var) {
      Graph g;
      const NodeId v = var == 0 ? g.var_x() : var == 1 ? g.var_y() : g.var_z();
      const Tape t = Tape::compile(g, g.unary(op, v));
      const std::vector<float>& in = var == 0 ? xs : var == 1 ? ys : zs;
      std::vector<float> expected(xs.size());
      for (std::size_t i = 0; i < xs.size(); ++i) expected[i] = op_eval<float>(op, in[i], 0.0f);
      check(t, xs, ys, zs, expected, std::string(op_name(op)) + "(var " + std::to_string(var) + ")");
    }
  }
}

TEST_P(Conformance, EveryBinaryOpOnAllPairsOfSpecialValues) {
  std::mt19937_64 rng(3);
  const std::vector<float> sp = value_set(rng, 10);
  std::vector<float> xs, ys, zs;
  for (float a : sp)
    for (float b : sp) xs.push_back(a), ys.push_back(b), zs.push_back(0.0f);
  for (int i = 0; i < 1500; ++i)
    xs.push_back(test::random_float(rng)), ys.push_back(test::random_float(rng)), zs.push_back(test::random_float(rng));
  for (Op op : test::ops_of_arity(2)) {
    Graph g;
    const NodeId x = g.var_x(), y = g.var_y(), z = g.var_z();  // ids in this order
    const Tape txy = Tape::compile(g, g.binary(op, x, y));
    const Tape tyx = Tape::compile(g, g.binary(op, y, x));
    const Tape tzx = Tape::compile(g, g.binary(op, z, x));
    std::vector<float> exy(xs.size()), eyx(xs.size()), ezx(xs.size());
    for (std::size_t i = 0; i < xs.size(); ++i) {
      exy[i] = op_eval<float>(op, xs[i], ys[i]);
      // For commutative min/max the graph puts the lower id (x) first, which can change the
      // sign of a zero tie (see GraphIdentities.CommutativeCanonicalOrderKeepsSignedZeroTies):
      // compare with the instruction the tape actually holds.
      const bool canon = op == Op::Min || op == Op::Max;
      eyx[i] = canon ? test::eval_ssa<float>(tyx.ssa(), xs[i], ys[i], zs[i]) : op_eval<float>(op, ys[i], xs[i]);
      ezx[i] = canon ? test::eval_ssa<float>(tzx.ssa(), xs[i], ys[i], zs[i]) : op_eval<float>(op, zs[i], xs[i]);
    }
    check(txy, xs, ys, zs, exy, std::string(op_name(op)) + "(x, y)");
    check(tyx, xs, ys, zs, eyx, std::string(op_name(op)) + "(y, x)");
    check(tzx, xs, ys, zs, ezx, std::string(op_name(op)) + "(z, x)");
  }
}

// op(v, v): both arguments in the same register (built with from_ssa to avoid graph identities).
TEST_P(Conformance, EveryBinaryOpWithTheSameRegisterTwice) {
  std::mt19937_64 rng(4);
  const std::vector<float> xs = value_set(rng, 300);
  const std::vector<float> ys(xs.size(), 1.0f), zs(xs.size(), 2.0f);
  for (Op op : test::ops_of_arity(2)) {
    const Tape t = Tape::from_ssa({{Op::VarX}, {op, 0, 0}});
    std::vector<float> expected(xs.size());
    for (std::size_t i = 0; i < xs.size(); ++i) expected[i] = op_eval<float>(op, xs[i], xs[i]);
    check(t, xs, ys, zs, expected, std::string(op_name(op)) + "(x, x)");
  }
}

// Immediate forms op(x, c) and op(c, y), both through the graph (with its identities) and through
// from_ssa (no identities, so mul by 1, div by 1, ... reach the evaluators as immediates).
TEST_P(Conformance, EveryBinaryOpWithAnImmediateOnEitherSide) {
  std::mt19937_64 rng(5);
  std::vector<float> consts = test::special_floats();
  for (int i = 0; i < 10; ++i) consts.push_back(test::random_float(rng));
  const std::vector<float> xs = value_set(rng, 40);
  std::vector<float> ys(xs.rbegin(), xs.rend()), zs(xs.size(), 0.25f);
  std::vector<float> e1(xs.size()), e2(xs.size()), r1(xs.size()), r2(xs.size());
  for (Op op : test::ops_of_arity(2)) {
    for (float c : consts) {
      for (std::size_t i = 0; i < xs.size(); ++i) {
        e1[i] = op_eval<float>(op, xs[i], c);
        e2[i] = op_eval<float>(op, c, ys[i]);
      }
      const std::string n = op_name(op).data();
      // Graph-built: identities may rewrite the instruction (and min/max are put in canonical
      // order), so compare with the reference evaluation of the tape's own SSA list.
      Graph g;
      const NodeId x = g.var_x(), y = g.var_y(), k = g.constant(c);
      const Tape g1 = Tape::compile(g, g.binary(op, x, k)), g2 = Tape::compile(g, g.binary(op, k, y));
      for (std::size_t i = 0; i < xs.size(); ++i) {
        r1[i] = test::eval_ssa<float>(g1.ssa(), xs[i], ys[i], zs[i]);
        r2[i] = test::eval_ssa<float>(g2.ssa(), xs[i], ys[i], zs[i]);
      }
      check(g1, xs, ys, zs, r1, n + "(x, " + fstr(c) + ") graph");
      check(g2, xs, ys, zs, r2, n + "(" + fstr(c) + ", y) graph");
      check(Tape::from_ssa({{Op::VarX}, {Op::Const, 0, 0, c}, {op, 0, 1}}), xs, ys, zs, e1, n + "(x, " + fstr(c) + ") ssa");
      check(Tape::from_ssa({{Op::Const, 0, 0, c}, {Op::VarY}, {op, 0, 1}}), xs, ys, zs, e2, n + "(" + fstr(c) + ", y) ssa");
    }
  }
}

// Random expressions over every opcode: the evaluator against the float reference of the SSA
// list, which itself must agree with a direct evaluation of the graph.
TEST_P(Conformance, RandomExpressionsMatchTheReference) {
  std::mt19937_64 rng(6);
  std::vector<float> xs, ys, zs, expected;
  for (int e = 0; e < 300; ++e) {
    Graph g;
    test::GenOptions opt;
    opt.max_depth = 4 + e % 5;
    test::ExprGen gen(g, rng, opt);
    const NodeId root = gen.gen();
    const Tape t = Tape::compile(g, root);
    xs.clear(), ys.clear(), zs.clear(), expected.clear();
    for (int i = 0; i < 300; ++i) {
      const bool everyday = i % 3 != 0;
      auto pick = [&] {
        return everyday ? std::uniform_real_distribution<float>(-3, 3)(rng) : test::random_float(rng);
      };
      xs.push_back(pick()), ys.push_back(pick()), zs.push_back(pick());
      expected.push_back(test::eval_ssa<float>(t.ssa(), xs.back(), ys.back(), zs.back()));
      if (GetParam() == "Point") {
        const float direct = test::eval_graph<float>(g, root, xs.back(), ys.back(), zs.back());
        ASSERT_TRUE(same_value(direct, expected.back())) << "Tape::compile changed the SSA semantics";
      }
    }
    check(t, xs, ys, zs, expected, "random expression #" + std::to_string(e));
    if (HasFailure()) return;
  }
}

// Tapes with heavy register reuse and many live values (deep sharing).
TEST_P(Conformance, WideExpressionsWithManyLiveRegisters) {
  std::mt19937_64 rng(7);
  Graph g;
  std::vector<NodeId> layer;
  for (int i = 0; i < 64; ++i) {
    const NodeId v = i % 3 == 0 ? g.var_x() : i % 3 == 1 ? g.var_y() : g.var_z();
    layer.push_back(g.binary(Op::Add, g.unary(Op::Sin, g.binary(Op::Mul, v, g.constant(0.1f * i + 0.05f))),
                             g.constant(static_cast<float>(i))));
  }
  while (layer.size() > 1) {
    std::vector<NodeId> next;
    for (std::size_t i = 0; i + 1 < layer.size(); i += 2) {
      const Op ops[] = {Op::Min, Op::Max, Op::Add, Op::Sub, Op::Mul, Op::Atan2, Op::Mod, Op::Compare};
      next.push_back(g.binary(ops[(i / 2 + layer.size()) % 8], layer[i], layer[i + 1]));
    }
    layer = next;
  }
  const Tape t = Tape::compile(g, layer[0]);
  std::vector<float> xs, ys, zs, expected;
  for (int i = 0; i < 700; ++i) {
    xs.push_back(std::uniform_real_distribution<float>(-5, 5)(rng));
    ys.push_back(std::uniform_real_distribution<float>(-5, 5)(rng));
    zs.push_back(std::uniform_real_distribution<float>(-5, 5)(rng));
    expected.push_back(test::eval_ssa<float>(t.ssa(), xs.back(), ys.back(), zs.back()));
  }
  check(t, xs, ys, zs, expected, "wide expression");
}

// A tape used after a bigger one with the same evaluator object (scratch reuse) and vice versa.
TEST_P(Conformance, ReusingOneEvaluatorAcrossTapesOfDifferentSizes) {
  std::mt19937_64 rng(8);
  std::vector<float> xs, ys, zs;
  for (int i = 0; i < 520; ++i) {
    xs.push_back(std::uniform_real_distribution<float>(-2, 2)(rng));
    ys.push_back(std::uniform_real_distribution<float>(-2, 2)(rng));
    zs.push_back(std::uniform_real_distribution<float>(-2, 2)(rng));
  }
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  const std::vector<NodeId> roots = {
      (x * y - z).id(),
      max(abs(x) - 1, max(abs(y) - 1, abs(z) - 1)).id(),
      g.var_x(),
      (sqrt(square(x) + square(y) + square(z)) - 1).id(),
      g.constant(3.5f),
      (sin(x * 3) * cos(y * 2) + atan2(z, x) - mod(y, g.c(0.3f))).id()};
  for (int round = 0; round < 2; ++round) {
    for (NodeId r : roots) {
      const Tape t = Tape::compile(g, r);
      std::vector<float> expected;
      for (std::size_t i = 0; i < xs.size(); ++i) expected.push_back(test::eval_ssa<float>(t.ssa(), xs[i], ys[i], zs[i]));
      check(t, xs, ys, zs, expected, "tape " + std::to_string(r));
    }
  }
}

// Expressions holding oracles (a mesh's signed distance, and the same mesh moved) mixed with other
// ops: every evaluator calls out to the oracle, and agrees with the reference evaluation that
// takes the oracle's own values (the interval evaluators on point boxes contain them).
TEST_P(Conformance, ExpressionsWithOracles) {
  Graph g;
  const auto mesh = std::make_shared<const MeshOracle>(test::make_sphere(2));
  Affine3 turn;  // 30 degrees about z, scaled by 1.5, moved
  const double c = std::cos(0.5236), s = std::sin(0.5236);
  turn.m[0][0] = 1.5 * c, turn.m[0][1] = -1.5 * s, turn.m[0][3] = 0.25;
  turn.m[1][0] = 1.5 * s, turn.m[1][1] = 1.5 * c, turn.m[1][3] = -0.5;
  turn.m[2][2] = 1.5;
  const Expr m(g, g.oracle(mesh)), moved(g, g.oracle(mesh->transformed(turn)));
  auto x = g.x(), y = g.y(), z = g.z();
  const std::vector<std::pair<std::string, NodeId>> roots = {
      {"mesh", m.id()},
      {"mesh - 0.25", (m - 0.25f).id()},
      {"mesh minus a sphere", max(m, -(sqrt(x * x + y * y + z * z) - 0.5f)).id()},
      {"union with the moved mesh", min(m, moved).id()},
      {"mesh squared plus sin x", (m * m + sin(x)).id()},
      {"shell of the moved mesh", (abs(moved) - 0.1f).id()}};
  std::mt19937_64 rng(9);
  std::vector<float> xs, ys, zs;
  std::uniform_real_distribution<float> u(-2, 2);
  for (int i = 0; i < 400; ++i) xs.push_back(u(rng)), ys.push_back(u(rng)), zs.push_back(u(rng));
  // Near the surface: the sphere's vertices moved in and out a little, and exactly on them.
  const TriMesh sphere = test::make_sphere(2);
  for (std::size_t i = 0; i < sphere.vertices.size(); i += 3)
    for (double k : {1.0, 1.001, 0.999}) {
      xs.push_back(static_cast<float>(k * sphere.vertices[i].x));
      ys.push_back(static_cast<float>(k * sphere.vertices[i].y));
      zs.push_back(static_cast<float>(k * sphere.vertices[i].z));
    }
  for (float v : test::special_floats()) xs.push_back(v), ys.push_back(0.5f), zs.push_back(-0.25f);
  for (const auto& [name, root] : roots) {
    const Tape t = Tape::compile(g, root);
    std::vector<float> expected;
    for (std::size_t i = 0; i < xs.size(); ++i)
      expected.push_back(test::eval_ssa<float>(t.ssa(), xs[i], ys[i], zs[i], t.oracles().get()));
    check(t, xs, ys, zs, expected, name);
  }
}

std::vector<std::string> conformance_params() {
  std::vector<std::string> v = {"Point", "Interval", "PointCloud"};
  for (const char* simd : {"Batch1", "Batch7", "Batch8", "Batch9", "Batch255", "Batch256", "Batch257", "Batch1000",
                           "Grad1", "Grad63", "Grad64", "Grad65", "Grad1000", "IntervalBatch"})
    for (std::int64_t t : test::simd_targets()) v.push_back(std::string(simd) + "_" + test::simd_target_name(t));
  // The JIT in each instruction set this CPU runs (the interpreter's SIMD target does not apply).
  for (const auto& [isa, name] : {std::pair{JitIsa::Avx2, "JitAvx2"}, std::pair{JitIsa::Avx512, "JitAvx512"}}) {
    if (!jit_supported(isa)) continue;
    for (const char* b : {"1", "7", "8", "9", "16", "17", "256", "1000"}) v.push_back(std::string(name) + "Batch" + b);
    for (const char* b : {"1", "9", "17", "1000"}) v.push_back(std::string(name) + "Grad" + b);
    v.push_back(std::string(name) + "IntervalBatch");
  }
  return v;
}

INSTANTIATE_TEST_SUITE_P(AllEvaluators, Conformance, ::testing::ValuesIn(conformance_params()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

TEST(SimdTargets, SeveralInstructionSetsAreTested) {
  // x86-64 CPUs of the last decade run at least SSE4 and AVX2; the library compiles both.
  std::string names;
  for (std::int64_t t : test::simd_targets()) names += test::simd_target_name(t) + " ";
  std::printf("SIMD targets under test: %s\n", names.c_str());
#if defined(__x86_64__)
  EXPECT_GE(test::simd_targets().size(), 2u) << names;
#endif
}

TEST(BatchEvaluator, ZeroPointsIsANoOp) {
  Graph g;
  const Tape t = Tape::compile(g, (g.x() + g.y()).id());
  BatchEvaluator ev;
  float out = 7.0f;
  ev.eval(t, nullptr, nullptr, nullptr, &out, 0);
  EXPECT_EQ(out, 7.0f);
  EXPECT_NE(std::string(BatchEvaluator::target_name()), "");
}

}  // namespace
}  // namespace frep
