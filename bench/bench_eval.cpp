// Engine benchmarks: the Prospero render (tiled + pruned vs brute force) and evaluator
// throughput. Run: build/bench/bench_eval (needs ../shared/data/vm).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <random>
#include <set>

#include "frep/eval/evaluators.hpp"
#include "frep/eval/interval_batch.hpp"
#include "frep/eval/jit.hpp"
#include "frep/io/vm.hpp"
#include "frep/render/render2d.hpp"

namespace {

std::string data_path(const char* name) { return std::string(FREP_SOURCE_DIR "/../shared/data/vm/") + name; }

const frep::Tape* load_tape(const char* name) {
  static std::map<std::string, frep::Tape> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return &it->second;
  const std::string path = data_path(name);
  if (!std::filesystem::exists(path)) return nullptr;
  frep::Model m = frep::read_vm(path);
  return &cache.emplace(name, frep::Tape::compile(*m.graph, m.root)).first->second;
}

void BM_ProsperoRender(benchmark::State& state) {
  const frep::Tape* tape = load_tape("prospero.vm");
  if (!tape) return state.SkipWithError("../shared/data/vm/prospero.vm not found");
  frep::RenderOptions opt;
  opt.size = static_cast<int>(state.range(0));
  opt.threads = static_cast<int>(state.range(1));
  if (const char* t = std::getenv("FREP_TILES")) {  // for tuning: e.g. FREP_TILES=256,64,16
    opt.tiles.clear();
    for (const char* p = t; *p;) {
      opt.tiles.push_back(std::atoi(p));
      while (*p && *p != ',') ++p;
      if (*p == ',') ++p;
    }
  }
  frep::Renderer2D renderer(opt);
  frep::Image img = renderer.render(*tape);  // warm-up, and the correctness check below
  // Every configuration timed is first checked against brute force, pixel for pixel.
  static std::set<std::pair<int, int>> checked;
  if (checked.insert({opt.size, opt.threads}).second) {
    const frep::Image ref = frep::render2d_brute_force(*tape, opt);
    if (ref.pixels != img.pixels) {
      std::fprintf(stderr, "MISMATCH: tiled render (%d threads) differs from brute force\n", opt.threads);
      std::exit(1);
    }
    std::fprintf(stderr, "check: tiled %dx%d render with %d thread(s) equals brute force (%s)\n", opt.size, opt.size,
                 opt.threads, frep::BatchEvaluator::target_name());
  }
  // Timed: re-rendering the same tape with a warm renderer (pool, scratch and tapes reused).
  for (auto _ : state) {
    img = renderer.render(*tape);
    benchmark::DoNotOptimize(img.pixels.data());
  }
}
BENCHMARK(BM_ProsperoRender)->Args({1024, 1})->Args({1024, 2})->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ProsperoBruteForce(benchmark::State& state) {
  const frep::Tape* tape = load_tape("prospero.vm");
  if (!tape) return state.SkipWithError("../shared/data/vm/prospero.vm not found");
  frep::RenderOptions opt;
  opt.size = static_cast<int>(state.range(0));
  for (auto _ : state) {
    frep::Image img = frep::render2d_brute_force(*tape, opt);
    benchmark::DoNotOptimize(img.pixels.data());
  }
}
BENCHMARK(BM_ProsperoBruteForce)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();

struct PointSet {
  std::vector<float> x, y, z, out;
};
PointSet random_points(std::size_t n, bool three_d) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  PointSet p;
  for (std::size_t i = 0; i < n; ++i) {
    p.x.push_back(u(rng));
    p.y.push_back(u(rng));
    p.z.push_back(three_d ? u(rng) : 0.0f);
  }
  p.out.resize(n);
  return p;
}

void BM_BatchEval(benchmark::State& state, const char* name) {
  const frep::Tape* tape = load_tape(name);
  if (!tape) return state.SkipWithError("shared data not found");
  PointSet p = random_points(4096, true);
  frep::BatchEvaluator ev;
  for (auto _ : state) {
    ev.eval(*tape, p.x.data(), p.y.data(), p.z.data(), p.out.data(), p.x.size());
    benchmark::DoNotOptimize(p.out.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * p.x.size()));
}
BENCHMARK_CAPTURE(BM_BatchEval, prospero, "prospero.vm");
BENCHMARK_CAPTURE(BM_BatchEval, bear, "bear.vm");

