// Tape::Builder (private to the evaluation code): writes one output tape during a forward sweep
// over a source tape. Shared by single-box and 16-box simplification.
#pragma once

#include <algorithm>
#include <cstdint>

#include "frep/error.hpp"
#include "frep/eval/backend.hpp"
#include "frep/eval/tape.hpp"
#include "frep/expr/semantics.hpp"

namespace frep {

// Grows a buffer whose contents are about to be overwritten to at least n entries: by half again
// at least (successive tapes written into one vary in size), freeing the old storage first so
// that its contents are neither copied nor kept alongside.
template <class V>
void grow_scratch(V& v, std::size_t n) {
  if (v.size() >= n) return;
  const std::size_t want = std::max(n, v.size() + v.size() / 2);
  V().swap(v);
  v.resize(want);
}

// Sizes the per-instruction arrays of an interval pass's record (backend.hpp) for `tape`, as
// every interval kernel needs them (their contents are about to be overwritten).
inline void size_interval_record(const Tape& tape, IntervalRecord& rec) {
  const std::size_t n = tape.code().size();
  grow_scratch(rec.left, n);
  grow_scratch(rec.right, n);
  grow_scratch(rec.fold, n);
  grow_scratch(rec.mins, static_cast<std::size_t>(tape.choice_count()) * 4 * IntervalRecord::kLanes);
}

// A stamp never given before (Tape::stamp).
std::uint64_t next_tape_stamp();

// Up to this many values, one register per value beats running the allocator (the batch
// evaluator's scratch stays small); beyond it registers are reused. Tapes that only run interval
// passes afford more (16 boxes' bounds per register: 512 KB at 4096).
inline constexpr std::size_t kMaxTrivialRegisters = 384;
inline constexpr std::size_t kMaxTrivialIntervalRegisters = 4096;

// Compacts the kept instructions, folds those whose arguments all became constants (exactly),
// and emits register code with one register per value on the fly.
class Tape::Builder {
 public:
  // `n_in`: the source tape's size; `n_out`: at most this many instructions will be kept (the
  // output buffers need no more). `remap`: where to keep the source-to-output index map (entry i
  // at remap[i * stride]); by default the output tape's own scratch.
  Builder(Tape& out, std::size_t n_in, bool registers, std::size_t n_out = SIZE_MAX, std::uint32_t* remap = nullptr,
          std::size_t stride = 1)
      : out_(out), registers_(registers), stride_(stride) {
    FREP_ASSERT(n_in < kConstBit, "tape too long");
    n_out = std::min(n_in, n_out);
    grow_scratch(out.ssa_, n_out);
    if (registers) grow_scratch(out.code_, n_out);
    if (!remap) {
      grow_scratch(out.remap_, n_in);
      remap = out.remap_.data();
    }
    os_ = out.ssa_.data();
    oc_ = out.code_.data();
    remap_ = remap;
  }

  // One register per value up to `n` values (default kMaxTrivialRegisters).
  void trivial_registers_up_to(std::size_t n) { trivial_limit_ = n; }

  [[gnu::always_inline]] void alias(std::size_t i, std::uint32_t src) { remap_[i * stride_] = remap_[src * stride_]; }

  [[gnu::always_inline]] void constant(std::size_t i, float v) {
    remap_[i * stride_] = m_ | kConstBit;
    os_[m_++] = {Op::Const, 0, 0, v};
  }

  [[gnu::always_inline]] inline void keep(std::size_t i, const SsaInstr& ins) {
    const int ar = op_arity(ins.op);
    if (ar == 0) {
      remap_[i * stride_] = ins.op == Op::Const ? m_ | kConstBit : m_;
      os_[m_] = ins;
      if (ins.op != Op::Const) {
        const bool oracle = ins.op == Op::Oracle;
        vars_ |= oracle ? std::uint8_t{7}
                        : static_cast<std::uint8_t>(1u << (static_cast<int>(ins.op) - static_cast<int>(Op::VarX)));
        if (registers_) oc_[k_++] = {ins.op, 0, m_, 0, 0, oracle ? ins.value : 0.0f};
      }
      ++m_;
      return;
    }
    // Constness travels in the remap entries, so that arguments' output entries (anywhere in
    // the output) are only read for the values of constants.
    const std::uint32_t ra = remap_[ins.a * stride_];
    const std::uint32_t rb = ar == 2 ? remap_[ins.b * stride_] : 0;
    const std::uint32_t a = ra & ~kConstBit, b = rb & ~kConstBit;
    const bool ca = ra & kConstBit;
    const bool cb = ar == 2 && (rb & kConstBit);
    if (ca && (ar == 1 || cb)) return constant(i, op_eval<float>(ins.op, os_[a].value, cb ? os_[b].value : 0.0f));
    remap_[i * stride_] = m_;
    const bool choice = op_is_choice(ins.op);
    os_[m_] = {ins.op, a, b, choice ? std::bit_cast<float>(choices_) : 0.0f};
    choices_ += choice;
    if (registers_) {
      RegInstr& r = oc_[k_++];
      r = {ins.op, 0, m_, a, b, 0.0f};
      if (ca) {
        r.mode = RegInstr::kImmA;
        r.imm = os_[a].value;
      } else if (cb) {
        r.mode = RegInstr::kImmB;
        r.imm = os_[b].value;
      }
    }
    ++m_;
  }

  void finish(std::size_t root_in) {
    Tape& t = out_;
    t.ssa_size_ = m_;
    t.code_size_ = k_;
    t.choices_ = choices_;
    t.vars_ = vars_;
    t.stamp_ = next_tape_stamp();
    t.passes_.n.store(0, std::memory_order_relaxed);
    t.code_slower_.n.store(0, std::memory_order_relaxed);
    const std::uint32_t root = remap_[root_in * stride_] & ~kConstBit;
    if (root + 1 != m_) {
      // Only a constant root can end up before other (then dead) instructions.
      FREP_ASSERT(os_[root].op == Op::Const, "root is not last");
      os_[0] = os_[root];
      t.ssa_size_ = 1;
      t.choices_ = 0;
      t.vars_ = 0;
    }
    t.num_regs_ = static_cast<std::uint32_t>(t.ssa_size_);
    t.root_reg_ = static_cast<std::uint32_t>(t.ssa_size_ - 1);
    if (!registers_) {
      t.code_size_ = 0;
      t.num_regs_ = 0;
      t.root_reg_ = 0;
    } else if (os_[t.ssa_size_ - 1].op == Op::Const || t.ssa_size_ > trivial_limit_) {
      t.allocate_registers();
    }
  }

 private:
  // Flags a remap entry whose output instruction is a constant (tapes stay below 2^31).
  static constexpr std::uint32_t kConstBit = 0x80000000u;
  Tape& out_;
  bool registers_;
  std::size_t trivial_limit_ = kMaxTrivialRegisters;
  std::size_t stride_;
  SsaInstr* os_;
  RegInstr* oc_;
  std::uint32_t* remap_;
  std::uint32_t m_ = 0;  // SSA instructions written
  std::uint32_t k_ = 0;  // register instructions written
  std::uint32_t choices_ = 0;
  std::uint8_t vars_ = 0;
};

}  // namespace frep
