// The JIT backend: a batch kernel that compiles tapes worth compiling and keeps their code, and
// the interpreter's kernels for everything else (jit.hpp says what runs where).
#include "frep/eval/jit.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <vector>

#include "eval/interp_kernels.hpp"
#include "eval/jit_codegen.hpp"
#include "eval/tape_builder.hpp"
#include "frep/error.hpp"
#include "frep/util/large_allocator.hpp"

namespace frep {
namespace {

// The statistics, counted per thread (a shared counter's cache line would bounce between the
// render's threads on every leaf) and summed by jit_stats. Each thread's counters stay registered
// after it ends, so nothing counted is lost.
struct alignas(64) Counters {
  std::atomic<std::uint64_t> tapes_compiled{0}, instructions_compiled{0}, compile_nanoseconds{0}, compile_failures{0},
      points_compiled{0}, points_interpreted{0}, interval_passes_compiled{0}, interval_passes_interpreted{0},
      tapes_dropped{0};
};
struct CounterRegistry {
  std::mutex mutex;
  std::vector<std::shared_ptr<Counters>> all;
};
CounterRegistry& registry() {
  static CounterRegistry r;
  return r;
}
Counters& counters() {
  thread_local const std::shared_ptr<Counters> mine = [] {
    auto c = std::make_shared<Counters>();
    CounterRegistry& r = registry();
    const std::lock_guard<std::mutex> lock(r.mutex);
    r.all.push_back(c);
    return c;
  }();
  return *mine;
}
// Adds to a counter only this thread writes: a plain load and store, no locked instruction.
void add(std::atomic<std::uint64_t>& c, std::uint64_t n) {
  c.store(c.load(std::memory_order_relaxed) + n, std::memory_order_relaxed);
}

bool debug_enabled() {
  static const bool on = [] {
    const char* e = std::getenv("FREP_JIT_DEBUG");
    return e && *e && std::strcmp(e, "0") != 0;
  }();
  return on;
}

bool resolve_avx512(JitIsa isa) {
  switch (isa) {
    case JitIsa::Avx512: return true;
    case JitIsa::Avx2: return false;
    default: return jit::cpu_has_avx512();
  }
}

// One evaluator's compiled tapes: the work asked of each recent tape (by stamp: points, or
// interval passes), and the code of those asked for enough.
class TapeCode {
 public:
  // channels: 1 values, 4 values and gradients, 0 interval passes.
  TapeCode(const JitOptions& o, bool avx512, int channels)
      : options_(o), cache_(avx512), channels_(channels),
        threshold_(channels == 0 ? o.compile_after_interval_passes : o.compile_after_points),
        max_instructions_(channels == 0 ? o.max_interval_instructions : o.max_instructions) {}
  ~TapeCode() {
    for (Entry& e : table_) cache_.release(e.fn);
  }
  TapeCode(const TapeCode&) = delete;
  TapeCode& operator=(const TapeCode&) = delete;

  int lanes() const { return cache_.lanes(); }
  int channels() const { return channels_; }

  // Reports how long the run after the last function_for_pass took (on its code or the
  // interpreter). A tape's code that, over its first kTrialRuns runs, is not faster than the
  // interpreter was on the same tape is dropped and the tape interpreted from then on, by
  // every evaluator (Tape::interval_code_slower): straight-line code for a long tape, run now
  // and then between other work, runs from cold caches (Prospero's interval pass inside a render: 217 us compiled, 62 us interpreted).
  // Only called while tracking().
  void timed(const Tape& tape, bool compiled, double ns) {
    Entry* e = last_;
    if (!compiled) {
      e->interp_ns += ns;
      ++e->interp_runs;
      return;
    }
    e->code_ns += ns;
    // The verdict, once: after it the tape is no longer tracked. Without interpreted runs to
    // compare with (a threshold of 1), the code stays.
    if (++e->code_runs < kTrialRuns || e->interp_runs == 0) return;
    const double code = e->code_ns / e->code_runs, interp = e->interp_ns / e->interp_runs;
    if (debug_enabled())
      std::fprintf(stderr, "frep jit: %s the code of a tape (intervals): %.1f us a pass, against %.1f us interpreted\n",
                   code >= interp ? "dropped" : "kept", code / 1e3, interp / 1e3);
    if (code >= interp) {
      cache_.release(e->fn);
      e->fn = nullptr;
      e->failed = true;
      --compiled_;
      add(counters().tapes_dropped, 1);
      tape.set_interval_code_slower();
    }
  }
  static constexpr std::uint32_t kTrialRuns = 8;
  // Whether the run after the last function_for_pass is to be timed: its tape is on trial (its
  // last interpreted passes before the compile count, then its first kTrialRuns compiled ones).
  // A threshold of 0 compiles every tape and keeps it: no trial.
  bool tracking() const { return last_ && threshold_ > 0 && !last_->failed && last_->code_runs < kTrialRuns; }

