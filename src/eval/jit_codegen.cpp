// Machine code for the batch, gradient and interval-batch evaluators' tapes, written with
// asmjit's assembler. (The interval pass is IntervalEmitter, below; what follows describes the
// point code.)
//
// The generated function runs the whole tape on one vector of points (8 or 16 lanes) at a time,
// in a loop over the vectors. Tape registers live in a scratch array, one vector each; a small
// cache keeps recently used ones in machine registers, so most arguments are never loaded.
// Results are written through to the scratch array (a store is cheap and leaves every value
// in memory when a register is evicted or a call clobbers them all). Each operation is the same
// f32 operation, with the same operand order, as the interpreter's (batch_eval.cpp), so results
// are bit-identical, NaNs included; libm functions and fmod are calls to the same scalar code.
#include "eval/jit_codegen.hpp"

#if FREP_HAVE_ASMJIT
#include <asmjit/x86.h>

#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

#include "eval/grad_partials.hpp"
#include "eval/interval_ops.hpp"
#include "frep/expr/semantics.hpp"

namespace frep::jit {
namespace {

using namespace asmjit;

// Ops the generated code calls out for, one vector at a time: o[i] = op(a[i], b[i]).
void scalar_op(float* o, const float* a, const float* b, int op, int lanes) {
  op_eval_lanes<float>(static_cast<Op>(op), o, a, 1, b, 1, static_cast<std::size_t>(lanes));
}

// The gradient evaluator's scalar path for one vector (grad_partials.hpp): o, A, B are blocks of
// four channels (value, d/dx, d/dy, d/dz; `lanes` floats each); flags: 1 = a is the immediate,
// 2 = b is, 4 = binary.
void grad_scalar(float* o, const float* A, const float* B, int op, int flags, int lanes, float imm) {
  const bool ia = flags & 1, ib = flags & 2, binary = flags & 4;
  for (int i = 0; i < lanes; ++i) {
    const float a = ia ? imm : A[i];
    const float b = !binary ? 0.0f : (ib ? imm : B[i]);
    const float da[3] = {A[lanes + i], A[2 * lanes + i], A[3 * lanes + i]};
    const float db[3] = {B[lanes + i], B[2 * lanes + i], B[3 * lanes + i]};
    float v, d[3];
    grad_detail::grad_lane(static_cast<Op>(op), a, da, !ia, b, db, binary && !ib, v, d);
    o[i] = v;
    for (int k = 0; k < 3; ++k) o[(k + 1) * lanes + i] = d[k];
  }
}

// Comparison predicates, as Highway uses them.
constexpr int kEqOQ = 0x00, kUnordQ = 0x03, kNeqUQ = 0x04, kLtOQ = 0x11, kLeOQ = 0x12, kNgeUQ = 0x19, kGeOQ = 0x1D,
              kGtOQ = 0x1E;
// vround/vrndscale immediates (rounding mode | suppress exceptions).
constexpr int kFloor = 0x09, kCeil = 0x0A, kTrunc = 0x0B;

class ErrorCatcher final : public ErrorHandler {
 public:
  void handleError(Error, const char* message, BaseEmitter*) override {
    if (!failed) why = message;
    failed = true;
  }
  bool failed = false;
  const char* why = nullptr;
};

// Whether the op has a vector form in value code; the others are calls.
bool native(Op op) {
  switch (op) {
    case Op::Neg: case Op::Abs: case Op::Recip: case Op::Sqrt: case Op::Square: case Op::Floor: case Op::Ceil:
    case Op::Round: case Op::Not: case Op::Add: case Op::Sub: case Op::Mul: case Op::Div: case Op::Min:
    case Op::Max: case Op::Compare: case Op::And: case Op::Or:
      return true;
    default: return false;
  }
}

// What both code generators share: the assembler and instruction set, a pool of float constants
// (stored after the code, broadcast from there), and the System V prologue and epilogue that save
// and restore the callee-saved registers the generated code uses.
class CodeWriter {
 protected:
  CodeWriter(x86::Assembler& a, bool avx512) : a_(a), avx512_(avx512) {}

  // Saves rbp, rbx and r12-r15, then reserves `frame` bytes of stack (frame % 16 == 8 keeps rsp
  // 16-byte aligned for calls).
  void prologue(int frame) {
    for (const x86::Gp& r : {x86::rbp, x86::rbx, x86::r12, x86::r13, x86::r14, x86::r15}) a_.push(r);
    a_.sub(x86::rsp, frame);
  }
  void epilogue(int frame) {
    a_.vzeroupper();
    a_.add(x86::rsp, frame);
    for (const x86::Gp& r : {x86::r15, x86::r14, x86::r13, x86::r12, x86::rbx, x86::rbp}) a_.pop(r);
    a_.ret();
  }

  // Vector register i of the instruction set (zmm or ymm).
  x86::Vec reg(int i) const {
    return avx512_ ? x86::Vec(x86::zmm(static_cast<std::uint32_t>(i))) : x86::Vec(x86::ymm(static_cast<std::uint32_t>(i)));
  }
  Label constant(float v) {
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(v);
    auto it = pool_.find(bits);
    if (it == pool_.end()) it = pool_.emplace(bits, a_.newLabel()).first;
    return it->second;
  }
  void broadcast(const x86::Vec& d, float v) { a_.vbroadcastss(d, x86::dword_ptr(constant(v))); }
  void vxor(const x86::Vec& d, const x86::Vec& p, const x86::Vec& q) { avx512_ ? a_.vpxord(d, p, q) : a_.vxorps(d, p, q); }
  // The constants, after the code.
  void emit_pool() {
    a_.align(AlignMode::kData, 4);
    for (auto& [bits, label] : pool_) {
      a_.bind(label);
      a_.embedUInt32(bits);
    }
  }

  x86::Assembler& a_;
  bool avx512_;

 private:
  std::unordered_map<std::uint32_t, Label> pool_;
};

class Emitter : CodeWriter {
 public:
  // channels: 1 for values, 4 for values and gradients (v, dx, dy, dz of a tape register are
  // four vectors, side by side in the scratch array).
  Emitter(x86::Assembler& a, bool avx512, std::uint32_t num_regs, int channels)
      : CodeWriter(a, avx512), vb_(avx512 ? 64 : 32), lanes_(avx512 ? 16 : 8), num_regs_(num_regs),
        channels_(channels), temps_(channels == 1 ? 2 : 6), first_slot_(temps_ + 2),
        slots_((avx512 ? 32 : 16) - first_slot_) {
    slot_.resize(static_cast<std::size_t>(slots_));
    where_.assign(static_cast<std::size_t>(num_regs) * static_cast<std::size_t>(channels), -1);
  }

