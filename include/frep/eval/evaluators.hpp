// The four evaluators. Each is a reusable object holding scratch memory; the tape is passed per
// call, because renderers and meshers switch between simplified tapes all the time. An evaluator
// object is not thread-safe: use one per thread. Tapes are read-only and can be shared.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "frep/eval/backend.hpp"
#include "frep/math/grad.hpp"
#include "frep/eval/interval.hpp"
#include "frep/eval/tape.hpp"

namespace frep {

// One point at a time, scalar.
class PointEvaluator {
 public:
  float eval(const Tape& tape, float x, float y, float z);

 private:
  std::vector<float> regs_;
};

// Many points at once with SIMD (AVX-512, AVX2 or SSE4, chosen at run time), run by a backend
// (backend.hpp: the interpreter unless another is chosen).
class BatchEvaluator {
 public:
  explicit BatchEvaluator(const Backend& backend = default_backend()) : kernel_(backend.batch()) {}

  // out[i] = f(xs[i], ys[i], zs[i]) for i < n. Bit-identical to PointEvaluator.
  void eval(const Tape& tape, const float* xs, const float* ys, const float* zs, float* out, std::size_t n) {
    kernel_->eval(tape, xs, ys, zs, out, n);
  }
  // Name of the instruction set chosen on this CPU, e.g. "AVX2".
  static const char* target_name();
  // Points the interpreter evaluates per pass over the tape.
  static constexpr std::size_t kChunk = 256;

 private:
  std::unique_ptr<BatchKernel> kernel_;
};

// Intervals: evaluates over a box and records, for every instruction, its interval and (for
// min/max/and/or) which side won, so that Tape::simplify can prune.
class IntervalEvaluator {
 public:
  Interval eval(const Tape& tape, Interval x, Interval y, Interval z);
  const std::vector<Interval>& values() const { return values_; }
  const std::vector<Choice>& choices() const { return choices_; }

  // Evaluates over the box and writes the simplified tape into `out`; returns the interval.
  Interval simplify(const Tape& tape, Interval x, Interval y, Interval z, Tape& out);

 private:
  std::vector<Interval> values_;
  std::vector<Choice> choices_;
};

// Value and gradient (forward mode), batched. Gradient conventions where the derivative does not exist: min/max/and/or take the gradient of
// the side they return; abs'(0) = +1; sqrt'(0) = 0 (so |p - a| has gradient 0, not NaN, exactly
// on a distance-to-edge curve); floor/ceil/round/compare/not have gradient 0.
class GradEvaluator {
 public:
  explicit GradEvaluator(const Backend& backend = default_backend()) : kernel_(backend.grad()) {}
  void eval(const Tape& tape, const float* xs, const float* ys, const float* zs, Grad* out, std::size_t n) {
    kernel_->eval(tape, xs, ys, zs, out, n);
  }
  Grad eval(const Tape& tape, float x, float y, float z) {
    Grad g;
    kernel_->eval(tape, &x, &y, &z, &g, 1);
    return g;
  }
  // Points the interpreter evaluates per pass over the tape.
  static constexpr std::size_t kChunk = 64;

 private:
  std::unique_ptr<GradKernel> kernel_;
};

}  // namespace frep
