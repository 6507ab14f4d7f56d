// Machine code for the batch evaluator's tapes, written with asmjit's assembler.
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
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "eval/grad_partials.hpp"
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
constexpr int kEqOQ = 0x00, kUnordQ = 0x03, kLtOQ = 0x11, kGeOQ = 0x1D, kGtOQ = 0x1E;
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

class Emitter {
 public:
  // channels: 1 for values, 4 for values and gradients (v, dx, dy, dz of a tape register are
  // four vectors, side by side in the scratch array).
  Emitter(x86::Assembler& a, bool avx512, std::uint32_t num_regs, int channels)
      : a_(a), avx512_(avx512), vb_(avx512 ? 64 : 32), lanes_(avx512 ? 16 : 8), num_regs_(num_regs),
        channels_(channels), temps_(channels == 1 ? 2 : 6), first_slot_(temps_ + 2),
        slots_((avx512 ? 32 : 16) - first_slot_) {
    slot_.resize(static_cast<std::size_t>(slots_));
    where_.assign(static_cast<std::size_t>(num_regs) * static_cast<std::size_t>(channels), -1);
  }

  bool emit(const Tape& tape, const char** why) {
    const x86::Gp regs = x86::rbx, xp = x86::r12, yp = x86::r13, zp = x86::r14, outp = x86::r15, count = x86::rbp;
    // Prologue: System V arguments x, y, z, out, regs, vectors in rdi, rsi, rdx, rcx, r8, r9.
    for (const x86::Gp& r : {x86::rbp, x86::rbx, x86::r12, x86::r13, x86::r14, x86::r15}) a_.push(r);
    a_.sub(x86::rsp, 8);  // 16-byte stack alignment for calls
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
    a_.vzeroupper();
    a_.add(x86::rsp, 8);
    for (const x86::Gp& r : {x86::r15, x86::r14, x86::r13, x86::r12, x86::rbx, x86::rbp}) a_.pop(r);
    a_.ret();
    // Constants: whole vectors, then single floats to broadcast.
    for (auto& [bits, label] : vector_pool_) {
      a_.align(AlignMode::kData, static_cast<std::uint32_t>(vb_));
      a_.bind(label);
      a_.embedUInt32(bits, static_cast<std::size_t>(lanes_));
    }
    a_.align(AlignMode::kData, 4);
    for (auto& [bits, label] : pool_) {
      a_.bind(label);
      a_.embedUInt32(bits);
    }
    return true;
  }

 private:
  static constexpr std::uint32_t kEmpty = UINT32_MAX;
  // Machine vector registers: temps_ temporaries (2 for values, 6 for gradients), then +1 and +0
  // for the whole loop (reloaded after calls), then the cache of tape registers.
  x86::Vec vec(int i) {
    // AVX2 has 16 registers (ymm16 and up need AVX-512, which an AVX2 machine would fault on).
    if (i >= (avx512_ ? 32 : 16)) out_of_registers_ = true;
    return avx512_ ? x86::Vec(x86::zmm(static_cast<std::uint32_t>(i))) : x86::Vec(x86::ymm(static_cast<std::uint32_t>(i)));
  }
  x86::Vec t0() { return vec(0); }
  x86::Vec t1() { return vec(1); }
  x86::Vec t(int i) { return vec(i); }
  x86::Vec one() { return vec(temps_); }
  x86::Vec zero() { return vec(temps_ + 1); }
  x86::Vec cached(int s) { return vec(first_slot_ + s); }
  std::uint32_t key(std::uint32_t reg, int c) const { return reg * static_cast<std::uint32_t>(channels_) + static_cast<std::uint32_t>(c); }

  Label constant(float v) {
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(v);
    auto it = pool_.find(bits);
    if (it == pool_.end()) it = pool_.emplace(bits, a_.newLabel()).first;
    return it->second;
  }
  // A whole vector of v, for operands that must be in memory.
  Label vector_constant(float v) {
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(v);
    auto it = vector_pool_.find(bits);
    if (it == vector_pool_.end()) it = vector_pool_.emplace(bits, a_.newLabel()).first;
    return it->second;
  }
  void broadcast(const x86::Vec& d, float v) { a_.vbroadcastss(d, x86::dword_ptr(constant(v))); }
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
  void vxor(const x86::Vec& d, const x86::Vec& p, const x86::Vec& q) { avx512_ ? a_.vpxord(d, p, q) : a_.vxorps(d, p, q); }
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

  // Whether the op has a vector form here; the others are calls.
  static bool native(Op op) {
    switch (op) {
      case Op::Neg: case Op::Abs: case Op::Recip: case Op::Sqrt: case Op::Square: case Op::Floor: case Op::Ceil:
      case Op::Round: case Op::Not: case Op::Add: case Op::Sub: case Op::Mul: case Op::Div: case Op::Min:
      case Op::Max: case Op::Compare: case Op::And: case Op::Or:
        return true;
      default: return false;
    }
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

  x86::Assembler& a_;
  bool avx512_;
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
  std::unordered_map<std::uint32_t, Label> pool_, vector_pool_;
};

}  // namespace

struct CodeCache::Runtime {
  JitRuntime rt;
};

CodeCache::CodeCache(bool avx512) : avx512_(avx512) {}
CodeCache::~CodeCache() = default;

CompiledFn CodeCache::compile(const Tape& tape, int channels, const char** why) {
  if (!rt_) rt_ = std::make_unique<Runtime>();  // evaluators that never compile never map code memory
  CodeHolder code;
  code.init(rt_->rt.environment());
  ErrorCatcher errors;
  code.setErrorHandler(&errors);
  x86::Assembler a(&code);
  Emitter e(a, avx512_, tape.num_registers(), channels);
  if (!e.emit(tape, why)) return nullptr;
  if (errors.failed) {
    *why = errors.why ? errors.why : "assembler error";
    return nullptr;
  }
  CompiledFn fn = nullptr;
  if (rt_->rt.add(&fn, &code) != kErrorOk) {
    *why = "no executable memory";
    return nullptr;
  }
  return fn;
}

void CodeCache::release(CompiledFn fn) {
  if (fn && rt_) rt_->rt.release(fn);
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
void CodeCache::release(CompiledFn) {}
bool cpu_has_avx2() { return false; }
bool cpu_has_avx512() { return false; }

}  // namespace frep::jit
#endif
