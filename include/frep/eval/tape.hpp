// A compiled expression: a flat SSA list of instructions (root last), and the same program
// after register allocation, which the point, batch and gradient evaluators run.
#pragma once

#include <atomic>
#include <bit>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include "frep/eval/interval.hpp"
#include "frep/expr/graph.hpp"
#include "frep/util/large_allocator.hpp"

namespace frep {

// SSA instruction: arguments are indices of earlier instructions.
struct SsaInstr {
  Op op;
  std::uint32_t a = 0;
  std::uint32_t b = 0;
  float value = 0;  // Op::Const: the value; min/max/and/or in a tape: the bits of choice_ordinal;
                    // Op::Oracle: the bits of its index in the tape's oracles (oracle_index)
};

// A min/max/and/or instruction's ordinal among its tape's choices (0 first, in tape order), so
// that evaluators can keep per-choice data in arrays of Tape::choice_count() entries.
inline std::uint32_t choice_ordinal(const SsaInstr& s) { return std::bit_cast<std::uint32_t>(s.value); }

// Register instruction. A constant argument is an immediate (`imm`), flagged in `mode`; an
// Op::Oracle instruction keeps its oracle's index in `imm` (oracle_index).
struct RegInstr {
  Op op;
  std::uint8_t mode = 0;  // kImmA / kImmB bits
  std::uint32_t out = 0;
  std::uint32_t a = 0;
  std::uint32_t b = 0;
  float imm = 0;

  static constexpr std::uint8_t kImmA = 1;
  static constexpr std::uint8_t kImmB = 2;
};

class IntervalBatchEvaluator;

// The root cap of simplification (Tape::simplify) that keeps every value exact.
inline constexpr float kExactValues = std::numeric_limits<float>::infinity();

class Tape {
 public:
  Tape() = default;

  // Compiles the part of `g` reachable from `root`. Iterative; linear in the node count. The
  // tape shares g's oracles (it holds them; the graph may go).
  static Tape compile(const Graph& g, NodeId root);
  // Builds a tape from SSA instructions (root last); folds constants and allocates registers.
  // Op::Oracle instructions index `oracles`.
  static Tape from_ssa(const std::vector<SsaInstr>& ssa, std::shared_ptr<const OracleTable> oracles = nullptr);

  std::span<const SsaInstr> ssa() const { return {ssa_.data(), ssa_size_}; }
  // Register code; empty if the tape was simplified without registers.
  std::span<const RegInstr> code() const { return {code_.data(), code_size_}; }
  std::uint32_t num_registers() const { return num_regs_; }
  std::uint32_t root_register() const { return root_reg_; }
  std::size_t size() const { return ssa_size_; }
  // Instructions its buffers hold before growing (simplifying into it reuses them).
  std::size_t capacity() const { return ssa_.size(); }
  // Number of min/max/and/or instructions: zero means simplifying cannot shrink it further.
  std::uint32_t choice_count() const { return choices_; }
  // Bit 0/1/2: x/y/z appear in the tape (an oracle counts as all three).
  std::uint8_t vars_used() const { return vars_; }
  // Identifies the tape's contents: every tape built (compiled, or simplified into) gets a new
  // stamp, copies keep it. Backends key compiled code by it (tape buffers are reused, so their
  // address says nothing). 0 for an empty tape.
  std::uint64_t stamp() const { return stamp_; }
  // Counts an interval pass over this tape's contents and returns the count, this one included
  // (a tape rebuilt starts again from 0; a copy starts from its original's count). Backends that compile the
  // tapes evaluated often (the JIT) read it; thread-safe, and a const tape may count.
  std::uint64_t count_interval_pass() const { return passes_.n.fetch_add(1, std::memory_order_relaxed) + 1; }
  // Whether a backend found compiled interval code for this tape slower than interpreting it
  // (then others need not try again); set by the backend, cleared when the tape is rebuilt.
  bool interval_code_slower() const { return code_slower_.n.load(std::memory_order_relaxed) != 0; }
  void set_interval_code_slower() const { code_slower_.n.store(1, std::memory_order_relaxed); }
  // The oracles its Op::Oracle instructions index (null if it has none); simplified tapes share
  // their parent's.
  const std::shared_ptr<const OracleTable>& oracles() const { return oracles_; }
  const Oracle& oracle(float index_bits) const { return *(*oracles_)[oracle_index(index_bits)]; }

  // Rebuilds the tape keeping only what matters inside a region, given the per-instruction
  // intervals and choices of an interval evaluation over that region: one-sided choices become
  // their winning side, regions where an instruction is a single non-zero value become that
  // constant, and dead code is dropped. Writes into `out` to reuse its storage. Without
  // `registers`, only the SSA form is built: enough for further interval evaluation and
  // simplification, not for the point, batch or gradient evaluators.
  // `root_cap` C: the output equals this tape wherever this tape's value is <= C or NaN, and is
  // > C wherever it is > C. +inf (the default) keeps every value exact; a consumer that reads only
  // signs (an inside/outside image) passes 0, and then terms that can only change positive
  // values go too (far parts of a union, intersections with a shape the region lies outside of).
  void simplify(const std::vector<Interval>& values, const std::vector<Choice>& choices, Tape& out,
                bool registers = true, float root_cap = kExactValues) const;
  Tape simplified(const std::vector<Interval>& values, const std::vector<Choice>& choices) const;
  // (For many boxes at once, see IntervalBatchEvaluator::simplify.)

 private:
  friend class IntervalBatchEvaluator;
  class Builder;
  static void rebuild(std::span<const SsaInstr> src, const Interval* values, const Choice* choices, Tape& out,
                      bool registers, float root_cap = kExactValues);
  // Renames the builder's one-register-per-value code (see tape_builder.hpp) to reuse registers.
  void allocate_registers();

  // Buffers only grow (their size is a high-water mark), so reusing a tape as the output of
  // simplification again and again neither allocates nor re-initializes memory.
  LargeVector<SsaInstr> ssa_;
  LargeVector<RegInstr> code_;
  std::size_t ssa_size_ = 0;
  std::size_t code_size_ = 0;
  std::uint32_t num_regs_ = 0;
  std::uint32_t root_reg_ = 0;
  std::uint32_t choices_ = 0;
  std::uint8_t vars_ = 0;
  std::uint64_t stamp_ = 0;
  // A counter that copies with its value (Tape stays copyable).
  struct Counter {
    mutable std::atomic<std::uint64_t> n{0};
    Counter() = default;
    Counter(const Counter& o) : n(o.n.load(std::memory_order_relaxed)) {}
    Counter& operator=(const Counter& o) {
      n.store(o.n.load(std::memory_order_relaxed), std::memory_order_relaxed);
      return *this;
    }
  };
  Counter passes_;       // interval passes over its contents (count_interval_pass)
  Counter code_slower_;  // 1: interval_code_slower
  std::shared_ptr<const OracleTable> oracles_;
  LargeVector<std::uint32_t> remap_;  // scratch for simplification into this tape
  std::vector<std::uint8_t> state_;   // scratch for simplification into this tape
  std::vector<float> caps_;           // scratch for simplification into this tape
};

}  // namespace frep
