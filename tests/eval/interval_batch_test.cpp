// The 16-box interval evaluator must agree exactly with the scalar interval evaluator, box by
// box (the root's interval; every instruction's interval and choice shows in the simplified
// tape), and its shared simplification must give the same tapes as simplifying box by box.
#include <gtest/gtest.h>

#include <random>

#include "frep/eval/evaluators.hpp"
#include "frep/eval/interval_batch.hpp"
#include "frep/io/vm.hpp"
#include "test_util.hpp"

namespace frep {
namespace {

// Equal bounds; the sign of a zero bound may differ (min/max of -0 and +0), which does not
// change what the interval contains.
bool same_interval(Interval a, Interval b) {
  if (a.is_unknown() || b.is_unknown()) return a.is_unknown() && b.is_unknown();
  return a.lo == b.lo && a.hi == b.hi;
}

bool same_tape(const Tape& a, const Tape& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const SsaInstr &x = a.ssa()[i], &y = b.ssa()[i];
    if (x.op != y.op) return false;
    if (x.op == Op::Const ? !test::same_bits(x.value, y.value) : (op_arity(x.op) >= 1 && x.a != y.a) || (op_arity(x.op) == 2 && x.b != y.b))
      return false;
  }
  return a.choice_count() == b.choice_count() && a.vars_used() == b.vars_used();
}

// With a root cap, the tapes must be those single-box simplification gives with that cap (their
// values are checked by the simplification tests).
void check_against_scalar(const Tape& tape, std::mt19937_64& rng, int count, float cap = kExactValues) {
  std::vector<Interval> xs(count), ys(count), zs(count);
  for (int k = 0; k < count; ++k) {
    xs[k] = test::random_interval(rng);
    ys[k] = test::random_interval(rng);
    zs[k] = test::random_interval(rng);
  }
  IntervalBatchEvaluator batch;
  batch.eval(tape, xs.data(), ys.data(), zs.data(), count);
  IntervalEvaluator scalar;
  std::vector<Tape> batch_out(IntervalBatchEvaluator::kLanes);
  batch.simplify(tape, (1u << count) - 1, batch_out.data(), 1.0, true, cap);
  for (int k = 0; k < count; ++k) {
    scalar.eval(tape, xs[k], ys[k], zs[k]);
    ASSERT_TRUE(same_interval(scalar.values().back(), batch.result(k)))
        << "box " << k << ": scalar " << test::istr(scalar.values().back()) << " batch " << test::istr(batch.result(k));
    Tape one;
    tape.simplify(scalar.values(), scalar.choices(), one, true, cap);
    EXPECT_TRUE(same_tape(one, batch_out[k])) << "box " << k << ": " << one.size() << " vs " << batch_out[k].size();
    if (cap != kExactValues) continue;
    // And the simplified tape gives the full tape's values inside the box.
    PointEvaluator pe;
    for (int s = 0; s < 8; ++s) {
      auto pick = [&](Interval iv) {
        return iv.lo == iv.hi ? iv.lo : std::uniform_real_distribution<float>(iv.lo, iv.hi)(rng);
      };
      const float x = pick(xs[k]), y = pick(ys[k]), z = pick(zs[k]);
      if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) continue;
      EXPECT_TRUE(test::same_value(pe.eval(tape, x, y, z), pe.eval(batch_out[k], x, y, z)));
    }
  }
}

TEST(IntervalBatch, MatchesScalarIntervalsOnRandomExpressions) {
  test::for_each_simd_target([&] {
    std::mt19937_64 rng(20261122);
    for (int trial = 0; trial < 200; ++trial) {
      Graph g;
      test::GenOptions opt;
      opt.max_depth = 5;
      test::ExprGen gen(g, rng, opt);
      const NodeId root = gen.gen();
      const Tape tape = Tape::compile(g, root);
      check_against_scalar(tape, rng, 1 + trial % 16);
    }
  });
}