  // The compiled code for `tape`, compiling it if it has now been asked for enough points; null
  // where the interpreter runs it. Called for every evaluation (the renderers' leaves included),
  // so the lookup is two table slots, not a search.
  void* function_for(const Tape& tape, std::size_t n) {
    Entry* e = entry(tape);
    if (!e) return nullptr;
    if (e->fn || e->failed) return e->fn;
    e->points += n;
    if (e->points < threshold_) return nullptr;
    if (channels_ == 1 && threshold_ > 0 &&
        static_cast<double>(jit::value_calls(tape)) > options_.max_call_share * static_cast<double>(tape.code().size())) {
      e->failed = true;  // not a failure: interpreting it is as fast
      if (debug_enabled())
        std::fprintf(stderr, "frep jit: a tape of %zu instructions (values) stays interpreted: %zu are library calls\n",
                     tape.code().size(), jit::value_calls(tape));
      return nullptr;
    }
    return compile(*e, tape);
  }

  // For interval passes, which come one at a time: the code for `tape` on its `passes`-th pass
  // (Tape::count_interval_pass), compiled at the threshold. The tape counts its own passes, so
  // only tapes near the threshold enter the table: the stream of simplified tapes a
  // subdivision makes and evaluates once each never pushes a whole model out before it gets
  // there. At least kTrialRuns passes before it are timed on the interpreter (see timed).
  void* function_for_pass(const Tape& tape, std::uint64_t passes) {
    last_ = nullptr;
    if (passes + kTrialRuns < threshold_ || (threshold_ > 0 && tape.interval_code_slower())) return nullptr;
    Entry* e = entry(tape);
    if (!e) return nullptr;
    if (e->fn || e->failed) return e->fn;
    e->points = static_cast<std::size_t>(passes);
    // Each evaluator times the interpreter on the tape before compiling it (a tape shared by
    // several workers may reach the count in another's passes).
    const std::size_t timed_first = std::min<std::size_t>(kTrialRuns, threshold_ > 0 ? threshold_ - 1 : 0);
    if (e->points < threshold_ || e->interp_runs < timed_first) return nullptr;
    return compile(*e, tape);
  }

 private:
  struct Entry;
  // The table entry of `tape` (made if new, replacing the candidate slot without code, else the
  // one used longer ago); null for tapes that are never compiled. Sets last_.
  Entry* entry(const Tape& tape) {
    last_ = nullptr;
    const std::uint64_t stamp = tape.stamp();
    if (stamp == 0 || tape.code().empty() || tape.code().size() > max_instructions_ || tape.oracles()) return nullptr;
    ++clock_;
    // Two candidate slots (stamps are consecutive: the first spreads them, the second is a hash).
    Entry* const a = &table_[stamp & (kSlots - 1)];
    Entry* const b = &table_[(stamp * 0x9E3779B97F4A7C15ull) >> (64 - kSlotBits)];
    Entry* e = a->stamp == stamp ? a : b->stamp == stamp ? b : nullptr;
    if (!e) {
      e = (!a->fn && b->fn) ? a : (a->fn && !b->fn) ? b : (a->used <= b->used ? a : b);
      if (e->fn) {
        cache_.release(e->fn);
        --compiled_;
      }
      *e = Entry();
      e->stamp = stamp;
    }
    e->used = clock_;
    last_ = e;
    return e;
  }