  bool emit(const Tape& tape, const char** why) {
    const x86::Gp regs = x86::rbx, xp = x86::r12, yp = x86::r13, zp = x86::r14, outp = x86::r15, count = x86::rbp;
    // Prologue: System V arguments x, y, z, out, regs, vectors in rdi, rsi, rdx, rcx, r8, r9.
    prologue(8);
    a_.mov(xp, x86::rdi);
    a_.mov(yp, x86::rsi);
    a_.mov(zp, x86::rdx);
    a_.mov(outp, x86::rcx);
    a_.mov(regs, x86::r8);
    a_.mov(count, x86::r9);
    const Label done = a_.newLabel(), loop = a_.newLabel();
    a_.test(count, count);
    a_.jz(done);
    load_constants();
    a_.bind(loop);
    flush();
    next_uses(tape);
    for (k_ = 0; k_ < tape.code().size(); ++k_) {
      pinned_ = 0;
      const RegInstr& ins = tape.code()[k_];
      if (ins.op == Op::Oracle) {  // tapes with oracles are not compiled
        *why = "an oracle";
        return false;
      }
      if (op_arity(ins.op) == 0) {
        leaf(ins, xp, yp, zp);
      } else if (!(channels_ == 1 ? instruction(ins, regs) : grad_instruction(ins, regs))) {
        *why = "an opcode the JIT does not know";
        return false;
      }
    }
    if (out_of_registers_) {
      *why = "too few registers";
      return false;
    }
    pinned_ = 0;
    for (int c = 0; c < channels_; ++c)
      a_.vmovups(x86::ptr(outp, c * vb_), get(key(tape.root_register(), c), kNever, regs));
    a_.add(xp, vb_);
    a_.add(yp, vb_);
    a_.add(zp, vb_);
    a_.add(outp, vb_ * channels_);
    a_.dec(count);
    a_.jnz(loop);
    a_.bind(done);
    epilogue(8);
    // Constants: whole vectors, then single floats to broadcast.
    for (auto& [bits, label] : vector_pool_) {
      a_.align(AlignMode::kData, static_cast<std::uint32_t>(vb_));
      a_.bind(label);
      a_.embedUInt32(bits, static_cast<std::size_t>(lanes_));
    }
    emit_pool();
    return true;
  }

 private:
  static constexpr std::uint32_t kEmpty = UINT32_MAX;
  // Machine vector registers: temps_ temporaries (2 for values, 6 for gradients), then +1 and +0
  // for the whole loop (reloaded after calls), then the cache of tape registers.
  x86::Vec vec(int i) {
    // AVX2 has 16 registers (ymm16 and up need AVX-512, which an AVX2 machine would fault on).
    if (i >= (avx512_ ? 32 : 16)) out_of_registers_ = true;
    return reg(i);
  }
  x86::Vec t0() { return vec(0); }
  x86::Vec t1() { return vec(1); }
  x86::Vec t(int i) { return vec(i); }
  x86::Vec one() { return vec(temps_); }
  x86::Vec zero() { return vec(temps_ + 1); }
  x86::Vec cached(int s) { return vec(first_slot_ + s); }
  std::uint32_t key(std::uint32_t reg, int c) const { return reg * static_cast<std::uint32_t>(channels_) + static_cast<std::uint32_t>(c); }

  // A whole vector of v, for operands that must be in memory.
  Label vector_constant(float v) {
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(v);
    auto it = vector_pool_.find(bits);
    if (it == vector_pool_.end()) it = vector_pool_.emplace(bits, a_.newLabel()).first;
    return it->second;
  }
  void load_constants() {
    broadcast(one(), 1.0f);
    if (avx512_) {
      a_.vpxord(zero(), zero(), zero());
    } else {
      a_.vxorps(zero(), zero(), zero());
    }
  }
  // Tape registers are cached in machine registers with write-back: a value goes to the scratch
  // array only when its slot is taken while the value will still be read (or before a call).
  // The slot to take is the one whose value is read furthest in the future (Belady's choice),
  // from the next uses computed once per tape.
  static constexpr std::uint32_t kNever = UINT32_MAX;
  struct Slot {
    std::uint32_t key = kEmpty;   // what it holds: channel c of tape register r (key(r, c))
    std::uint32_t next = kNever;  // index of the instruction that reads it next
    bool dirty = false;           // not yet in the scratch array
  };

  // def_next_[k]: the first read of instruction k's result; arg_next_[2k + i]: the next read of
  // argument i's value after instruction k (kNever: none; the root is read after the last one).
  void next_uses(const Tape& tape) {
    const auto code = tape.code();
    const std::size_t n = code.size();
    def_next_.assign(n, kNever);
    arg_next_.assign(2 * n, kNever);
    std::vector<std::uint32_t> next_read(num_regs_, kNever);
    next_read[tape.root_register()] = static_cast<std::uint32_t>(n);
    for (std::size_t k = n; k-- > 0;) {
      const RegInstr& r = code[k];
      def_next_[k] = next_read[r.out];
      next_read[r.out] = kNever;  // earlier reads of this register see an older value
      const int ar = op_arity(r.op);
      if (ar >= 1 && !(r.mode & RegInstr::kImmA)) {
        arg_next_[2 * k] = next_read[r.a];
        next_read[r.a] = static_cast<std::uint32_t>(k);
      }
      if (ar >= 2 && !(r.mode & RegInstr::kImmB)) {
        arg_next_[2 * k + 1] = r.b == r.a && !(r.mode & RegInstr::kImmA) ? arg_next_[2 * k] : next_read[r.b];
        next_read[r.b] = static_cast<std::uint32_t>(k);
      }
    }
  }

  void flush() {
    for (Slot& s : slot_) s = Slot();
    free_ = slots_ == 32 ? ~0u : (1u << slots_) - 1;
    std::fill(where_.begin(), where_.end(), -1);
  }

  x86::Mem slot_mem(std::uint32_t k, const x86::Gp& regs) const {
    return x86::ptr(regs, static_cast<std::int32_t>(static_cast<std::int64_t>(k) * vb_));
  }
  Slot& slot(int s) { return slot_[static_cast<std::size_t>(s)]; }
  // Writes slot s's value to the scratch array if it is still to be read and not there yet.
  void write_back(int s) {
    Slot& c = slot(s);
    if (c.key != kEmpty && c.dirty && c.next != kNever) a_.vmovaps(slot_mem(c.key, x86::rbx), cached(s));
    c.dirty = false;
  }
  // Empties slot s (writing its value back if needed).
  void evict(int s) {
    Slot& c = slot(s);
    if (c.key == kEmpty) return;
    write_back(s);
    where_[c.key] = -1;
    c = Slot();
    free_ |= 1u << s;
  }
  void pin(int s) { pinned_ |= 1u << s; }
  // Records slot s's next read (kNever: its value is dead, the slot free to take).
  void set_next(int s, std::uint32_t next) {
    slot(s).next = next;
    if (next == kNever) {
      free_ |= 1u << s;
    } else {
      free_ &= ~(1u << s);
    }
  }
  // The slot to take, not pinned by the instruction being written: an empty or dead one (a bit
  // mask keeps them: compiling is mostly this choice), else the one read furthest ahead.
  int victim() {
    if (const std::uint32_t avail = free_ & ~pinned_) return std::countr_zero(avail);
    int best = -1;
    for (int s = 0; s < slots_; ++s) {
      if (pinned_ >> s & 1) continue;
      const Slot& c = slot(s);
      if (best < 0 || c.next > slot(best).next) best = s;
    }
    if (best < 0) {  // every register pinned: cannot happen with the counts above; refuse the tape
      out_of_registers_ = true;
      return 0;
    }
    return best;
  }
  // `k` (a key) in a machine register, loaded if needed and pinned for the rest of the
  // instruction; its value is next read at `next`.
  x86::Vec get(std::uint32_t k, std::uint32_t next, const x86::Gp& regs) {
    int s = where_[k];
    if (s < 0) {
      s = victim();
      evict(s);
      a_.vmovaps(cached(s), slot_mem(k, regs));
      slot(s).key = k;
      where_[k] = s;
    }
    set_next(s, next);
    pin(s);
    return cached(s);
  }