// The batch evaluator on a named backend ("interp", or "jit" with its code compiled before the
// timing starts), over state.range(0) points a call: the JIT's gain per point, which with its
// compile time (BM_JitCompile) gives the number of points a tape must be asked for to pay back
// its compilation (bench/jit.sh).
template <class Evaluator, class Out>
void BM_EvaluatorOn(benchmark::State& state, const char* name, const char* backend_name) {
  const frep::Tape* tape = load_tape(name);
  if (!tape) return state.SkipWithError("shared data not found");
  const bool jit = std::string(backend_name) == "jit";
  if (jit && !frep::jit_supported()) return state.SkipWithError("this CPU runs no JIT code");
  const auto backend = frep::make_jit_backend({.compile_after_points = 0});
  Evaluator ev(jit ? *backend : frep::interpreter_backend());
  PointSet p = random_points(static_cast<std::size_t>(state.range(0)), true);
  std::vector<Out> out(p.x.size());
  ev.eval(*tape, p.x.data(), p.y.data(), p.z.data(), out.data(), p.x.size());  // compiles
  for (auto _ : state) {
    ev.eval(*tape, p.x.data(), p.y.data(), p.z.data(), out.data(), p.x.size());
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * p.x.size()));
  state.counters["instructions"] = static_cast<double>(tape->code().size());
}
void BM_BatchOn(benchmark::State& state, const char* name, const char* backend_name) {
  BM_EvaluatorOn<frep::BatchEvaluator, float>(state, name, backend_name);
}
BENCHMARK_CAPTURE(BM_BatchOn, prospero_interp, "prospero.vm", "interp")->Arg(256)->Arg(4096);
BENCHMARK_CAPTURE(BM_BatchOn, prospero_jit, "prospero.vm", "jit")->Arg(256)->Arg(4096);
BENCHMARK_CAPTURE(BM_BatchOn, bear_interp, "bear.vm", "interp")->Arg(256)->Arg(4096);
BENCHMARK_CAPTURE(BM_BatchOn, bear_jit, "bear.vm", "jit")->Arg(256)->Arg(4096);

// The same for the gradient evaluator (values and three partial derivatives).
void BM_GradOn(benchmark::State& state, const char* name, const char* backend_name) {
  BM_EvaluatorOn<frep::GradEvaluator, frep::Grad>(state, name, backend_name);
}
BENCHMARK_CAPTURE(BM_GradOn, prospero_interp, "prospero.vm", "interp")->Arg(4096);
BENCHMARK_CAPTURE(BM_GradOn, prospero_jit, "prospero.vm", "jit")->Arg(4096);
BENCHMARK_CAPTURE(BM_GradOn, bear_interp, "bear.vm", "interp")->Arg(4096);
BENCHMARK_CAPTURE(BM_GradOn, bear_jit, "bear.vm", "jit")->Arg(4096);

// The counters of a compile benchmark: the tape's length, and the compile time per 1,000
// instructions since `before`.
void report_compile_time(benchmark::State& state, const frep::Tape& tape, const frep::JitStats& before) {
  const frep::JitStats after = frep::jit_stats();
  const double instructions = static_cast<double>(after.instructions_compiled - before.instructions_compiled);
  state.counters["instructions"] = static_cast<double>(tape.code().size());
  state.counters["compile_us_per_1000"] =
      instructions > 0 ? static_cast<double>(after.compile_nanoseconds - before.compile_nanoseconds) / 1e3 / (instructions / 1000) : 0;
}

// Compiling a whole tape: a fresh evaluator (empty code cache) each time, asked for one point.
void BM_JitCompile(benchmark::State& state, const char* name) {
  const frep::Tape* tape = load_tape(name);
  if (!tape) return state.SkipWithError("shared data not found");
  if (!frep::jit_supported()) return state.SkipWithError("this CPU runs no JIT code");
  const auto backend = frep::make_jit_backend({.compile_after_points = 0});
  float p = 0.5f, out = 0;
  const frep::JitStats s0 = frep::jit_stats();
  for (auto _ : state) {
    frep::BatchEvaluator ev(*backend);
    ev.eval(*tape, &p, &p, &p, &out, 1);
    benchmark::DoNotOptimize(out);
  }
  report_compile_time(state, *tape, s0);
}
BENCHMARK_CAPTURE(BM_JitCompile, prospero, "prospero.vm")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_JitCompile, bear, "bear.vm")->Unit(benchmark::kMicrosecond);

