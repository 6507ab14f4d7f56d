// Evaluator backends: the code that runs tapes. BatchEvaluator, GradEvaluator and
// IntervalBatchEvaluator (evaluators.hpp, interval_batch.hpp) are what the subdivision driver, the
// mesher, the renderers and the samplers use; each hands its work to a kernel made by the backend
// chosen when the evaluator is made. A new backend (a JIT, a GPU) implements the kernels below and
// registers itself; no caller changes. Leaves computed by code (oracles, frep/expr/oracle.hpp)
// are called out to by every backend through the same Oracle interface.
//
// Which backend: the library option (set_default_backend), else the environment variable
// FREP_BACKEND: `jit` (the default: tapes compiled to machine code where that pays, jit.hpp; the
// interpreter runs the rest, and everything on CPUs without AVX2) or `interp` (the interpreter
// only).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "frep/math/grad.hpp"
#include "frep/eval/tape.hpp"
#include "frep/util/large_allocator.hpp"

namespace frep {

// Many points at once: out[i] = f(xs[i], ys[i], zs[i]), bit-identical to the point evaluator.
class BatchKernel {
 public:
  virtual ~BatchKernel() = default;
  virtual void eval(const Tape& tape, const float* xs, const float* ys, const float* zs, float* out, std::size_t n) = 0;
};

// Values and gradients (forward mode), with GradEvaluator's conventions.
class GradKernel {
 public:
  virtual ~GradKernel() = default;
  virtual void eval(const Tape& tape, const float* xs, const float* ys, const float* zs, Grad* out, std::size_t n) = 0;
};

// What an interval pass over 16 boxes leaves for simplification (IntervalBatchEvaluator::simplify,
// which is the same for every backend): per register instruction, bit masks of the boxes where a
// choice took its left or right side (set for choices only: the entries of other instructions
// are not read) and where the result folded to one value; each folded
// instruction's 16 values; each recorded min's argument bounds (for caps); the root's bounds.
struct IntervalRecord {
  static constexpr int kLanes = 16;
  LargeVector<std::uint16_t> left, right, fold;  // per register instruction
  LargeVector<float> mins;                       // per recorded min: alo, ahi, blo, bhi x 16 lanes
  std::size_t mins_count = 0;
  LargeVector<float> folds;                      // per instruction with folded lanes: its 16 values
  float result_lo[kLanes] = {}, result_hi[kLanes] = {};
};

// Interval arithmetic over up to 16 boxes at once, recording what simplification needs. `box`
// holds six rows of 16 lanes (x lo, x hi, y lo, y hi, z lo, z hi; unused lanes repeat box 0);
// `count` boxes are real, and only lanes of `fold_lanes` may be simplified afterwards.
class IntervalBatchKernel {
 public:
  virtual ~IntervalBatchKernel() = default;
  virtual void eval(const Tape& tape, const float* box, int count, std::uint32_t fold_lanes, IntervalRecord& record) = 0;
};

class Backend {
 public:
  virtual ~Backend() = default;
  // The name FREP_BACKEND selects it by.
  virtual const char* name() const = 0;
  virtual std::unique_ptr<BatchKernel> batch() const = 0;
  virtual std::unique_ptr<GradKernel> grad() const = 0;
  virtual std::unique_ptr<IntervalBatchKernel> interval_batch() const = 0;
};

// The interpreter: SIMD loops over register code (Highway, the instruction set chosen at run time).
const Backend& interpreter_backend();

// The backend evaluators use when made without one: set_default_backend's, else FREP_BACKEND's
// (read once; an unknown name is an InputError listing the available ones), else the JIT.
const Backend& default_backend();
// Chooses the default backend for evaluators made from now on (null: back to FREP_BACKEND's).
void set_default_backend(const Backend* backend);
// The backends of this build, by name.
std::vector<const Backend*> available_backends();
// The backend named `name`; InputError naming the available ones if there is none.
const Backend& backend_by_name(const std::string& name);

}  // namespace frep