  // The destination of instruction k_ writing key `k`: a slot other than the arguments' and the
  // other destinations' (pinned), so sequences of several operations may read the arguments
  // after writing it.
  x86::Vec dest(std::uint32_t k) {
    if (const int old = where_[k]; old >= 0) {
      // The register's previous value dies here (an argument's slot is pinned, so it stays
      // intact until the instruction is written).
      slot(old) = Slot();
      free_ |= 1u << old;
      where_[k] = -1;
    }
    const int s = victim();
    evict(s);
    slot(s) = {k, def_next_[k_], true};
    set_next(s, def_next_[k_]);
    where_[k] = s;
    pin(s);
    return cached(s);
  }

  // Bitwise operations (AVX-512F has them on integers only; the bits are the same).
  void vand(const x86::Vec& d, const x86::Vec& p, const x86::Vec& q) { avx512_ ? a_.vpandd(d, p, q) : a_.vandps(d, p, q); }
  void vor(const x86::Vec& d, const x86::Vec& p, const x86::Vec& q) { avx512_ ? a_.vpord(d, p, q) : a_.vorps(d, p, q); }
  void vround(const x86::Vec& d, const x86::Vec& s, int mode) {
    avx512_ ? a_.vrndscaleps(d, s, mode) : a_.vroundps(d, s, mode);
  }
  // d = mask(p, q, predicate) ? t : d, with the mask in k1 or t0. (t must not be t0 on AVX2.)
  void select_where(const x86::Vec& d, const x86::Vec& p, const x86::Vec& q, int predicate, const x86::Vec& t) {
    if (avx512_) {
      a_.vcmpps(x86::k1, p, q, predicate);
      a_.k(x86::k1).vmovaps(d, t);
    } else {
      a_.vcmpps(t0(), p, q, predicate);
      a_.vblendvps(d, d, t, t0());
    }
  }

  // A variable (its value; for gradients, the unit vector of its axis) or a constant (zero
  // gradient), for either channel count.
  void leaf(const RegInstr& ins, const x86::Gp& xp, const x86::Gp& yp, const x86::Gp& zp) {
    const int axis = static_cast<int>(ins.op) - static_cast<int>(Op::VarX);  // 0, 1, 2 for variables
    if (ins.op == Op::Const) {
      broadcast(dest(key(ins.out, 0)), ins.imm);
    } else {
      a_.vmovups(dest(key(ins.out, 0)), x86::ptr(axis == 0 ? xp : axis == 1 ? yp : zp));
    }
    for (int c = 1; c < channels_; ++c)
      a_.vmovaps(dest(key(ins.out, c)), ins.op != Op::Const && c - 1 == axis ? one() : zero());
  }

  bool instruction(const RegInstr& ins, const x86::Gp& regs) {
    const int ar = op_arity(ins.op);
    if (!native(ins.op)) return call_out(ins, regs, ar);
    // Arguments: cached or loaded registers, immediates broadcast into t1.
    x86::Vec p, q;
    if (ins.mode & RegInstr::kImmA) {
      p = t1();
      broadcast(p, ins.imm);
    } else {
      p = get(ins.a, arg_next_[2 * k_], regs);
    }
    if (ar == 2) {
      if (ins.mode & RegInstr::kImmB) {
        q = t1();
        broadcast(q, ins.imm);
      } else {
        q = get(ins.b, arg_next_[2 * k_ + 1], regs);
      }
    }
    const x86::Vec d = dest(ins.out);
    switch (ins.op) {
      case Op::Neg:
        broadcast(t0(), -0.0f);
        vxor(d, p, t0());
        break;
      case Op::Abs:
        broadcast(t0(), std::bit_cast<float>(0x7fffffffu));
        vand(d, p, t0());
        break;
      case Op::Recip: a_.vdivps(d, one(), p); break;
      case Op::Sqrt: a_.vsqrtps(d, p); break;
      case Op::Square: a_.vmulps(d, p, p); break;
      case Op::Floor: vround(d, p, kFloor); break;
      case Op::Ceil: vround(d, p, kCeil); break;
      case Op::Round: {
        // t = trunc(p); |p - t| >= 0.5 ? t + copysign(1, p) : t
        const x86::Vec c = t1();  // free: a unary op's argument is never an immediate
        vround(d, p, kTrunc);
        a_.vsubps(t0(), p, d);
        broadcast(c, std::bit_cast<float>(0x7fffffffu));
        vand(t0(), t0(), c);
        broadcast(c, 0.5f);
        if (avx512_) {
          a_.vcmpps(x86::k2, t0(), c, kGeOQ);
          broadcast(c, -0.0f);
          vand(c, p, c);
          vor(c, c, one());
          a_.vaddps(c, d, c);
          a_.k(x86::k2).vmovaps(d, c);
        } else {
          a_.vcmpps(t0(), t0(), c, kGeOQ);
          broadcast(c, -0.0f);
          vand(c, p, c);
          vor(c, c, one());
          a_.vaddps(c, d, c);
          a_.vblendvps(d, d, c, t0());
        }
        break;
      }
      case Op::Not:  // p == 0 ? 1 : 0
        if (avx512_) {
          a_.vmovaps(d, zero());
          select_where(d, p, zero(), kEqOQ, one());
        } else {
          a_.vcmpps(t0(), p, zero(), kEqOQ);
          vand(d, t0(), one());
        }
        break;
      case Op::Add: a_.vaddps(d, p, q); break;
      case Op::Sub: a_.vsubps(d, p, q); break;
      case Op::Mul: a_.vmulps(d, p, q); break;
      case Op::Div: a_.vdivps(d, p, q); break;
      case Op::Min:  // minps is p < q ? p : q; a NaN in p must win too
        a_.vminps(d, p, q);
        select_where(d, p, p, kUnordQ, p);
        break;
      case Op::Max:
        a_.vmaxps(d, p, q);
        select_where(d, p, p, kUnordQ, p);
        break;
      case Op::Compare: {
        // p < q ? -1 : p > q ? 1 : 0; p + q (NaN) if either is NaN
        if (avx512_) {
          a_.vmovaps(d, zero());
          select_where(d, p, q, kGtOQ, one());
          broadcast(t0(), -1.0f);
          select_where(d, p, q, kLtOQ, t0());
          a_.vaddps(t0(), p, q);
          select_where(d, p, q, kUnordQ, t0());
        } else {
          // t1 may hold an argument: it is overwritten only once the masks are taken.
          a_.vcmpps(t0(), p, q, kGtOQ);
          vand(d, t0(), one());
          a_.vcmpps(t0(), p, q, kLtOQ);
          a_.vblendvps(d, d, x86::ptr(vector_constant(-1.0f)), t0());
          a_.vcmpps(t0(), p, q, kUnordQ);
          a_.vaddps(t1(), p, q);
          a_.vblendvps(d, d, t1(), t0());
        }
        break;
      }
      case Op::And:  // p == 0 ? p : q
        a_.vmovaps(d, q);
        select_where(d, p, zero(), kEqOQ, p);
        break;
      case Op::Or:  // p != 0 ? p : q
        a_.vmovaps(d, p);
        select_where(d, p, zero(), kEqOQ, q);
        break;
      default: return false;
    }
    return true;
  }