// One 16-box interval pass of a whole tape on a named backend (the JIT's code compiled before
// the timing starts), 16 tiles of a 4x4 split of [-1, 1]^2 at z = 0: with BM_JitIntervalCompile,
// the number of passes a tape must be asked for to pay back its compilation (bench/jit.sh).
void BM_IntervalPassOn(benchmark::State& state, const char* name, const char* backend_name) {
  const frep::Tape* tape = load_tape(name);
  if (!tape) return state.SkipWithError("shared data not found");
  const bool jit = std::string(backend_name) == "jit";
  if (jit && !frep::jit_supported()) return state.SkipWithError("this CPU runs no JIT code");
  const auto backend = frep::make_jit_backend({.compile_after_interval_passes = 0});
  frep::IntervalBatchEvaluator ev(jit ? *backend : frep::interpreter_backend());
  frep::Interval x[16], y[16], z[16];
  for (int k = 0; k < 16; ++k) {
    x[k] = {-1.0f + 0.5f * static_cast<float>(k % 4), -0.5f + 0.5f * static_cast<float>(k % 4)};
    y[k] = {-1.0f + 0.5f * static_cast<float>(k / 4), -0.5f + 0.5f * static_cast<float>(k / 4)};
    z[k] = {0.0f, 0.0f};
  }
  ev.eval(*tape, x, y, z, 16);  // compiles
  for (auto _ : state) {
    ev.eval(*tape, x, y, z, 16);
    benchmark::DoNotOptimize(ev.result(0));
  }
  state.counters["instructions"] = static_cast<double>(tape->code().size());
}
BENCHMARK_CAPTURE(BM_IntervalPassOn, prospero_interp, "prospero.vm", "interp")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_IntervalPassOn, prospero_jit, "prospero.vm", "jit")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_IntervalPassOn, bear_interp, "bear.vm", "interp")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_IntervalPassOn, bear_jit, "bear.vm", "jit")->Unit(benchmark::kMicrosecond);

// Compiling a whole tape's interval pass: a fresh evaluator (empty code cache) each time.
void BM_JitIntervalCompile(benchmark::State& state, const char* name) {
  const frep::Tape* tape = load_tape(name);
  if (!tape) return state.SkipWithError("shared data not found");
  if (!frep::jit_supported()) return state.SkipWithError("this CPU runs no JIT code");
  const auto backend = frep::make_jit_backend({.compile_after_interval_passes = 0});
  const frep::Interval x{-0.5f, 0.5f};
  const frep::JitStats s0 = frep::jit_stats();
  for (auto _ : state) {
    frep::IntervalBatchEvaluator ev(*backend);
    ev.eval(*tape, &x, &x, &x, 1);
    benchmark::DoNotOptimize(ev.result(0));
  }
  report_compile_time(state, *tape, s0);
}
BENCHMARK_CAPTURE(BM_JitIntervalCompile, prospero, "prospero.vm")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_JitIntervalCompile, bear, "bear.vm")->Unit(benchmark::kMicrosecond);

void BM_PointEval(benchmark::State& state, const char* name) {
  const frep::Tape* tape = load_tape(name);
  if (!tape) return state.SkipWithError("shared data not found");
  PointSet p = random_points(256, true);
  frep::PointEvaluator ev;
  for (auto _ : state) {
    for (std::size_t i = 0; i < p.x.size(); ++i) p.out[i] = ev.eval(*tape, p.x[i], p.y[i], p.z[i]);
    benchmark::DoNotOptimize(p.out.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * p.x.size()));
}
BENCHMARK_CAPTURE(BM_PointEval, prospero, "prospero.vm");
BENCHMARK_CAPTURE(BM_PointEval, bear, "bear.vm");

void BM_GradEval(benchmark::State& state, const char* name) {
  const frep::Tape* tape = load_tape(name);
  if (!tape) return state.SkipWithError("shared data not found");
  PointSet p = random_points(1024, true);
  std::vector<frep::Grad> g(p.x.size());
  frep::GradEvaluator ev;
  for (auto _ : state) {
    ev.eval(*tape, p.x.data(), p.y.data(), p.z.data(), g.data(), p.x.size());
    benchmark::DoNotOptimize(g.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * p.x.size()));
}
BENCHMARK_CAPTURE(BM_GradEval, prospero, "prospero.vm");
BENCHMARK_CAPTURE(BM_GradEval, bear, "bear.vm");

void BM_IntervalEval(benchmark::State& state, const char* name) {
  const frep::Tape* tape = load_tape(name);
  if (!tape) return state.SkipWithError("shared data not found");
  frep::IntervalEvaluator ev;
  for (auto _ : state) {
    auto r = ev.eval(*tape, {-0.5f, -0.25f}, {0.25f, 0.5f}, {0.0f, 0.0f});
    benchmark::DoNotOptimize(r);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
}
BENCHMARK_CAPTURE(BM_IntervalEval, prospero, "prospero.vm");

}  // namespace

BENCHMARK_MAIN();