  // Compiles `tape` into entry e; its code, or null (then e is marked failed).
  void* compile(Entry& e, const Tape& tape) {
    // Keep at most max_cached_tapes compiled: the least recently used compiled one goes.
    if (compiled_ >= static_cast<std::size_t>(std::max(options_.max_cached_tapes, 1))) {
      Entry* oldest = nullptr;
      for (Entry& c : table_)
        if (c.fn && (!oldest || c.used < oldest->used)) oldest = &c;
      if (oldest) {
        cache_.release(oldest->fn);  // (never e, which has no code yet)
        *oldest = Entry();
        --compiled_;
      }
    }
    const auto t0 = std::chrono::steady_clock::now();
    const char* why = "";
    e.fn = channels_ == 0 ? reinterpret_cast<void*>(cache_.compile_intervals(tape, &why))
                          : reinterpret_cast<void*>(cache_.compile(tape, channels_, &why));
    const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - t0).count();
    const char* what = channels_ == 1 ? "values" : channels_ == 4 ? "gradients" : "intervals";
    if (!e.fn) {
      e.failed = true;
      add(counters().compile_failures, 1);
      if (debug_enabled())
        std::fprintf(stderr, "frep jit: a tape of %zu instructions (%s) runs on the interpreter: %s\n", tape.code().size(),
                     what, why);
      return nullptr;
    }
    ++compiled_;
    add(counters().tapes_compiled, 1);
    add(counters().instructions_compiled, tape.code().size());
    add(counters().compile_nanoseconds, static_cast<std::uint64_t>(ns));
    if (debug_enabled())
      std::fprintf(stderr, "frep jit: compiled a tape of %zu instructions (%s) in %.1f us\n", tape.code().size(), what,
                   static_cast<double>(ns) / 1e3);
    return e.fn;
  }

  struct Entry {
    std::uint64_t stamp = 0;
    std::size_t points = 0;          // asked of the tape so far (points, or interval passes)
    void* fn = nullptr;              // its code, once compiled
    bool failed = false;             // compilation failed, or its code was slower: interpret it
    std::uint64_t used = 0;          // when last asked for (for eviction)
    double interp_ns = 0, code_ns = 0;       // time of the runs timed (see timed)
    std::uint32_t interp_runs = 0, code_runs = 0;
  };

  Entry* last_ = nullptr;  // the entry of the last function_for(_pass), if it has one

  static constexpr int kSlotBits = 6;
  static constexpr std::size_t kSlots = std::size_t{1} << kSlotBits;
  JitOptions options_;
  jit::CodeCache cache_;
  int channels_;
  std::size_t threshold_;         // work asked of a tape before it is compiled
  std::size_t max_instructions_;  // longer tapes stay interpreted
  std::array<Entry, kSlots> table_{};
  std::size_t compiled_ = 0;  // entries with code
  std::uint64_t clock_ = 0;
};

// What a JIT kernel keeps: its compiled tapes, the interpreter's kernel for the others, and
// scratch for the generated code.
template <class Kernel>
struct KernelState {
  KernelState(const JitOptions& o, bool avx512, int channels, std::unique_ptr<Kernel> interpreter)
      : code(o, avx512, channels), fallback(std::move(interpreter)) {}

  // The code to run `tape` on n points with (its scratch sized), or null where the interpreter
  // runs it; counts the points either way.
  jit::CompiledFn prepare(const Tape& tape, std::size_t n) {
    const auto fn = reinterpret_cast<jit::CompiledFn>(code.function_for(tape, n));
    add(fn ? counters().points_compiled : counters().points_interpreted, n);
    if (fn) {
      const std::size_t need = jit::CodeCache::scratch_floats(tape, code.lanes(), code.channels());
      if (regs.size() < need) regs.resize(need);
    }
    return fn;
  }
  // Runs fn on the last n < L points through copies padded with zeros (as the interpreter pads
  // its chunks); its channels x L outputs land in `block`.
  const float* run_partial(jit::CompiledFn fn, const float* xs, const float* ys, const float* zs, std::size_t n) {
    alignas(64) float px[16] = {}, py[16] = {}, pz[16] = {};
    std::memcpy(px, xs, n * sizeof(float));
    std::memcpy(py, ys, n * sizeof(float));
    std::memcpy(pz, zs, n * sizeof(float));
    grow_block(1);
    fn(px, py, pz, block.data(), regs.data(), 1);
    return block.data();
  }
  void grow_block(std::size_t vectors) {
    const std::size_t need = vectors * static_cast<std::size_t>(code.lanes() * code.channels());
    if (block.size() < need) block.resize(need);
  }