  x86::Mem spare(int k) const {
    return x86::ptr(x86::rbx, static_cast<std::int32_t>((static_cast<std::int64_t>(num_regs_) * channels_ + k) * vb_));
  }

  // ---- Values and gradients (channels_ == 4) -------------------------------------------------
  // Each operation computes what the interpreter's gradient evaluator computes (grad_eval.cpp:
  // its SIMD forms for the ops it vectorizes, its scalar path through grad_partials.hpp for the
  // others, which are calls here too).

  void unpin(int s) { pinned_ &= ~(1u << s); }
  int slot_of(const x86::Vec& v) const { return static_cast<int>(v.id()) - first_slot_; }
  // An argument's channel c: its cached register, or for an immediate its value in `imm_reg`
  // (c = 0) and +0 (gradients).
  x86::Vec garg(const RegInstr& ins, bool second, int c, const x86::Gp& regs) {
    const bool imm = second ? (ins.mode & RegInstr::kImmB) : (ins.mode & RegInstr::kImmA);
    if (imm) return c == 0 ? t(second ? 5 : 4) : zero();
    return get(key(second ? ins.b : ins.a, c), arg_next_[2 * k_ + (second ? 1 : 0)], regs);
  }
  void release_arg(const RegInstr& ins, bool second, const x86::Vec& v) {
    const bool imm = second ? (ins.mode & RegInstr::kImmB) : (ins.mode & RegInstr::kImmA);
    if (!imm) unpin(slot_of(v));
  }
  // d = p == 0 ? +0 : p * dv (a zero partial never turns an infinite or NaN gradient into NaN);
  // d must not be p.
  void scaled(const x86::Vec& d, const x86::Vec& p, const x86::Vec& dv) {
    a_.vmulps(d, p, dv);
    if (avx512_) {
      a_.vcmpps(x86::k1, p, zero(), kEqOQ);
      a_.k(x86::k1).vmovaps(d, zero());
    } else {
      a_.vcmpps(t0(), p, zero(), kEqOQ);
      a_.vandnps(d, t0(), d);
    }
  }
  // d = mask ? q : p, the mask from a compare into k2 (AVX-512) or t(2) (AVX2).
  void cmp_mask(const x86::Vec& p, const x86::Vec& q, int predicate) {
    if (avx512_) {
      a_.vcmpps(x86::k2, p, q, predicate);
    } else {
      a_.vcmpps(t(2), p, q, predicate);
    }
  }
  void blend_mask(const x86::Vec& d, const x86::Vec& p, const x86::Vec& q) {
    if (avx512_) {
      if (d != p) a_.vmovaps(d, p);
      a_.k(x86::k2).vmovaps(d, q);
    } else {
      a_.vblendvps(d, p, q, t(2));
    }
  }

  bool grad_instruction(const RegInstr& ins, const x86::Gp& regs) {
    const int ar = op_arity(ins.op);
    switch (ins.op) {
      case Op::Add: case Op::Sub: case Op::Mul: case Op::Div: case Op::Min: case Op::Max: case Op::Neg:
      case Op::Abs: case Op::Square: case Op::Sqrt:
        break;
      default: return call_out(ins, regs, ar);
    }
    if (ins.mode & RegInstr::kImmA) broadcast(t(4), ins.imm);
    if (ins.mode & RegInstr::kImmB) broadcast(t(5), ins.imm);
    const x86::Vec av = garg(ins, false, 0, regs);
    const x86::Vec bv = ar == 2 ? garg(ins, true, 0, regs) : zero();
    // The value, and what the gradient channels need from it.
    const x86::Vec v = dest(key(ins.out, 0));
    switch (ins.op) {
      case Op::Add: a_.vaddps(v, av, bv); break;
      case Op::Sub: a_.vsubps(v, av, bv); break;
      case Op::Mul: a_.vmulps(v, av, bv); break;
      case Op::Div:
        a_.vdivps(t(2), one(), bv);  // d/da = 1 / b
        a_.vmulps(t(3), bv, bv);     // d/db = -(a / (b * b))
        a_.vdivps(t(3), av, t(3));
        broadcast(t1(), -0.0f);
        vxor(t(3), t(3), t1());
        a_.vdivps(v, av, bv);
        break;
      case Op::Min:
      case Op::Max:
        if (ins.op == Op::Min) {
          a_.vminps(v, av, bv);
        } else {
          a_.vmaxps(v, av, bv);
        }
        if (avx512_) {
          a_.vcmpps(x86::k1, av, av, kUnordQ);
          a_.k(x86::k1).vmovaps(v, av);
          a_.vcmpps(x86::k2, av, bv, ins.op == Op::Min ? kLtOQ : kGtOQ);  // take a's gradient
          a_.vcmpps(x86::k3, v, v, kUnordQ);                              // NaN: the gradient is the value
        } else {
          a_.vcmpps(t0(), av, av, kUnordQ);
          a_.vblendvps(v, v, av, t0());
          a_.vcmpps(t(2), av, bv, ins.op == Op::Min ? kLtOQ : kGtOQ);
          a_.vcmpps(t(3), v, v, kUnordQ);
        }
        break;
      case Op::Neg:
        broadcast(t(3), -0.0f);
        vxor(v, av, t(3));
        break;
      case Op::Abs:
        broadcast(t(3), -0.0f);
        cmp_mask(av, zero(), kLtOQ);  // negative: the gradient flips
        avx512_ ? a_.vpandnd(v, t(3), av) : a_.vandnps(v, t(3), av);
        break;
      case Op::Square:
        a_.vmulps(v, av, av);
        broadcast(t(2), 2.0f);
        a_.vmulps(t(2), t(2), av);  // d/da = 2 a
        break;
      case Op::Sqrt:
        a_.vsqrtps(v, av);
        broadcast(t(2), 0.5f);
        a_.vdivps(t(2), t(2), v);  // d/da = 0.5 / v, or 0 where v is 0
        if (avx512_) {
          a_.vcmpps(x86::k1, v, zero(), kEqOQ);
          a_.k(x86::k1).vmovaps(t(2), zero());
        } else {
          a_.vcmpps(t0(), v, zero(), kEqOQ);
          a_.vandnps(t(2), t0(), t(2));
        }
        break;
      default: return false;
    }
    // The gradient channels, one at a time (their arguments are released after each, so that
    // AVX2's few registers suffice).
    for (int c = 1; c < 4; ++c) {
      const x86::Vec da = garg(ins, false, c, regs);
      const x86::Vec db = ar == 2 ? garg(ins, true, c, regs) : zero();
      const x86::Vec d = dest(key(ins.out, c));
      switch (ins.op) {
        case Op::Add: a_.vaddps(d, da, db); break;
        case Op::Sub: a_.vsubps(d, da, db); break;
        case Op::Mul:  // b da + a db
          scaled(d, bv, da);
          scaled(t1(), av, db);
          a_.vaddps(d, d, t1());
          break;
        case Op::Div:
          scaled(d, t(2), da);
          scaled(t1(), t(3), db);
          a_.vaddps(d, d, t1());
          break;
        case Op::Min:
        case Op::Max:
          if (avx512_) {
            a_.vmovaps(d, db);
            a_.k(x86::k2).vmovaps(d, da);
            a_.k(x86::k3).vmovaps(d, v);
          } else {
            a_.vblendvps(d, db, da, t(2));
            a_.vblendvps(d, d, v, t(3));
          }
          break;
        case Op::Neg: vxor(d, da, t(3)); break;
        case Op::Abs:
          vxor(t1(), da, t(3));
          blend_mask(d, da, t1());
          break;
        case Op::Square:
        case Op::Sqrt: scaled(d, t(2), da); break;
        default: return false;
      }
      release_arg(ins, false, da);
      if (ar == 2) release_arg(ins, true, db);
    }
    return true;
  }

