// The JIT backend: tapes compiled to x86-64 machine code (AVX-512 or AVX2, chosen at run time)
// with asmjit. It is an evaluator backend (backend.hpp), selected by FREP_BACKEND=jit or
// set_default_backend(&jit_backend()), and gives results bit-identical to the interpreter's: the
// same f32 operations in the same order.
//
// What it compiles: the tapes of the batch and gradient evaluators. A tape is compiled once it
// has been asked for enough points to pay for its compilation (JitOptions::compile_after_points,
// measured by bench/jit.sh), and its code is kept for later calls, keyed by Tape::stamp.
// Everything else runs on the interpreter: tapes with oracles (their code is a call anyway),
// tapes longer than max_instructions, CPUs without AVX2, the interval evaluator (each of its
// tapes is evaluated once, over 16 boxes: never enough to pay back a compilation), and any tape
// whose compilation fails (reported on stderr when FREP_JIT_DEBUG is set).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>

#include "frep/eval/backend.hpp"

namespace frep {

// The instruction set of generated code.
enum class JitIsa {
  Best,    // AVX-512 where the CPU has it, else AVX2, else none (the interpreter runs)
  Avx2,    // 8 lanes in ymm registers
  Avx512,  // 16 lanes in zmm registers
};

struct JitOptions {
  JitIsa isa = JitIsa::Best;  // instruction set of the generated code
  // A tape is compiled once the points asked of it (this call's included) reach this many: its
  // compilation pays for itself after about as many points again (bench/jit.sh measures 1,100
  // to 2,600 points on bear.vm and Prospero, whatever the tape's length), so a tape asked for
  // few points never waits for a compiler, and one asked for many is compiled early. 0
  // compiles every tape on first use (the tests do, to run the generated code on everything).
  std::size_t compile_after_points = 2048;
  std::size_t max_instructions = std::size_t{1} << 18;  // longer tapes stay interpreted
  int max_cached_tapes = 16;  // compiled tapes kept per evaluator (at most 64; the least recently used goes)
};

// True if this build has the JIT and this CPU runs `isa`'s code.
bool jit_supported(JitIsa isa = JitIsa::Best);

// A JIT backend with the given options (JitIsa::Best falls back to the interpreter on CPUs
// without AVX2; an explicit ISA the CPU lacks is an InputError).
std::unique_ptr<Backend> make_jit_backend(const JitOptions& options = {});

// The backend FREP_BACKEND=jit selects: default options.
const Backend& jit_backend();

// Counters over the whole process (every thread), for benchmarks and tests.
struct JitStats {
  std::uint64_t tapes_compiled = 0;        // compilations that produced code
  std::uint64_t instructions_compiled = 0; // register instructions in those tapes
  std::uint64_t compile_nanoseconds = 0;   // time spent compiling them
  std::uint64_t compile_failures = 0;      // tapes that could not be compiled (then interpreted)
  std::uint64_t points_compiled = 0;       // points evaluated by generated code
  std::uint64_t points_interpreted = 0;    // points a JIT evaluator left to the interpreter
};
JitStats jit_stats();

}  // namespace frep
