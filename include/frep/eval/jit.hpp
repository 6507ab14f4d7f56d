// The JIT backend: tapes compiled to x86-64 machine code (AVX-512 or AVX2, chosen at run time)
// with asmjit. It is an evaluator backend (backend.hpp), selected by FREP_BACKEND=jit or
// set_default_backend(&jit_backend()), and gives results bit-identical to the interpreter's: the
// same f32 operations in the same order.
//
// What it compiles: the tapes of the batch, gradient and 16-box interval evaluators. A tape is
// compiled once it has been asked for enough work to pay for its compilation (points:
// JitOptions::compile_after_points; interval passes: compile_after_interval_passes; both
// measured by bench/jit.sh), and its code is kept for later calls, keyed by Tape::stamp. Most
// interval tapes are simplified ones, evaluated in a pass or a few and then rebuilt: they stay
// on the interpreter. Tapes evaluated again and again reach the count (Tape::count_interval_pass):
// a model re-rendered, or sliced layer by layer; their code is timed on its first passes and
// dropped if it is not faster than the interpreter was on the same tape (long straight-line
// code run between other work runs from cold caches). Everything else runs on the
// interpreter: tapes with oracles (their code is a call anyway), tapes longer than
// max_instructions (max_interval_instructions), CPUs without AVX2, the single-box interval
// evaluator, and any tape whose compilation fails (reported on stderr when FREP_JIT_DEBUG is
// set).
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
  // compilation pays for itself after about as many points again (bench/jit.sh measures 2,600
  // to 3,400 points on Prospero, whatever the tape's length), so a tape asked for
  // few points never waits for a compiler, and one asked for many is compiled early. 0
  // compiles every tape on first use (the tests do, to run the generated code on everything).
  std::size_t compile_after_points = 2048;
  // The same for the interval-batch evaluator, in passes over up to 16 boxes: bench/jit.sh
  // measures a break-even of 80 to 90 passes on Prospero and bear.vm (compiling costs about
  // 0.4 ms per 1,000 instructions, a compiled pass run back to back about half an interpreted
  // one; code found slower where it runs is dropped). 0 compiles every tape on its first pass,
  // and keeps it.
  std::size_t compile_after_interval_passes = 80;
  // Value tapes whose library calls (exp, sin, fmod, ...: scalar code called out to, one vector
  // at a time) are more than this share of their instructions stay interpreted: a call costs the
  // generated code about what 25 native instructions save (bench/jit.sh: bear.vm, 5% calls, runs
  // 0.95x the interpreter's speed compiled). Not applied with compile_after_points = 0.
  double max_call_share = 0.04;
  std::size_t max_instructions = std::size_t{1} << 18;  // longer tapes stay interpreted
  // The same for interval passes, whose code is longer (about 170 bytes per instruction with
  // AVX-512, 320 with AVX2): at most 11 or 21 MB of code and ~30 ms of compilation per tape.
  std::size_t max_interval_instructions = std::size_t{1} << 16;
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
  std::uint64_t interval_passes_compiled = 0;     // 16-box interval passes run by generated code
  std::uint64_t interval_passes_interpreted = 0;  // and those left to the interpreter
  std::uint64_t tapes_dropped = 0;  // compiled interval passes slower than the interpreter's, given up
};
JitStats jit_stats();

}  // namespace frep