  // o = scalar_op(a, b) through memory: every value still to be read, and the arguments, are
  // written back first (the call clobbers all vector registers); immediates go to the two
  // spare vectors.
  bool call_out(const RegInstr& ins, const x86::Gp& regs, int ar) {
    if (ar < 1 || ar > 2) return false;
    for (std::uint32_t r : {ins.a, ins.b})
      for (int c = 0; c < channels_ && r < num_regs_; ++c)
        if (const int s = where_[key(r, c)]; s >= 0 && slot(s).dirty) {
          a_.vmovaps(slot_mem(key(r, c), regs), cached(s));
          slot(s).dirty = false;
        }
    for (int s = 0; s < slots_; ++s) write_back(s);
    if (channels_ == 4) {
      // grad_scalar(o, A, B, op, flags, lanes, imm): blocks of four channels; an immediate is
      // passed by value (its pointer argument is any valid address).
      const bool ia = ins.mode & RegInstr::kImmA, ib = ins.mode & RegInstr::kImmB;
      a_.lea(x86::rdi, slot_mem(key(ins.out, 0), regs));
      a_.lea(x86::rsi, slot_mem(key(ia ? ins.out : ins.a, 0), regs));
      a_.lea(x86::rdx, slot_mem(key(ar == 2 && !ib ? ins.b : ins.out, 0), regs));
      a_.mov(x86::ecx, static_cast<int>(ins.op));
      a_.mov(x86::r8d, (ia ? 1 : 0) | (ib ? 2 : 0) | (ar == 2 ? 4 : 0));
      a_.mov(x86::r9d, lanes_);
      a_.vmovss(x86::xmm0, x86::dword_ptr(constant(ins.imm)));
      a_.vzeroupper();  // keeps xmm0 (the low half)
      a_.mov(x86::rax, reinterpret_cast<std::uint64_t>(&grad_scalar));
      a_.call(x86::rax);
      flush();
      load_constants();
      return true;
    }
    const auto operand = [&](bool imm, std::uint32_t reg, int spare_index, const x86::Gp& dst) {
      if (imm) {
        broadcast(t0(), ins.imm);
        a_.vmovaps(spare(spare_index), t0());
        a_.lea(dst, spare(spare_index));
      } else {
        a_.lea(dst, slot_mem(reg, regs));
      }
    };
    operand(ins.mode & RegInstr::kImmA, ins.a, 0, x86::rsi);
    if (ar == 2) {
      operand(ins.mode & RegInstr::kImmB, ins.b, 1, x86::rdx);
    } else {
      a_.mov(x86::rdx, x86::rsi);  // unused by unary ops, but a valid pointer
    }
    a_.lea(x86::rdi, slot_mem(ins.out, regs));
    a_.mov(x86::ecx, static_cast<int>(ins.op));
    a_.mov(x86::r8d, lanes_);
    a_.vzeroupper();
    a_.mov(x86::rax, reinterpret_cast<std::uint64_t>(&scalar_op));
    a_.call(x86::rax);
    // The call clobbers every vector register: the cache is empty and the constants come back.
    flush();
    load_constants();
    return true;
  }

  int vb_, lanes_;
  std::uint32_t num_regs_;
  int channels_, temps_, first_slot_;
  int slots_;  // (after first_slot_: initialized from it)
  std::vector<Slot> slot_;                  // the cache: machine registers first_slot_ and up
  std::vector<int> where_;                  // per key: its slot, or -1
  std::uint32_t pinned_ = 0;                // slots the instruction being written reads or writes
  std::uint32_t free_ = 0;                  // slots empty or holding a dead value
  bool out_of_registers_ = false;
  std::vector<std::uint32_t> def_next_, arg_next_;
  std::size_t k_ = 0;                       // the instruction being written
  std::unordered_map<std::uint32_t, Label> vector_pool_;
};


// The interval pass of IntervalBatchKernel (interval_batch.cpp, EvalBoxes) for one tape: each
// instruction's lower and upper bounds over 16 boxes, with the same f32 operations in the same
// order, and the same record (choice and fold bits, mins' argument bounds, folded values).
// Values go through the scratch array (each interval pass of a tape runs once per call: there is
// no loop to keep registers across). AVX2 code runs every row of 16 lanes as two halves of 8.

// Interval ops without a vector form, lane by lane: o (16 lower, then 16 upper bounds) = op(a, b)
// with the interpreter's scalar code. Returns the boxes choosing left (bits 0-15) and right
// (16-31). Each lane reads its arguments before writing, so o may be a or b.
std::uint32_t interval_lanes(float* o, const float* a, const float* b, int op) {
  const Op o_op = static_cast<Op>(op);
  const bool binary = op_arity(o_op) == 2;
  std::uint32_t l = 0, r = 0;
  for (int k = 0; k < 16; ++k) {
    Choice c;
    const Interval v = ival::op_generic(o_op, {a[k], a[16 + k]}, binary ? Interval{b[k], b[16 + k]} : Interval{}, &c);
    o[k] = v.lo;
    o[16 + k] = v.hi;
    if (c == Choice::Left) l |= 1u << k;
    if (c == Choice::Right) r |= 1u << k;
  }
  return l | r << 16;
}

class IntervalEmitter : CodeWriter {
 public:
  IntervalEmitter(x86::Assembler& a, bool avx512, std::uint32_t num_regs)
      : CodeWriter(a, avx512), vb_(avx512 ? 64 : 32), halves_(avx512 ? 1 : 2), num_regs_(num_regs) {}

