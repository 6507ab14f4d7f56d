// SsaBuilder: a tape appended with its variables replaced evaluates, bit for bit, like the
// expression remapped in the graph; affine forms drop zero terms and unit factors; constants and
// oracles are copied as they are; the finished tape has its root last.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <string>

#include "frep/eval/ssa_builder.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/expr/expr.hpp"
#include "frep/expr/oracle.hpp"
#include "frep/expr/remap.hpp"
#include "test_util.hpp"

namespace frep {
namespace {

using test::fstr;
using test::same_value;

// f(X, Y, Z) for random expressions f, X, Y, Z: appending f's tape onto the tapes of X, Y and Z
// gives, at every point, what the tape of the remapped expression gives.
TEST(SsaBuilder, AppendSubstitutesVariablesLikeRemap) {
  std::mt19937_64 rng(20240611);
  PointEvaluator pe;
  int points = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Graph g;
    test::GenOptions outer;
    outer.max_depth = 5;
    test::GenOptions inner;
    inner.max_depth = 3;
    const NodeId f = test::ExprGen(g, rng, outer).gen();
    NodeId sub[3];
    for (NodeId& s : sub) s = test::ExprGen(g, rng, inner).gen();

    SsaBuilder b;
    const SsaBuilder::Vars xyz = b.variables();
    SsaBuilder::Vars at;
    for (int k = 0; k < 3; ++k) at[k] = b.append(Tape::compile(g, sub[k]), xyz);
    const SsaBuilder::Ref root = b.append(Tape::compile(g, f), at);
    const Tape built = b.finish(root);
    EXPECT_EQ(b.size(), 0u) << "finish leaves the builder empty";

    const Tape want = Tape::compile(g, remap(g, f, sub[0], sub[1], sub[2]));
    for (int i = 0; i < 20; ++i) {
      const float x = test::random_float(rng), y = test::random_float(rng), z = test::random_float(rng);
      const float got = pe.eval(built, x, y, z), expected = pe.eval(want, x, y, z);
      ASSERT_TRUE(same_value(got, expected))
          << "trial " << trial << " at (" << fstr(x) << ", " << fstr(y) << ", " << fstr(z) << "): " << fstr(got)
          << " instead of " << fstr(expected);
      ++points;
    }
  }
  EXPECT_EQ(points, 6000);
}

// Variables replaced by other instructions are not copied; every other instruction is, in order.
TEST(SsaBuilder, AppendReplacesOnlyTheVariables) {
  Graph g;
  const Expr x = g.x(), y = g.y(), z = g.z();
  const Tape t = Tape::compile(g, (max(x * 2.0f - y, z) + 1.5f).id());
  SsaBuilder b;
  const SsaBuilder::Ref u = b.constant(3), v = b.constant(-4), w = b.constant(0.25f);
  const std::size_t before = b.size();
  const SsaBuilder::Ref root = b.append(t, {u, v, w});
  EXPECT_EQ(b.size() - before, t.size() - 3) << "x, y and z become u, v and w";
  EXPECT_EQ(root, b.size() - 1);
  for (const SsaInstr& s : b.ssa()) EXPECT_TRUE(s.op < Op::VarX || s.op > Op::VarZ) << "no variable left";
  const Tape built = b.finish(root);
  PointEvaluator pe;
  EXPECT_EQ(pe.eval(built, 0, 0, 0), std::max(3.0f * 2.0f + 4.0f, 0.25f) + 1.5f);
}

// A field computed by code: here x + 2 y + 3 z, whatever point it is given.
class PlaneOracle final : public Oracle {
 public:
  void values(const float* x, const float* y, const float* z, float* out, std::size_t n) const override {
    for (std::size_t i = 0; i < n; ++i) out[i] = x[i] + 2 * y[i] + 3 * z[i];
  }
  void gradients(const float* x, const float* y, const float* z, Grad* out, std::size_t n) const override {
    for (std::size_t i = 0; i < n; ++i) out[i] = {x[i] + 2 * y[i] + 3 * z[i], 1, 2, 3};
  }
  double lipschitz() const override { return std::sqrt(14.0); }
  std::string describe() const override { return "a plane"; }
  NodeId closed_form(Graph& g) const override { return (g.x() + 2.0f * g.y() + 3.0f * g.z()).id(); }
};

// Oracles keep their index: the finished tape evaluates them through the table it is given.
TEST(SsaBuilder, AppendKeepsOraclesAndConstants) {
  Graph g;
  const Expr o(g, g.oracle(std::make_shared<PlaneOracle>()));
  const Tape t = Tape::compile(g, min(o, g.x() - 7.0f).id());
  SsaBuilder b;
  const SsaBuilder::Vars xyz = b.variables();
  const SsaBuilder::Ref root = b.append(t, xyz);
  std::size_t oracles = 0, sevens = 0;
  for (const SsaInstr& s : b.ssa()) {
    if (s.op == Op::Oracle) {
      ++oracles;
      EXPECT_EQ(oracle_index(s.value), 0u);
    }
    sevens += s.op == Op::Const && std::fabs(s.value) == 7.0f;
  }
  EXPECT_EQ(oracles, 1u);
  EXPECT_EQ(sevens, 1u);
  const Tape built = b.finish(root, t.oracles());
  PointEvaluator pe;
  for (const float p : {-10.0f, -1.0f, 0.0f, 2.5f, 9.0f})
    EXPECT_EQ(pe.eval(built, p, 1, -p), pe.eval(t, p, 1, -p)) << p;
}

// Zero terms are dropped, +-1 needs no multiplication, and a lone unit term is the variable.
TEST(SsaBuilder, AffineDropsZeroTermsAndUnitFactors) {
  SsaBuilder b;
  const SsaBuilder::Vars uvw = b.variables();
  const auto added = [&](const std::array<float, 4>& c, std::size_t n, const char* what) {
    const std::size_t before = b.size();
    const SsaBuilder::Ref r = b.affine(c, uvw);
    EXPECT_EQ(b.size() - before, n) << what;
    return r;
  };
  EXPECT_EQ(added({0, 1, 0, 0}, 0, "v"), uvw[1]);
  EXPECT_EQ(b.ssa()[added({0, 0, -1, 0}, 1, "-w")].op, Op::Neg);
  added({2, 0, 0, 0}, 2, "2 u: a constant and a product");
  EXPECT_EQ(b.ssa()[added({0, 0, 0, 5}, 1, "5")].value, 5.0f);
  added({1, 0, 0, 0.5f}, 2, "u + 0.5: a constant and a sum");
  added({1, -1, 0, 0}, 2, "u - v: a negation and a sum");
  added({0.5f, 3, -1, 2}, 9, "every term");
}

// The value is the float sum of the terms in order, whatever the coefficients.
TEST(SsaBuilder, AffineEvaluatesTheFormInOrder) {
  std::mt19937_64 rng(7);
  PointEvaluator pe;
  const float pick[] = {0.0f, 1.0f, -1.0f, 0.5f, -3.25f, 1e-3f};
  for (int trial = 0; trial < 200; ++trial) {
    std::array<float, 4> c;
    for (float& ck : c) ck = pick[rng() % 6];
    SsaBuilder b;
    const SsaBuilder::Vars uvw = b.variables();
    const Tape t = b.finish(b.affine(c, uvw));
    const float u = test::random_float(rng), v = test::random_float(rng), w = test::random_float(rng);
    const float q[3] = {u, v, w};
    float want = 0;
    bool any = false;
    for (int k = 0; k < 3; ++k) {
      if (c[k] == 0) continue;
      const float term = c[k] == 1 ? q[k] : c[k] == -1 ? -q[k] : c[k] * q[k];
      want = any ? want + term : term;
      any = true;
    }
    if (!any) want = c[3];
    else if (c[3] != 0) want = want + c[3];
    EXPECT_TRUE(same_value(pe.eval(t, u, v, w), want)) << trial;
  }
}

// A root written before other instructions is moved last (+ 0); a root already last is kept.
TEST(SsaBuilder, FinishPutsTheRootLast) {
  SsaBuilder b;
  const SsaBuilder::Vars xyz = b.variables();
  const Tape y = b.finish(xyz[1]);
  PointEvaluator pe;
  EXPECT_EQ(pe.eval(y, 1, 2, 3), 2.0f);

  const SsaBuilder::Vars again = b.variables();
  const SsaBuilder::Ref sum = b.emit(Op::Add, again[0], again[2]);
  EXPECT_EQ(b.size(), 4u);
  const Tape t = b.finish(sum);
  EXPECT_EQ(pe.eval(t, 1, 2, 3), 4.0f);
}

}  // namespace
}  // namespace frep
