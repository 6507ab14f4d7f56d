// Machine code for tapes (private to the JIT backend, src/eval/jit_backend.cpp). The only file
// that includes asmjit is jit_codegen.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>

#include "frep/eval/tape.hpp"

namespace frep::jit {

// For v < vectors and i < L lanes (L = 8 or 16), point p = v * L + i: values, out[p] = f(x[p], ...);
// or values and gradients, out[4 v L + c L + i] = channel c (f, df/dx, df/dy, df/dz) at p.
// `regs` is scratch of scratch_floats floats, 64-byte aligned.
using CompiledFn = void (*)(const float* x, const float* y, const float* z, float* out, float* regs, std::size_t vectors);

// What compiled interval code reads and writes (IntervalRecord's arrays, backend.hpp): one
// interval pass over 16 boxes, per register instruction i: left[i], right[i], fold[i]; the
// bounds of recorded mins appended at `mins` and folded values at `folds`, both pointers moved
// past what was appended. Registers: per tape register, 16 lower then 16 upper bounds in `regs`
// (interval_scratch_floats, 64-byte aligned).
struct IntervalArgs {
  const float* box;  // six rows of 16 lanes: x lo, x hi, y lo, y hi, z lo, z hi
  float* regs;
  std::uint16_t* left;
  std::uint16_t* right;
  std::uint16_t* fold;
  float* mins;
  float* folds;
  std::uint32_t fold_lanes;  // the boxes that may be simplified afterwards
};
using IntervalFn = void (*)(IntervalArgs* args);

// Owns generated code (one per evaluator: not shared between threads).
class CodeCache {
 public:
  explicit CodeCache(bool avx512);
  ~CodeCache();
  CodeCache(const CodeCache&) = delete;
  CodeCache& operator=(const CodeCache&) = delete;

  int lanes() const { return avx512_ ? 16 : 8; }
  // Compiles the tape's register code for values (channels 1) or values and gradients
  // (channels 4); null if it cannot (an opcode it does not know, an assembler error), with the
  // reason in `why`.
  CompiledFn compile(const Tape& tape, int channels, const char** why);
  // Compiles the tape's register code for IntervalBatchKernel's pass (in either instruction
  // set: AVX2 code runs each 16-lane row as two halves); null with the reason in `why` if it
  // cannot.
  IntervalFn compile_intervals(const Tape& tape, const char** why);
  // Gives back the memory of a function compile or compile_intervals returned.
  void release(void* fn);
  // Floats of scratch a compiled tape needs.
  static std::size_t scratch_floats(const Tape& tape, int lanes, int channels) {
    return (static_cast<std::size_t>(tape.num_registers()) * static_cast<std::size_t>(channels) + 2) *
           static_cast<std::size_t>(lanes);
  }
  static std::size_t interval_scratch_floats(const Tape& tape) {
    return (static_cast<std::size_t>(tape.num_registers()) + 2) * 32;
  }

 private:
  struct Runtime;
  bool avx512_;
  std::unique_ptr<Runtime> rt_;
};

// The tape's register instructions that value code calls out for (libm functions, fmod).
std::size_t value_calls(const Tape& tape);

// True if the CPU runs AVX2 (with FMA-free AVX2 code only) or AVX-512F code.
bool cpu_has_avx2();
bool cpu_has_avx512();

}  // namespace frep::jit