  bool emit(const Tape& tape, const char** why) {
    // Prologue: the IntervalArgs pointer in rdi. Kept on the stack: it (at [rsp]) and fold_lanes
    // (at [rsp + 8]).
    prologue(24);
    a_.mov(x86::ptr(x86::rsp), x86::rdi);
    a_.mov(x86::eax, x86::dword_ptr(x86::rdi, offsetof(IntervalArgs, fold_lanes)));
    a_.mov(x86::dword_ptr(x86::rsp, 8), x86::eax);
    a_.mov(kRegs, x86::ptr(x86::rdi, offsetof(IntervalArgs, regs)));
    a_.mov(kLeft, x86::ptr(x86::rdi, offsetof(IntervalArgs, left)));
    a_.mov(kRight, x86::ptr(x86::rdi, offsetof(IntervalArgs, right)));
    a_.mov(kFold, x86::ptr(x86::rdi, offsetof(IntervalArgs, fold)));
    a_.mov(kMins, x86::ptr(x86::rdi, offsetof(IntervalArgs, mins)));
    a_.mov(kFolds, x86::ptr(x86::rdi, offsetof(IntervalArgs, folds)));
    load_constants();
    const auto code = tape.code();
    for (std::size_t i = 0; i < code.size(); ++i) {
      const RegInstr& ins = code[i];
      if (ins.op == Op::Oracle) {
        *why = "an oracle";
        return false;
      }
      if (!instruction(ins, static_cast<std::int32_t>(2 * i))) {
        *why = "an opcode the JIT does not know";
        return false;
      }
    }
    // Epilogue: where the record's appended arrays end.
    a_.mov(x86::rax, x86::ptr(x86::rsp));
    a_.mov(x86::ptr(x86::rax, offsetof(IntervalArgs, mins)), kMins);
    a_.mov(x86::ptr(x86::rax, offsetof(IntervalArgs, folds)), kFolds);
    epilogue(24);
    emit_pool();
    return true;
  }

 private:
  // General registers held through the whole pass (callee-saved).
  static constexpr x86::Gp kRegs = x86::rbx, kLeft = x86::rbp, kRight = x86::r12, kFold = x86::r13,
                           kMins = x86::r14, kFolds = x86::r15;
  // Vector registers: v0-v3 arguments (a lo, a hi, b lo, b hi), v4-v7 results and temporaries,
  // masks in k1-k3 (AVX-512) or v8-v10 (AVX2), constants in v11-v15.
  x86::Vec v(int i) const { return reg(i); }
  x86::Vec sign() const { return v(11); }
  x86::Vec nan() const { return v(12); }
  x86::Vec ninf() const { return v(13); }
  x86::Vec pinf() const { return v(14); }
  x86::Vec zero() const { return v(15); }

  void load_constants() {
    broadcast(sign(), -0.0f);
    broadcast(nan(), std::numeric_limits<float>::quiet_NaN());
    broadcast(ninf(), -std::numeric_limits<float>::infinity());
    broadcast(pinf(), std::numeric_limits<float>::infinity());
    vxor(zero(), zero(), zero());
  }

  // Masks: m in 0..2 is k1-k3 or v8-v10.
  void cmp(int m, const x86::Vec& p, const x86::Vec& q, int predicate) {
    if (avx512_) {
      a_.vcmpps(x86::k(static_cast<std::uint32_t>(m + 1)), p, q, predicate);
    } else {
      a_.vcmpps(v(8 + m), p, q, predicate);
    }
  }
  void mask_or(int d, int m) {
    if (avx512_) {
      a_.korw(x86::k(static_cast<std::uint32_t>(d + 1)), x86::k(static_cast<std::uint32_t>(d + 1)),
              x86::k(static_cast<std::uint32_t>(m + 1)));
    } else {
      a_.vorps(v(8 + d), v(8 + d), v(8 + m));
    }
  }
  void mask_and(int d, int m) {
    if (avx512_) {
      a_.kandw(x86::k(static_cast<std::uint32_t>(d + 1)), x86::k(static_cast<std::uint32_t>(d + 1)),
               x86::k(static_cast<std::uint32_t>(m + 1)));
    } else {
      a_.vandps(v(8 + d), v(8 + d), v(8 + m));
    }
  }
  // d = m ? s : d, lane by lane.
  void blend(const x86::Vec& d, int m, const x86::Vec& s) {
    if (avx512_) {
      a_.k(x86::k(static_cast<std::uint32_t>(m + 1))).vmovaps(d, s);
    } else {
      a_.vblendvps(d, d, s, v(8 + m));
    }
  }
  // Mask m's lanes of half h into bits of `acc` (set by half 0, or-ed in by half 1).
  void bits(const x86::Gp& acc, int m, int h) {
    if (avx512_) {
      a_.kmovw(acc, x86::k(static_cast<std::uint32_t>(m + 1)));
    } else if (h == 0) {
      a_.vmovmskps(acc, v(8 + m));
    } else {
      a_.vmovmskps(x86::eax, v(8 + m));
      a_.shl(x86::eax, 8);
      a_.or_(acc, x86::eax);
    }
  }

  // Register r's bounds in half h.
  x86::Mem lo(std::uint32_t r, int h) const {
    return x86::ptr(kRegs, static_cast<std::int32_t>(static_cast<std::int64_t>(r) * 128 + h * vb_));
  }
  x86::Mem hi(std::uint32_t r, int h) const {
    return x86::ptr(kRegs, static_cast<std::int32_t>(static_cast<std::int64_t>(r) * 128 + 64 + h * vb_));
  }
  // The arguments' bounds of half h into v0, v1 (a) and v2, v3 (b); an immediate is both bounds.
  void load_args(const RegInstr& ins, int h) {
    if (ins.mode & RegInstr::kImmA) {
      broadcast(v(0), ins.imm);
      a_.vmovaps(v(1), v(0));
    } else {
      a_.vmovaps(v(0), lo(ins.a, h));
      a_.vmovaps(v(1), hi(ins.a, h));
    }
    if (op_arity(ins.op) < 2) return;
    if (ins.mode & RegInstr::kImmB) {
      broadcast(v(2), ins.imm);
      a_.vmovaps(v(3), v(2));
    } else {
      a_.vmovaps(v(2), lo(ins.b, h));
      a_.vmovaps(v(3), hi(ins.b, h));
    }
  }
  // Stores half h of the result, NaN where mask `unknown` (or -1: nowhere) is set.
  // For ops with arguments, also collects half h's fold bits (fold_bits).
  void store(const RegInstr& ins, int h, const x86::Vec& l, const x86::Vec& u, int unknown) {
    if (unknown >= 0) {
      blend(l, unknown, nan());
      blend(u, unknown, nan());
    }
    a_.vmovaps(lo(ins.out, h), l);
    a_.vmovaps(hi(ins.out, h), u);
    if (op_arity(ins.op) > 0) fold_bits(ins, h, l, u);
  }
  // Half h's lanes whose result [l, u] is a single value into the fold bits (r10d): a zero only
  // where the op yields an exact +0.
  void fold_bits(const RegInstr& ins, int h, const x86::Vec& l, const x86::Vec& u) {
    cmp(0, l, u, kEqOQ);
    if (ins.op != Op::Compare && ins.op != Op::Not) {
      cmp(1, l, zero(), kNeqUQ);
      mask_and(0, 1);
    }
    bits(x86::r10d, 0, h);
  }
  // Mask m |= either bound of v(p), v(p + 1) is NaN (mask m + 1 is scratch).
  void or_unordered(int m, int p) {
    cmp(m + 1, v(p), v(p + 1), kUnordQ);
    mask_or(m, m + 1);
  }