  TapeCode code;
  std::unique_ptr<Kernel> fallback;
  LargeVector<float> regs, block;
};

class JitBatch final : public BatchKernel {
 public:
  JitBatch(const JitOptions& o, bool avx512) : s_(o, avx512, 1, interp::make_batch_kernel()) {}

  void eval(const Tape& tape, const float* xs, const float* ys, const float* zs, float* out, std::size_t n) override {
    if (n == 0) return;
    const jit::CompiledFn fn = s_.prepare(tape, n);
    if (!fn) return s_.fallback->eval(tape, xs, ys, zs, out, n);
    // Whole vectors straight into `out`, then the last partial one.
    const std::size_t lanes = static_cast<std::size_t>(s_.code.lanes()), full = n / lanes * lanes;
    fn(xs, ys, zs, out, s_.regs.data(), full / lanes);
    if (full < n)
      std::memcpy(out + full, s_.run_partial(fn, xs + full, ys + full, zs + full, n - full), (n - full) * sizeof(float));
  }

 private:
  KernelState<BatchKernel> s_;
};

class JitGrad final : public GradKernel {
 public:
  JitGrad(const JitOptions& o, bool avx512) : s_(o, avx512, 4, interp::make_grad_kernel()) {}

  void eval(const Tape& tape, const float* xs, const float* ys, const float* zs, Grad* out, std::size_t n) override {
    if (n == 0) return;
    const jit::CompiledFn fn = s_.prepare(tape, n);
    if (!fn) return s_.fallback->eval(tape, xs, ys, zs, out, n);
    // The code writes four channel vectors per vector of points: through a block of 64 vectors
    // (it stays in cache) into Grad records.
    const std::size_t L = static_cast<std::size_t>(s_.code.lanes()), full = n / L * L;
    constexpr std::size_t kPiece = 64;
    s_.grow_block(kPiece);
    const auto store = [&](std::size_t base, const float* b, std::size_t count) {
      for (std::size_t p = 0; p < count; ++p) {
        const float* v = b + (p / L) * 4 * L + p % L;
        out[base + p] = {v[0], v[L], v[2 * L], v[3 * L]};
      }
    };
    for (std::size_t base = 0; base < full; base += kPiece * L) {
      const std::size_t count = std::min(kPiece * L, full - base);
      fn(xs + base, ys + base, zs + base, s_.block.data(), s_.regs.data(), count / L);
      store(base, s_.block.data(), count);
    }
    if (full < n) store(full, s_.run_partial(fn, xs + full, ys + full, zs + full, n - full), n - full);
  }

 private:
  KernelState<GradKernel> s_;
};

// The interval pass: compiled tapes write the same record as the interpreter's.
class JitIntervalBatch final : public IntervalBatchKernel {
 public:
  JitIntervalBatch(const JitOptions& o, bool avx512)
      : code_(o, avx512, 0), fallback_(interp::make_interval_batch_kernel()) {}

  void eval(const Tape& tape, const float* box, int count, std::uint32_t fold_lanes, IntervalRecord& rec) override {
    const auto fn = reinterpret_cast<jit::IntervalFn>(code_.function_for_pass(tape, tape.count_interval_pass()));
    add(fn ? counters().interval_passes_compiled : counters().interval_passes_interpreted, 1);
    // Only tapes near or past the threshold are timed: the clock stays off the passes of the
    // many tapes evaluated once.
    if (!code_.tracking()) return run(fn, tape, box, count, fold_lanes, rec);
    const auto t0 = std::chrono::steady_clock::now();
    run(fn, tape, box, count, fold_lanes, rec);
    code_.timed(tape, fn != nullptr, std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count());
  }