TEST(IntervalBatch, MatchesScalarOnMinMaxHeavyExpressions) {
  test::for_each_simd_target([&] {
    std::mt19937_64 rng(7);
    for (int trial = 0; trial < 100; ++trial) {
      Graph g;
      test::GenOptions opt;
      opt.max_depth = 7;
      opt.ops = {Op::Min, Op::Max, Op::Add, Op::Sub, Op::Mul, Op::Square, Op::Sqrt, Op::Neg, Op::Abs, Op::And, Op::Or};
      test::ExprGen gen(g, rng, opt);
      const Tape tape = Tape::compile(g, gen.gen());
      check_against_scalar(tape, rng, 16);
    }
  });
}

TEST(IntervalBatch, MatchesScalarWithARootCap) {
  test::for_each_simd_target([&] {
    std::mt19937_64 rng(8);
    for (int trial = 0; trial < 100; ++trial) {
      Graph g;
      test::GenOptions opt;
      opt.max_depth = 6;
      opt.ops = {Op::Min, Op::Max, Op::Add, Op::Sub, Op::Mul, Op::Square, Op::Sqrt, Op::Neg, Op::Abs, Op::And, Op::Or};
      test::ExprGen gen(g, rng, opt);
      const NodeId a = gen.gen(), b = gen.gen();
      const Tape tape = Tape::compile(g, g.binary(trial % 2 ? Op::Min : Op::Max, a, b));
      check_against_scalar(tape, rng, 1 + trial % 16, trial % 3 ? 0.0f : std::uniform_real_distribution<float>(-2, 2)(rng));
    }
  });
}

TEST(IntervalBatch, MatchesScalarOnProsperoTiles) {
  FREP_REQUIRE_DATA("prospero.vm");
  const Model m = read_vm(test::data_file("prospero.vm"));
  const Tape tape = Tape::compile(*m.graph, m.root);
  // 16 tiles of a 4x4 split of [-1, 1]^2, as the renderer does.
  Interval xs[16], ys[16], zs[16];
  for (int k = 0; k < 16; ++k) {
    const float x0 = -1.0f + 0.5f * (k % 4), y0 = -1.0f + 0.5f * (k / 4);
    xs[k] = {x0, x0 + 0.5f};
    ys[k] = {y0, y0 + 0.5f};
    zs[k] = {0.0f, 0.0f};
  }
  IntervalBatchEvaluator batch;
  batch.eval(tape, xs, ys, zs, 16);
  std::vector<Tape> outs(16);
  batch.simplify(tape, 0xFFFF, outs.data());
  IntervalEvaluator scalar;
  std::size_t total = 0, exact[16];
  for (int k = 0; k < 16; ++k) {
    scalar.eval(tape, xs[k], ys[k], zs[k]);
    EXPECT_TRUE(same_interval(scalar.values().back(), batch.result(k)));
    Tape one;
    tape.simplify(scalar.values(), scalar.choices(), one);
    EXPECT_TRUE(same_tape(one, outs[k])) << "tile " << k;
    EXPECT_FALSE(outs[k].code().empty());  // with register code, for the next level's interval pass
    total += outs[k].size();
    exact[k] = outs[k].size();
  }
  EXPECT_LT(total, 16 * tape.size() / 2) << "pruning should shrink the tiles' tapes a lot";
  // Again from the same pass, with the root cap of a render that reads only signs. Compared on
  // the tiles a render would not settle (the others collapse to a constant).
  batch.simplify(tape, 0xFFFF, outs.data(), 1.0, true, 0.0f);
  std::size_t capped = 0, uncapped = 0;
  int open = 0;
  for (int k = 0; k < 16; ++k) {
    scalar.eval(tape, xs[k], ys[k], zs[k]);
    Tape one;
    tape.simplify(scalar.values(), scalar.choices(), one, true, 0.0f);
    EXPECT_TRUE(same_tape(one, outs[k])) << "tile " << k << " with the sign cap";
    const Interval v = batch.result(k);
    if (v.hi < 0 || v.lo >= 0) continue;
    ++open;
    capped += outs[k].size();
    uncapped += exact[k];
  }
  EXPECT_GE(open, 8);
  EXPECT_LT(capped, uncapped * 3 / 4) << "the sign cap should drop much more of Prospero's undecided tiles";
}

}  // namespace
}  // namespace frep