  bool instruction(const RegInstr& ins, std::int32_t at) {
    const int ar = op_arity(ins.op);
    // Choice bits (only choices store them: the record's other entries are not read) and fold
    // bits.
    const x86::Gp lbits = x86::r8d, rbits = x86::r9d, fbits = x86::r10d;
    if (ar == 0) {
      const int axis = static_cast<int>(ins.op) - static_cast<int>(Op::VarX);
      if (ins.op != Op::Const) {
        a_.mov(x86::rax, x86::ptr(x86::rsp));
        a_.mov(x86::rax, x86::ptr(x86::rax, offsetof(IntervalArgs, box)));
      }
      for (int h = 0; h < halves_; ++h) {
        if (ins.op == Op::Const) {
          broadcast(v(4), ins.imm);
          a_.vmovaps(v(5), v(4));
        } else {
          a_.vmovups(v(4), x86::ptr(x86::rax, 2 * axis * 64 + h * vb_));
          a_.vmovups(v(5), x86::ptr(x86::rax, (2 * axis + 1) * 64 + h * vb_));
        }
        store(ins, h, v(4), v(5), -1);
      }
      a_.mov(x86::word_ptr(kFold, at), 0);
      return true;
    }
    switch (ins.op) {
      case Op::Add:
      case Op::Sub:
        for (int h = 0; h < halves_; ++h) {
          load_args(ins, h);
          // -inf + inf (inf - inf) inside the boxes gives NaN although the bounds do not show it.
          if (ins.op == Op::Add) {
            a_.vaddps(v(4), v(0), v(2));
            a_.vaddps(v(5), v(1), v(3));
            cmp(0, v(0), ninf(), kEqOQ);
            cmp(1, v(3), pinf(), kEqOQ);
            mask_and(0, 1);
            cmp(1, v(1), pinf(), kEqOQ);
            cmp(2, v(2), ninf(), kEqOQ);
          } else {
            a_.vsubps(v(4), v(0), v(3));
            a_.vsubps(v(5), v(1), v(2));
            cmp(0, v(1), pinf(), kEqOQ);
            cmp(1, v(3), pinf(), kEqOQ);
            mask_and(0, 1);
            cmp(1, v(0), ninf(), kEqOQ);
            cmp(2, v(2), ninf(), kEqOQ);
          }
          mask_and(1, 2);
          mask_or(0, 1);
          or_unordered(0, 4);
          store(ins, h, v(4), v(5), 0);
        }
        break;
      case Op::Neg:
        for (int h = 0; h < halves_; ++h) {
          load_args(ins, h);
          vxor(v(4), v(1), sign());
          vxor(v(5), v(0), sign());
          store(ins, h, v(4), v(5), -1);
        }
        break;
      case Op::Mul:
        for (int h = 0; h < halves_; ++h) {
          load_args(ins, h);
          a_.vmulps(v(4), v(0), v(2));
          a_.vmulps(v(5), v(0), v(3));
          a_.vmulps(v(6), v(1), v(2));
          a_.vmulps(v(7), v(1), v(3));
          // Unknown: a NaN product, or 0 * inf inside the boxes (which the corners may not show):
          // (a has 0 and b an infinite bound) or (b has 0 and a an infinite bound).
          cmp(0, v(4), v(5), kUnordQ);
          cmp(1, v(6), v(7), kUnordQ);
          mask_or(0, 1);
          for (int side = 0; side < 2; ++side) {
            const int z = side == 0 ? 0 : 2, f = side == 0 ? 2 : 0;  // bounds holding 0; infinite
            cmp(1, v(z), zero(), kLeOQ);
            cmp(2, v(z + 1), zero(), kGeOQ);
            mask_and(1, 2);
            cmp(2, v(f), ninf(), kEqOQ);
            mask_and(2, 1);
            mask_or(0, 2);
            cmp(2, v(f + 1), pinf(), kEqOQ);
            mask_and(2, 1);
            mask_or(0, 2);
          }
          a_.vminps(v(0), v(4), v(5));
          a_.vminps(v(1), v(6), v(7));
          a_.vminps(v(0), v(0), v(1));
          a_.vmaxps(v(2), v(4), v(5));
          a_.vmaxps(v(3), v(6), v(7));
          a_.vmaxps(v(2), v(2), v(3));
          store(ins, h, v(0), v(2), 0);
        }
        break;
      case Op::Square:
      case Op::Abs:
        for (int h = 0; h < halves_; ++h) {
          load_args(ins, h);
          cmp(0, v(0), zero(), kGeOQ);  // positive
          cmp(1, v(1), zero(), kLeOQ);  // negative
          // Square: candidates a lo^2, a hi^2; abs: -a hi, -a lo. The lower bound is the first
          // where positive, else the second where negative, else 0; the upper bound the second
          // where positive, else the first where negative, else the larger.
          const x86::Vec first = v(6), second = v(7);
          if (ins.op == Op::Square) {
            a_.vmulps(first, v(0), v(0));
            a_.vmulps(second, v(1), v(1));
            a_.vmovaps(v(4), zero());
            blend(v(4), 1, second);
            blend(v(4), 0, first);
            a_.vmaxps(v(5), first, second);
            blend(v(5), 1, first);
            blend(v(5), 0, second);
          } else {
            vxor(first, v(1), sign());   // -a hi
            vxor(second, v(0), sign());  // -a lo
            a_.vmovaps(v(4), zero());
            blend(v(4), 1, first);
            blend(v(4), 0, v(0));
            a_.vmaxps(v(5), second, v(1));
            blend(v(5), 1, second);
            blend(v(5), 0, v(1));
          }
          cmp(0, v(0), v(1), kUnordQ);
          store(ins, h, v(4), v(5), 0);
        }
        break;
      case Op::Sqrt:
        for (int h = 0; h < halves_; ++h) {
          load_args(ins, h);
          a_.vsqrtps(v(4), v(0));
          a_.vsqrtps(v(5), v(1));
          cmp(0, v(0), zero(), kNgeUQ);
          store(ins, h, v(4), v(5), 0);
        }
        break;
      case Op::Min:
      case Op::Max: {
        const bool is_min = ins.op == Op::Min;
        // Comparisons with NaN are false: unknown lanes make no choice.
        for (int h = 0; h < halves_; ++h) {
          load_args(ins, h);
          if (is_min) {
            cmp(0, v(1), v(2), kLtOQ);  // a hi < b lo
            cmp(1, v(3), v(0), kLtOQ);  // b hi < a lo
          } else {
            cmp(0, v(0), v(3), kGtOQ);  // a lo > b hi
            cmp(1, v(2), v(1), kGtOQ);  // b lo > a hi
          }
          bits(lbits, 0, h);
          bits(rbits, 1, h);
        }
        if (is_min) {
          // The arguments' bounds, for caps, where a box to simplify keeps both sides
          // (caps::min_bounds_recorded), before the result may overwrite an argument.
          const Label skip = a_.newLabel();
          a_.mov(x86::eax, lbits);
          a_.or_(x86::eax, rbits);
          a_.not_(x86::eax);
          a_.and_(x86::eax, x86::dword_ptr(x86::rsp, 8));
          a_.jz(skip);
          for (int h = 0; h < halves_; ++h) {
            if (halves_ > 1) load_args(ins, h);  // one half: still in v0-v3
            for (int row = 0; row < 4; ++row) a_.vmovups(x86::ptr(kMins, row * 64 + h * vb_), v(row));
          }
          a_.add(kMins, 4 * 64);
          a_.bind(skip);
        }
        for (int h = 0; h < halves_; ++h) {
          if (halves_ > 1) load_args(ins, h);
          cmp(0, v(0), v(1), kUnordQ);
          or_unordered(0, 2);
          if (is_min) {
            a_.vminps(v(4), v(0), v(2));
            a_.vminps(v(5), v(1), v(3));
          } else {
            a_.vmaxps(v(4), v(0), v(2));
            a_.vmaxps(v(5), v(1), v(3));
          }
          store(ins, h, v(4), v(5), 0);
        }
        break;
      }
      default:
        if (!call_out(ins, ar)) return false;
        for (int h = 0; h < halves_; ++h) {
          a_.vmovaps(v(4), lo(ins.out, h));
          a_.vmovaps(v(5), hi(ins.out, h));
          fold_bits(ins, h, v(4), v(5));
        }
    }
    if (op_is_choice(ins.op)) {
      a_.mov(x86::word_ptr(kLeft, at), lbits.r16());
      a_.mov(x86::word_ptr(kRight, at), rbits.r16());
    }
    a_.and_(fbits, x86::dword_ptr(x86::rsp, 8));
    a_.mov(x86::word_ptr(kFold, at), fbits.r16());
    const Label skip = a_.newLabel();
    a_.jz(skip);
    for (int h = 0; h < halves_; ++h) {
      a_.vmovaps(v(4), lo(ins.out, h));
      a_.vmovups(x86::ptr(kFolds, h * vb_), v(4));
    }
    a_.add(kFolds, 64);
    a_.bind(skip);
    return true;
  }