 private:
  void run(jit::IntervalFn fn, const Tape& tape, const float* box, int count, std::uint32_t fold_lanes,
           IntervalRecord& rec) {
    if (!fn) return fallback_->eval(tape, box, count, fold_lanes, rec);
    constexpr std::size_t L = IntervalRecord::kLanes;
    const std::size_t n = tape.code().size();
    grow_scratch(regs_, jit::CodeCache::interval_scratch_floats(tape));
    size_interval_record(tape, rec);
    // Room for every instruction's folded values (the interpreter appends; the code writes in
    // place, and simplification reads only as many as the fold bits say).
    if (rec.folds.size() < n * L) rec.folds.resize(n * L);
    jit::IntervalArgs args{box, regs_.data(), rec.left.data(), rec.right.data(), rec.fold.data(), rec.mins.data(),
                           rec.folds.data(), fold_lanes};
    fn(&args);
    rec.mins_count = static_cast<std::size_t>(args.mins - rec.mins.data()) / (4 * L);
    const float* root = regs_.data() + static_cast<std::size_t>(tape.root_register()) * 2 * L;
    std::copy(root, root + L, rec.result_lo);
    std::copy(root + L, root + 2 * L, rec.result_hi);
  }

  TapeCode code_;
  std::unique_ptr<IntervalBatchKernel> fallback_;
  LargeVector<float> regs_;
};

class Jit final : public Backend {
 public:
  explicit Jit(const JitOptions& o) : options_(o), active_(o.isa == JitIsa::Best ? jit_supported(JitIsa::Best) : true) {}
  const char* name() const override { return "jit"; }
  std::unique_ptr<BatchKernel> batch() const override {
    if (!active_) return interp::make_batch_kernel();
    return std::make_unique<JitBatch>(options_, resolve_avx512(options_.isa));
  }
  std::unique_ptr<GradKernel> grad() const override {
    if (!active_) return interp::make_grad_kernel();
    return std::make_unique<JitGrad>(options_, resolve_avx512(options_.isa));
  }
  std::unique_ptr<IntervalBatchKernel> interval_batch() const override {
    if (!active_) return interp::make_interval_batch_kernel();
    return std::make_unique<JitIntervalBatch>(options_, resolve_avx512(options_.isa));
  }

 private:
  JitOptions options_;
  bool active_;  // false: this CPU has no instruction set the JIT writes
};

}  // namespace

bool jit_supported(JitIsa isa) {
  switch (isa) {
    case JitIsa::Avx512: return jit::cpu_has_avx512();
    case JitIsa::Avx2: return jit::cpu_has_avx2();
    default: return jit::cpu_has_avx2() || jit::cpu_has_avx512();
  }
}

std::unique_ptr<Backend> make_jit_backend(const JitOptions& options) {
  if (options.isa != JitIsa::Best && !jit_supported(options.isa))
    throw InputError("FREP_BACKEND", 0,
                     std::string("this CPU does not run the JIT's ") + (options.isa == JitIsa::Avx512 ? "AVX-512" : "AVX2") +
                         " code");
  return std::make_unique<Jit>(options);
}

const Backend& jit_backend() {
  static const std::unique_ptr<Backend> b = make_jit_backend();
  return *b;
}

JitStats jit_stats() {
  JitStats s;
  CounterRegistry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  for (const auto& c : r.all) {
    s.tapes_compiled += c->tapes_compiled.load(std::memory_order_relaxed);
    s.instructions_compiled += c->instructions_compiled.load(std::memory_order_relaxed);
    s.compile_nanoseconds += c->compile_nanoseconds.load(std::memory_order_relaxed);
    s.compile_failures += c->compile_failures.load(std::memory_order_relaxed);
    s.points_compiled += c->points_compiled.load(std::memory_order_relaxed);
    s.points_interpreted += c->points_interpreted.load(std::memory_order_relaxed);
    s.interval_passes_compiled += c->interval_passes_compiled.load(std::memory_order_relaxed);
    s.interval_passes_interpreted += c->interval_passes_interpreted.load(std::memory_order_relaxed);
    s.tapes_dropped += c->tapes_dropped.load(std::memory_order_relaxed);
  }
  return s;
}

}  // namespace frep
