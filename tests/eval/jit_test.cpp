// The JIT backend: bit-identical to the interpreter on every opcode at special values (random
// cases, and the fuzz target's corpus replayed), compiled only when worth it, never confused by
// tape buffers reused for other contents, and the same pictures as the interpreter's.
#include <gtest/gtest.h>

#include <bit>
#include <random>

#include "../../fuzz/jit_differential.hpp"
#include "frep/convert/mesh_oracle.hpp"
#include "frep/eval/jit.hpp"
#include "frep/eval/interval_batch.hpp"
#include "frep/expr/expr.hpp"
#include "frep/io/vm.hpp"
#include "frep/render/render2d.hpp"
#include "fuzz_replay.hpp"
#include "mesh_test_util.hpp"
#include "test_util.hpp"

namespace frep {
namespace {

std::vector<JitIsa> isas() {
  std::vector<JitIsa> v;
  for (JitIsa isa : {JitIsa::Avx2, JitIsa::Avx512})
    if (jit_supported(isa)) v.push_back(isa);
  return v;
}

#define FREP_REQUIRE_JIT()                                                     \
  if (isas().empty()) GTEST_SKIP() << "this CPU runs none of the JIT's code"

TEST(Jit, BitIdenticalToTheInterpreterOnRandomCasesOverEveryOpcode) {
  FREP_REQUIRE_JIT();
  std::mt19937_64 rng(27);
  const JitStats before = jit_stats();
  int cases = 0;
  for (int k = 0; k < 4000; ++k) {
    std::vector<std::uint8_t> bytes(16 + rng() % 400);
    for (auto& b : bytes) b = static_cast<std::uint8_t>(rng());
    const fuzz::DiffCase c = fuzz::decode_case(bytes.data(), bytes.size());
    for (JitIsa isa : isas()) {
      const std::string diff = fuzz::check_case(c, isa);
      ASSERT_EQ(diff, "") << "case " << k;
      ++cases;
    }
  }
  // The generated code ran (the interpreter did not stand in for it), for values, gradients and
  // intervals.
  EXPECT_GE(jit_stats().tapes_compiled - before.tapes_compiled, static_cast<std::uint64_t>(3 * cases));
  EXPECT_GE(jit_stats().interval_passes_compiled - before.interval_passes_compiled, static_cast<std::uint64_t>(2 * cases));
  EXPECT_EQ(jit_stats().compile_failures, before.compile_failures);
}

TEST(Jit, ReplaysTheFuzzCorpus) {
  FREP_REQUIRE_JIT();
  const test::ReplayCounts n = test::replay_corpus("jit", [](std::string_view bytes) {
    const fuzz::DiffCase c = fuzz::decode_case(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    for (JitIsa isa : isas()) {
      const std::string diff = fuzz::check_case(c, isa);
      EXPECT_EQ(diff, "");
      if (!diff.empty()) return false;
    }
    return true;
  });
  EXPECT_GT(n.seeds, 10u);
}

// Renders over [-1, 1]^2 with every evaluator on `backend`.
Image render_on(const Backend& backend, const Tape& t, int size) {
  set_default_backend(&backend);
  RenderOptions o;
  o.size = size;
  Image img = render2d(t, o);
  set_default_backend(nullptr);
  return img;
}

TEST(Jit, CompilesATapeOnlyOnceItIsAskedForEnoughPoints) {
  FREP_REQUIRE_JIT();
  Graph g;
  auto x = g.x(), y = g.y();
  const Tape t = Tape::compile(g, (sqrt(x * x + y * y) - 0.5f).id());
  const auto backend = make_jit_backend({.compile_after_points = 1000});
  BatchEvaluator jit(*backend), interp(interpreter_backend());
  std::vector<float> xs(100), ys(100), zs(100, 0.0f), a(100), b(100);
  for (int i = 0; i < 100; ++i) xs[i] = 0.01f * i, ys[i] = -0.02f * i;
  const JitStats s0 = jit_stats();
  for (int k = 0; k < 9; ++k) jit.eval(t, xs.data(), ys.data(), zs.data(), a.data(), 100);
  const JitStats s1 = jit_stats();
  EXPECT_EQ(s1.tapes_compiled, s0.tapes_compiled) << "900 points: not yet worth compiling";
  EXPECT_EQ(s1.points_interpreted - s0.points_interpreted, 900u);
  for (int k = 0; k < 5; ++k) jit.eval(t, xs.data(), ys.data(), zs.data(), a.data(), 100);
  const JitStats s2 = jit_stats();
  EXPECT_EQ(s2.tapes_compiled, s1.tapes_compiled + 1) << "compiled once, at 1000 points, then reused";
  EXPECT_EQ(s2.points_compiled - s1.points_compiled, 500u);
  interp.eval(t, xs.data(), ys.data(), zs.data(), b.data(), 100);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(std::bit_cast<std::uint32_t>(a[i]), std::bit_cast<std::uint32_t>(b[i]));
  // One call with enough points compiles at once.
  const Tape t2 = Tape::compile(g, (x * y + 1.0f).id());
  std::vector<float> big(5000, 0.25f), out(5000);
  jit.eval(t2, big.data(), big.data(), big.data(), out.data(), big.size());
  EXPECT_EQ(jit_stats().tapes_compiled, s2.tapes_compiled + 1);
  EXPECT_EQ(out[4999], 1.0625f);
}

TEST(Jit, CompilesAnIntervalTapeOnlyAfterEnoughPassesAndSimplifiesLikeTheInterpreter) {
  FREP_REQUIRE_JIT();
  Graph g;
  auto x = g.x(), y = g.y();
  const NodeId root = min(sqrt(x * x + y * y) - 0.5f, max(abs(x) - 0.25f, y * y - 0.1f)).id();
  for (JitIsa isa : isas()) {
    const Tape t = Tape::compile(g, root);  // a tape counts its passes: a new one per backend
    const auto backend = make_jit_backend({.isa = isa, .compile_after_interval_passes = 5});
    IntervalBatchEvaluator jit(*backend), interp(interpreter_backend());
    Interval xs[16], ys[16], zs[16];
    for (int k = 0; k < 16; ++k) {
      xs[k] = {-1.0f + 0.5f * static_cast<float>(k % 4), -0.5f + 0.5f * static_cast<float>(k % 4)};
      ys[k] = {-1.0f + 0.5f * static_cast<float>(k / 4), -0.5f + 0.5f * static_cast<float>(k / 4)};
      zs[k] = {0, 0};
    }
    const JitStats s0 = jit_stats();
    for (int pass = 0; pass < 8; ++pass) {
      jit.eval(t, xs, ys, zs, 16);
      interp.eval(t, xs, ys, zs, 16);
      Tape a[16], b[16];
      ASSERT_EQ(jit.simplify(t, 0xFFFF, a), interp.simplify(t, 0xFFFF, b));
      for (int k = 0; k < 16; ++k) {
        EXPECT_EQ(std::bit_cast<std::uint64_t>(jit.result(k)), std::bit_cast<std::uint64_t>(interp.result(k)));
        ASSERT_EQ(a[k].size(), b[k].size()) << "pass " << pass << " box " << k;
        for (std::size_t i = 0; i < a[k].size(); ++i) {
          EXPECT_EQ(a[k].ssa()[i].op, b[k].ssa()[i].op);
          EXPECT_EQ(a[k].ssa()[i].a, b[k].ssa()[i].a);
          EXPECT_EQ(a[k].ssa()[i].b, b[k].ssa()[i].b);
          EXPECT_EQ(std::bit_cast<std::uint32_t>(a[k].ssa()[i].value), std::bit_cast<std::uint32_t>(b[k].ssa()[i].value));
        }
      }
    }
    const JitStats s1 = jit_stats();
    EXPECT_EQ(s1.tapes_compiled - s0.tapes_compiled, 1u) << "compiled once, on the fifth pass";
    // (the interpreter's passes are not counted: it is not a JIT evaluator)
    EXPECT_EQ(s1.interval_passes_interpreted - s0.interval_passes_interpreted, 4u);
    EXPECT_EQ(s1.interval_passes_compiled - s0.interval_passes_compiled, 4u);
  }
}

TEST(Jit, AWholeTapeIsCompiledAmongManySimplifiedOnes) {
  FREP_REQUIRE_JIT();
  // The subdivision driver's pattern: a pass on the whole tape, then passes on dozens of
  // simplified children (each a new tape), again and again. Tapes count their own passes, so
  // the children cannot push the whole tape out of the evaluator's table before it is compiled.
  Graph g;
  auto x = g.x(), y = g.y();
  Expr f = sqrt(x * x + y * y) - 0.9f;
  for (int i = 0; i < 24; ++i) f = min(f, abs(x - 0.07f * static_cast<float>(i)) + abs(y + 0.05f * static_cast<float>(i)) - 0.03f);
  const Tape t = Tape::compile(g, f.id());
  const auto backend = make_jit_backend({.compile_after_interval_passes = 5});
  IntervalBatchEvaluator ev(*backend);
  std::vector<Tape> children(16);
  Interval xs[16], ys[16], zs[16];
  const JitStats s0 = jit_stats();
  for (int pass = 0; pass < 10; ++pass) {
    for (int k = 0; k < 16; ++k) {
      xs[k] = {-1.0f + 0.5f * static_cast<float>(k % 4), -0.5f + 0.5f * static_cast<float>(k % 4)};
      ys[k] = {-1.0f + 0.5f * static_cast<float>(k / 4), -0.5f + 0.5f * static_cast<float>(k / 4)};
      zs[k] = {0, 0};
    }
    ev.eval(t, xs, ys, zs, 16);
    const std::uint32_t built = ev.simplify(t, 0xFFFF, children.data());
    for (int k = 0; k < 16; ++k) {
      if (!(built >> k & 1)) continue;
      for (int c = 0; c < 4; ++c) {  // each child split again, as a subdivision would
        Interval cx = {xs[k].lo + 0.125f * static_cast<float>(c), xs[k].lo + 0.125f * static_cast<float>(c + 1)};
        ev.eval(children[static_cast<std::size_t>(k)], &cx, &ys[k], &zs[k], 1);
      }
    }
  }
  const JitStats s1 = jit_stats();
  EXPECT_EQ(s1.tapes_compiled - s0.tapes_compiled, 1u) << "the whole tape, once";
  EXPECT_EQ(s1.interval_passes_compiled - s0.interval_passes_compiled, 6u) << "its passes 5 to 10";
}

TEST(Jit, WarmRerendersCompileTheWholeTapesIntervalPass) {
  FREP_REQUIRE_JIT();
  Graph g;
  auto x = g.x(), y = g.y();
  const Tape t = Tape::compile(g, min(sqrt(x * x + y * y) - 0.5f, max(abs(x) - 0.8f, abs(y + 0.3f) - 0.1f)).id());
  const auto backend = make_jit_backend({.compile_after_interval_passes = 3});
  set_default_backend(backend.get());
  RenderOptions o;
  o.size = 200;
  o.threads = 1;
  Renderer2D warm(o);
  const JitStats s0 = jit_stats();
  Image img;
  for (int frame = 0; frame < 6; ++frame) img = warm.render(t);
  set_default_backend(nullptr);
  EXPECT_GT(jit_stats().interval_passes_compiled, s0.interval_passes_compiled);
  EXPECT_EQ(img.pixels, render_on(interpreter_backend(), t, 200).pixels);
}

TEST(Jit, ValueTapesDominatedByLibraryCallsStayInterpreted) {
  FREP_REQUIRE_JIT();
  Graph g;
  auto x = g.x(), y = g.y();
  const Tape calls = Tape::compile(g, (exp(x) + sin(y) * cos(x) - 1.0f).id());  // 3 calls in 7
  const Tape arithmetic = Tape::compile(g, (x * x + y * y - 1.0f + abs(x - y) * 0.5f).id());
  const auto backend = make_jit_backend({.compile_after_points = 100});
  BatchEvaluator ev(*backend);
  std::vector<float> p(200, 0.25f), out(200);
  const JitStats s0 = jit_stats();
  ev.eval(calls, p.data(), p.data(), p.data(), out.data(), p.size());
  EXPECT_EQ(jit_stats().tapes_compiled, s0.tapes_compiled);
  EXPECT_EQ(jit_stats().compile_failures, s0.compile_failures) << "a choice, not a failure";
  ev.eval(arithmetic, p.data(), p.data(), p.data(), out.data(), p.size());
  EXPECT_EQ(jit_stats().tapes_compiled, s0.tapes_compiled + 1);
  // compile_after_points = 0 compiles everything, calls or not (the conformance tests do).
  const auto all = make_jit_backend({.compile_after_points = 0});
  BatchEvaluator every(*all);
  every.eval(calls, p.data(), p.data(), p.data(), out.data(), p.size());
  EXPECT_EQ(jit_stats().tapes_compiled, s0.tapes_compiled + 2);
}

TEST(Jit, ATapeObjectSimplifiedAgainRunsItsNewContents) {
  FREP_REQUIRE_JIT();
  // Simplification writes children into reused Tape objects; compiled code is keyed by the
  // contents' stamp, so a reused object never runs the code of what it held before.
  Graph g;
  auto x = g.x(), y = g.y();
  const Tape parent = Tape::compile(g, min(x - 0.5f, max(y + 0.25f, x * y)).id());
  const auto backend = make_jit_backend({.compile_after_points = 0});
  BatchEvaluator jit(*backend), interp(interpreter_backend());
  IntervalBatchEvaluator boxes;
  Tape child;
  std::vector<float> xs(64), ys(64), zs(64, 0.0f), a(64), b(64);
  std::mt19937_64 rng(3);
  for (int round = 0; round < 40; ++round) {
    const float cx = std::uniform_real_distribution<float>(-2, 2)(rng), cy = std::uniform_real_distribution<float>(-2, 2)(rng);
    Interval bx{cx - 0.1f, cx + 0.1f}, by{cy - 0.1f, cy + 0.1f}, bz{0, 0};
    boxes.eval(parent, &bx, &by, &bz, 1);
    if (!boxes.simplify(parent, 1, &child)) continue;
    for (int i = 0; i < 64; ++i) xs[i] = cx - 0.1f + 0.2f * (i % 8) / 7, ys[i] = cy - 0.1f + 0.2f * (i / 8) / 7;
    jit.eval(child, xs.data(), ys.data(), zs.data(), a.data(), 64);
    interp.eval(child, xs.data(), ys.data(), zs.data(), b.data(), 64);
    for (int i = 0; i < 64; ++i)
      ASSERT_EQ(std::bit_cast<std::uint32_t>(a[i]), std::bit_cast<std::uint32_t>(b[i])) << "round " << round;
  }
}

TEST(Jit, OraclesAndTapesBeyondTheLimitRunOnTheInterpreter) {
  FREP_REQUIRE_JIT();
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  const auto backend = make_jit_backend({.compile_after_points = 0, .max_instructions = 4});
  BatchEvaluator jit(*backend);
  const Tape longer = Tape::compile(g, (x * x + y * y + z * z - 1.0f).id());
  ASSERT_GT(longer.code().size(), 4u);
  float p = 0.5f, out = 0;
  const JitStats s0 = jit_stats();
  jit.eval(longer, &p, &p, &p, &out, 1);
  EXPECT_EQ(jit_stats().tapes_compiled, s0.tapes_compiled);
  EXPECT_EQ(out, -0.25f);
  const Tape mesh = Tape::compile(g, g.oracle(std::make_shared<const MeshOracle>(test::make_sphere(2))));
  EXPECT_TRUE(mesh.oracles());
  jit.eval(mesh, &p, &p, &p, &out, 1);
  EXPECT_EQ(jit_stats().tapes_compiled, s0.tapes_compiled);
}

TEST(Jit, SelectedByNameAndExplicitInstructionSetsTheCpuLacksAreErrors) {
  EXPECT_STREQ(backend_by_name("jit").name(), "jit");
  EXPECT_EQ(&backend_by_name("jit"), &jit_backend());
  for (JitIsa isa : {JitIsa::Avx2, JitIsa::Avx512})
    if (!jit_supported(isa)) {
      EXPECT_THROW(make_jit_backend({.isa = isa}), InputError);
    }
}

TEST(Jit, RendersTheSameImagesAsTheInterpreter) {
  FREP_REQUIRE_JIT();
  std::mt19937_64 rng(11);
  for (JitIsa isa : isas()) {
    // Every tape compiled, interval passes included: the subdivision simplifies from the
    // generated code's records.
    const auto backend = make_jit_backend({.isa = isa, .compile_after_points = 0, .compile_after_interval_passes = 0});
    for (int e = 0; e < 20; ++e) {
      Graph g;
      test::GenOptions opt;
      opt.vars = 2;
      opt.max_depth = 6;
      test::ExprGen gen(g, rng, opt);
      const Tape t = Tape::compile(g, gen.gen());
      EXPECT_EQ(render_on(*backend, t, 97).pixels, render_on(interpreter_backend(), t, 97).pixels) << "expression " << e;
    }
  }
}

TEST(Jit, RendersProsperoLikeTheInterpreter) {
  FREP_REQUIRE_JIT();
  FREP_REQUIRE_DATA("prospero.vm");
  const Model m = read_vm(test::data_file("prospero.vm"));
  const Tape t = Tape::compile(*m.graph, m.root);
  for (JitIsa isa : isas()) {
    const auto backend = make_jit_backend({.isa = isa, .compile_after_points = 0, .compile_after_interval_passes = 0});
    const JitStats s0 = jit_stats();
    EXPECT_EQ(render_on(*backend, t, 256).pixels, render_on(interpreter_backend(), t, 256).pixels);
    EXPECT_GT(jit_stats().interval_passes_compiled, s0.interval_passes_compiled);
    set_default_backend(backend.get());
    RenderOptions o;
    o.size = 128;
    const Image brute = render2d_brute_force(t, o);
    set_default_backend(nullptr);
    EXPECT_EQ(brute.pixels, render2d_brute_force(t, o).pixels);
    EXPECT_GT(jit_stats().tapes_compiled, s0.tapes_compiled);
  }
}

}  // namespace
}  // namespace frep
