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

#include "frep/expr/semantics.hpp"

namespace frep::jit {
namespace {

using namespace asmjit;

// Ops the generated code calls out for, one vector at a time: o[i] = op(a[i], b[i]).
void scalar_op(float* o, const float* a, const float* b, int op, int lanes) {
  for (int i = 0; i < lanes; ++i) o[i] = op_eval<float>(static_cast<Op>(op), a[i], b[i]);
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
  Emitter(x86::Assembler& a, bool avx512, std::uint32_t num_regs)
      : a_(a), avx512_(avx512), vb_(avx512 ? 64 : 32), lanes_(avx512 ? 16 : 8), num_regs_(num_regs),
        slots_(avx512 ? 28 : 12) {
    slot_.resize(static_cast<std::size_t>(slots_));
    where_.assign(num_regs, -1);
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
      if (!instruction(tape.code()[k_], regs, xp, yp, zp)) {
        *why = "an opcode the JIT does not know";
        return false;
      }
    }
    a_.vmovups(x86::ptr(outp), get(tape.root_register(), kNever, regs, -1));
    a_.add(xp, vb_);
    a_.add(yp, vb_);
    a_.add(zp, vb_);
    a_.add(outp, vb_);
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
  // Machine vector registers: 0 and 1 are temporaries, 2 holds +1 and 3 holds +0 for the whole
  // loop (reloaded after calls), 4 and up cache tape registers.
  x86::Vec vec(int i) const { return avx512_ ? x86::Vec(x86::zmm(static_cast<std::uint32_t>(i))) : x86::Vec(x86::ymm(static_cast<std::uint32_t>(i))); }
  x86::Vec t0() const { return vec(0); }
  x86::Vec t1() const { return vec(1); }
  x86::Vec one() const { return vec(2); }
  x86::Vec zero() const { return vec(3); }

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
    std::uint32_t reg = kEmpty;   // tape register held
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
    std::fill(where_.begin(), where_.end(), -1);
  }

  x86::Mem slot_mem(std::uint32_t reg, const x86::Gp& regs) const {
    return x86::ptr(regs, static_cast<std::int32_t>(static_cast<std::int64_t>(reg) * vb_));
  }
  Slot& slot(int s) { return slot_[static_cast<std::size_t>(s)]; }
  // Writes slot s's value to the scratch array if it is still to be read and not there yet.
  void write_back(int s) {
    Slot& c = slot(s);
    if (c.reg != kEmpty && c.dirty && c.next != kNever) a_.vmovaps(slot_mem(c.reg, x86::rbx), vec(4 + s));
    c.dirty = false;
  }
  // Empties slot s (writing its value back if needed).
  void evict(int s) {
    Slot& c = slot(s);
    if (c.reg == kEmpty) return;
    write_back(s);
    where_[c.reg] = -1;
    c = Slot();
  }
  // The slot to take, other than `keep_a` and `keep_b`: an empty or dead one, else the one read
  // furthest ahead.
  int victim(int keep_a, int keep_b) {
    int best = -1;
    for (int s = 0; s < slots_; ++s) {
      if (s == keep_a || s == keep_b) continue;
      const Slot& c = slot(s);
      if (c.reg == kEmpty || c.next == kNever) return s;
      if (best < 0 || c.next > slot(best).next) best = s;
    }
    return best;
  }
  // Tape register `reg` in a machine register (loaded if needed), not taking slot `keep`; its
  // value is next read at `next`.
  x86::Vec get(std::uint32_t reg, std::uint32_t next, const x86::Gp& regs, int keep) {
    int s = where_[reg];
    if (s < 0) {
      s = victim(keep, -1);
      evict(s);
      a_.vmovaps(vec(4 + s), slot_mem(reg, regs));
      slot(s).reg = reg;
      where_[reg] = s;
    }
    slot(s).next = next;
    return vec(4 + s);
  }
  int slot_of(const x86::Vec& v) const { return static_cast<int>(v.id()) - 4; }