  // interval_lanes through memory (an immediate argument goes to a spare register's place);
  // the call clobbers every vector register and r8-r11.
  bool call_out(const RegInstr& ins, int ar) {
    if (ar < 1 || ar > 2) return false;
    const std::uint32_t spare_a = num_regs_, spare_b = num_regs_ + 1;
    const auto operand = [&](bool imm, std::uint32_t reg, std::uint32_t spare, const x86::Gp& dst) {
      if (imm) {
        broadcast(v(0), ins.imm);
        for (int h = 0; h < halves_; ++h) {
          a_.vmovaps(lo(spare, h), v(0));
          a_.vmovaps(hi(spare, h), v(0));
        }
        reg = spare;
      }
      a_.lea(dst, lo(reg, 0));
    };
    operand(ins.mode & RegInstr::kImmA, ins.a, spare_a, x86::rsi);
    if (ar == 2) {
      operand(ins.mode & RegInstr::kImmB, ins.b, spare_b, x86::rdx);
    } else {
      a_.mov(x86::rdx, x86::rsi);  // unused by unary ops, but a valid pointer
    }
    a_.lea(x86::rdi, lo(ins.out, 0));
    a_.mov(x86::ecx, static_cast<int>(ins.op));
    a_.vzeroupper();
    a_.mov(x86::rax, reinterpret_cast<std::uint64_t>(&interval_lanes));
    a_.call(x86::rax);
    a_.mov(x86::r8d, x86::eax);
    a_.and_(x86::r8d, 0xFFFF);
    a_.mov(x86::r9d, x86::eax);
    a_.shr(x86::r9d, 16);
    load_constants();
    return true;
  }

  int vb_, halves_;
  std::uint32_t num_regs_;
};

}  // namespace

struct CodeCache::Runtime {
  JitRuntime rt;
};

CodeCache::CodeCache(bool avx512) : avx512_(avx512) {}
CodeCache::~CodeCache() = default;

namespace {

// Runs write(assembler) and adds the code to the runtime; null with the reason in `why` if
// write refuses or the assembler or the runtime fails.
template <class Fn, class Write>
Fn assemble(JitRuntime& rt, Write&& write, const char** why) {
  CodeHolder code;
  code.init(rt.environment());
  ErrorCatcher errors;
  code.setErrorHandler(&errors);
  x86::Assembler a(&code);
  if (!write(a)) return nullptr;
  if (errors.failed) {
    *why = errors.why ? errors.why : "assembler error";
    return nullptr;
  }
  Fn fn = nullptr;
  if (rt.add(&fn, &code) != kErrorOk) {
    *why = "no executable memory";
    return nullptr;
  }
  return fn;
}

}  // namespace

CompiledFn CodeCache::compile(const Tape& tape, int channels, const char** why) {
  if (!rt_) rt_ = std::make_unique<Runtime>();  // evaluators that never compile never map code memory
  return assemble<CompiledFn>(rt_->rt, [&](x86::Assembler& a) {
    Emitter e(a, avx512_, tape.num_registers(), channels);
    return e.emit(tape, why);
  }, why);
}

IntervalFn CodeCache::compile_intervals(const Tape& tape, const char** why) {
  if (!rt_) rt_ = std::make_unique<Runtime>();
  return assemble<IntervalFn>(rt_->rt, [&](x86::Assembler& a) {
    IntervalEmitter e(a, avx512_, tape.num_registers());
    return e.emit(tape, why);
  }, why);
}

void CodeCache::release(void* fn) {
  if (fn && rt_) rt_->rt.release(fn);
}

std::size_t value_calls(const Tape& tape) {
  std::size_t n = 0;
  for (const RegInstr& r : tape.code()) n += op_arity(r.op) > 0 && !native(r.op);
  return n;
}

bool cpu_has_avx2() {
  const auto& f = CpuInfo::host().features().x86();
  return f.hasAVX2();
}

bool cpu_has_avx512() {
  const auto& f = CpuInfo::host().features().x86();
  return f.hasAVX512_F();
}

}  // namespace frep::jit

#else  // a build without asmjit (or not on x86-64): the JIT backend always interprets

namespace frep::jit {

struct CodeCache::Runtime {};
CodeCache::CodeCache(bool avx512) : avx512_(avx512) {}
CodeCache::~CodeCache() = default;
CompiledFn CodeCache::compile(const Tape&, int, const char** why) {
  *why = "this build has no JIT";
  return nullptr;
}
IntervalFn CodeCache::compile_intervals(const Tape&, const char** why) {
  *why = "this build has no JIT";
  return nullptr;
}
void CodeCache::release(void*) {}
std::size_t value_calls(const Tape&) { return 0; }
bool cpu_has_avx2() { return false; }
bool cpu_has_avx512() { return false; }

}  // namespace frep::jit
#endif