  // The destination of instruction k_ writing tape register `out`: a slot other than its
  // arguments' (so sequences of several operations may read them after writing it).
  x86::Vec dest(std::uint32_t out, int keep_a, int keep_b) {
    if (const int old = where_[out]; old >= 0) {
      // The register's previous value dies here (an argument's slot is kept intact until the
      // instruction is written: it is one of keep_a, keep_b).
      slot(old) = Slot();
      where_[out] = -1;
    }
    const int s = victim(keep_a, keep_b);
    evict(s);
    slot(s) = {out, def_next_[k_], true};
    where_[out] = s;
    return vec(4 + s);
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

  bool instruction(const RegInstr& ins, const x86::Gp& regs, const x86::Gp& xp, const x86::Gp& yp, const x86::Gp& zp) {
    const int ar = op_arity(ins.op);
    switch (ins.op) {
      case Op::VarX:
      case Op::VarY:
      case Op::VarZ: {
        const x86::Vec d = dest(ins.out, -1, -1);
        a_.vmovups(d, x86::ptr(ins.op == Op::VarX ? xp : ins.op == Op::VarY ? yp : zp));
        return true;
      }
      case Op::Const: {
        const x86::Vec d = dest(ins.out, -1, -1);
        broadcast(d, ins.imm);
        return true;
      }
      case Op::Oracle: return false;  // tapes with oracles are not compiled
      default: break;
    }
    if (!native(ins.op)) return call_out(ins, regs, ar);
    // Arguments: cached or loaded registers, immediates broadcast into t1.
    x86::Vec p, q;
    int keep_a = -1, keep_b = -1;
    if (ins.mode & RegInstr::kImmA) {
      p = t1();
      broadcast(p, ins.imm);
    } else {
      p = get(ins.a, arg_next_[2 * k_], regs, -1);
      keep_a = slot_of(p);
    }
    if (ar == 2) {
      if (ins.mode & RegInstr::kImmB) {
        q = t1();
        broadcast(q, ins.imm);
      } else {
        q = get(ins.b, arg_next_[2 * k_ + 1], regs, keep_a);
        keep_b = slot_of(q);
      }
    }
    const x86::Vec d = dest(ins.out, keep_a, keep_b);
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
    return x86::ptr(x86::rbx, static_cast<std::int32_t>((static_cast<std::int64_t>(num_regs_) + k) * vb_));
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
      if (const int s = r < num_regs_ ? where_[r] : -1; s >= 0 && slot(s).dirty) {
        a_.vmovaps(slot_mem(r, regs), vec(4 + s));
        slot(s).dirty = false;
      }
    for (int s = 0; s < slots_; ++s) write_back(s);
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
  int slots_;
  std::vector<Slot> slot_;                  // the cache: machine registers 4 and up
  std::vector<int> where_;                  // per tape register: its slot, or -1
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

BatchFn CodeCache::compile_batch(const Tape& tape, const char** why) {
  if (!rt_) rt_ = std::make_unique<Runtime>();  // evaluators that never compile never map code memory
  CodeHolder code;
  code.init(rt_->rt.environment());
  ErrorCatcher errors;
  code.setErrorHandler(&errors);
  x86::Assembler a(&code);
  Emitter e(a, avx512_, tape.num_registers());
  if (!e.emit(tape, why)) return nullptr;
  if (errors.failed) {
    *why = errors.why ? errors.why : "assembler error";
    return nullptr;
  }
  BatchFn fn = nullptr;
  if (rt_->rt.add(&fn, &code) != kErrorOk) {
    *why = "no executable memory";
    return nullptr;
  }
  return fn;
}

void CodeCache::release(BatchFn fn) {
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
BatchFn CodeCache::compile_batch(const Tape&, const char** why) {
  *why = "this build has no JIT";
  return nullptr;
}
void CodeCache::release(BatchFn) {}
bool cpu_has_avx2() { return false; }
bool cpu_has_avx512() { return false; }

}  // namespace frep::jit
#endif
