// IntervalBatchEvaluator: interval arithmetic on 16 boxes at once. Highway compiles this file
// once per instruction set and picks the best at run time. The common ops are SIMD across the
// boxes; the rest fall back to the scalar interval code box by box, so results always equal
// IntervalEvaluator's.
#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS (HWY_SSSE3 | HWY_AVX3_DL)
#endif
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "eval/interval_batch.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <bit>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <optional>

#include "eval/simd_ops-inl.h"

#include "eval/caps.hpp"
#include "eval/interval_ops.hpp"
#include "frep/error.hpp"
#include "eval/tape_builder.hpp"
#include "eval/interp_kernels.hpp"
#include "frep/eval/interval_batch.hpp"
#include "frep/expr/oracle.hpp"

#ifndef FREP_EVAL_INTERVAL_BATCH_ONCE
#define FREP_EVAL_INTERVAL_BATCH_ONCE
namespace frep {
// What the backward pass of IntervalBatchEvaluator::simplify reads and writes.
struct SimplifyPass {
  const SsaInstr* in;          // the tape's SSA code
  std::size_t n, code_size;    // its SSA and register instructions
  std::uint32_t* marks;        // per SSA instruction: boxes needing it (bits 0-15, set for the
                               // root), and those of them where its cap is finite (bits 16-31)
  std::uint16_t* sides;        // per choice: boxes keeping only a, only b (both: a min above its cap)
  float* caps;                 // per choice and box: its cap (then, for a min above it, its constant)
  const std::uint16_t* left;   // the interval pass's record, per register instruction
  const std::uint16_t* right;
  const std::uint16_t* fold;
  const float* mins_end;       // just past the recorded mins' bounds
  std::uint32_t simplifiable;  // the boxes the pass recorded for
  std::size_t* kept;           // per box: live instructions counted, or null not to count
};
}  // namespace frep
#endif

HWY_BEFORE_NAMESPACE();
namespace frep {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<float>;
using V = hn::Vec<D>;
using M = hn::Mask<D>;
constexpr int L = IntervalBatchEvaluator::kLanes;

HWY_INLINE std::uint32_t Bits(D d, M m) {
  std::uint8_t buf[8] = {0};
  hn::StoreMaskBits(d, m, buf);
  std::uint32_t v;
  std::memcpy(&v, buf, sizeof v);
  return v;
}

// Runs f(lo_out, hi_out, j) for every group of lanes; f stores and returns choice bits.
template <class F>
HWY_INLINE void Lanes(F f) {
  const D d;
  for (int j = 0; j < L; j += static_cast<int>(hn::Lanes(d))) f(d, j);
}

// Evaluates register code over 16 boxes. Per instruction k: choice and fold bit masks; for each
// `min` where a box to simplify (a lane of `fold_lanes`) keeps both sides, its arguments' bounds
// (alo, ahi, blo, bhi, 16 lanes each) appended to `mins` for the caps of simplification
// (caps::min_bounds_recorded); for each instruction with folded lanes, its 16 lower bounds
// appended to `folds` (grown as needed). Registers hold [register][lane] bounds.
// Returns the number of mins stored.
std::size_t EvalBoxes(const RegInstr* code, std::size_t n, float* lo, float* hi, std::uint16_t* left,
                      std::uint16_t* right, std::uint16_t* fold, float* mins, LargeVector<float>& folds,
                      std::uint32_t fold_lanes, const float* box, int count, const OracleTable* oracles) {
  const float* const mins_begin = mins;
  const D d;
  const V nan = hn::Set(d, std::numeric_limits<float>::quiet_NaN());
  const V zero = hn::Zero(d);
  const V pinf = hn::Set(d, std::numeric_limits<float>::infinity()), ninf = hn::Neg(pinf);
  alignas(64) float imm[L];
  for (std::size_t i = 0; i < n; ++i) {
    const RegInstr& ins = code[i];
    float* HWY_RESTRICT olo = lo + static_cast<std::size_t>(ins.out) * L;
    float* HWY_RESTRICT ohi = hi + static_cast<std::size_t>(ins.out) * L;
    const float* alo = lo + static_cast<std::size_t>(ins.a) * L;
    const float* ahi = hi + static_cast<std::size_t>(ins.a) * L;
    const float* blo = lo + static_cast<std::size_t>(ins.b) * L;
    const float* bhi = hi + static_cast<std::size_t>(ins.b) * L;
    if (ins.mode) {
      for (int j = 0; j < L; ++j) imm[j] = ins.imm;
      if (ins.mode & RegInstr::kImmA) alo = ahi = imm;
      else blo = bhi = imm;
    }
    std::uint32_t lbits = 0, rbits = 0;
    auto store = [&](D dd, int j, V rl, V rh, M unknown) {
      hn::Store(hn::IfThenElse(unknown, nan, rl), dd, olo + j);
      hn::Store(hn::IfThenElse(unknown, nan, rh), dd, ohi + j);
    };
    switch (ins.op) {
      case Op::VarX:
      case Op::VarY:
      case Op::VarZ: {
        const int axis = static_cast<int>(ins.op) - static_cast<int>(Op::VarX);
        std::memcpy(olo, box + (2 * axis) * L, L * sizeof(float));
        std::memcpy(ohi, box + (2 * axis + 1) * L, L * sizeof(float));
        break;
      }
      case Op::Const:  // only as the whole code of a constant tape
        for (int j = 0; j < L; ++j) olo[j] = ohi[j] = ins.imm;
        break;
      case Op::Oracle: {
        Interval bx[L], by[L], bz[L], r[L];
        for (int k = 0; k < count; ++k) {
          bx[k] = {box[0 * L + k], box[1 * L + k]};
          by[k] = {box[2 * L + k], box[3 * L + k]};
          bz[k] = {box[4 * L + k], box[5 * L + k]};
        }
        (*oracles)[oracle_index(ins.imm)]->bounds(bx, by, bz, r, static_cast<std::size_t>(count));
        for (int k = 0; k < L; ++k) {  // unused lanes repeat box 0
          olo[k] = r[k < count ? k : 0].lo;
          ohi[k] = r[k < count ? k : 0].hi;
        }
        break;
      }
      case Op::Add:
        Lanes([&](D dd, int j) {
          const V al = hn::Load(dd, alo + j), ah = hn::Load(dd, ahi + j);
          const V bl = hn::Load(dd, blo + j), bh = hn::Load(dd, bhi + j);
          const V rl = hn::Add(al, bl), rh = hn::Add(ah, bh);
          // -inf + inf inside the boxes gives NaN although the bounds do not show it.
          const M bad = hn::Or(hn::And(al == ninf, bh == pinf), hn::And(ah == pinf, bl == ninf));
          store(dd, j, rl, rh, hn::Or(bad, hn::Or(hn::IsNaN(rl), hn::IsNaN(rh))));
        });
        break;
      case Op::Sub:
        Lanes([&](D dd, int j) {
          const V al = hn::Load(dd, alo + j), ah = hn::Load(dd, ahi + j);
          const V bl = hn::Load(dd, blo + j), bh = hn::Load(dd, bhi + j);
          const V rl = hn::Sub(al, bh), rh = hn::Sub(ah, bl);
          const M bad = hn::Or(hn::And(ah == pinf, bh == pinf), hn::And(al == ninf, bl == ninf));
          store(dd, j, rl, rh, hn::Or(bad, hn::Or(hn::IsNaN(rl), hn::IsNaN(rh))));
        });
        break;
      case Op::Neg:
        Lanes([&](D dd, int j) {
          const V al = hn::Load(dd, alo + j), ah = hn::Load(dd, ahi + j);
          hn::Store(hn::Neg(ah), dd, olo + j);
          hn::Store(hn::Neg(al), dd, ohi + j);
        });
        break;
      case Op::Mul:
        Lanes([&](D dd, int j) {
          const V al = hn::Load(dd, alo + j), ah = hn::Load(dd, ahi + j);
          const V bl = hn::Load(dd, blo + j), bh = hn::Load(dd, bhi + j);
          const V p0 = hn::Mul(al, bl), p1 = hn::Mul(al, bh), p2 = hn::Mul(ah, bl), p3 = hn::Mul(ah, bh);
          // 0 * inf inside the boxes gives NaN although the corner products may not show it.
          const M a_zero = hn::And(al <= zero, ah >= zero), b_zero = hn::And(bl <= zero, bh >= zero);
          const M a_inf = hn::Or(al == ninf, ah == pinf), b_inf = hn::Or(bl == ninf, bh == pinf);
          const M bad = hn::Or(hn::Or(hn::Or(hn::IsNaN(p0), hn::IsNaN(p1)), hn::Or(hn::IsNaN(p2), hn::IsNaN(p3))),
                               hn::Or(hn::And(a_zero, b_inf), hn::And(b_zero, a_inf)));
          store(dd, j, hn::Min(hn::Min(p0, p1), hn::Min(p2, p3)), hn::Max(hn::Max(p0, p1), hn::Max(p2, p3)), bad);
        });
        break;
      case Op::Square:
        Lanes([&](D dd, int j) {
          const V al = hn::Load(dd, alo + j), ah = hn::Load(dd, ahi + j);
          const V l2 = hn::Mul(al, al), h2 = hn::Mul(ah, ah);
          const M pos = al >= zero, neg = ah <= zero;
          const V rl = hn::IfThenElse(pos, l2, hn::IfThenElse(neg, h2, zero));
          const V rh = hn::IfThenElse(pos, h2, hn::IfThenElse(neg, l2, hn::Max(l2, h2)));
          store(dd, j, rl, rh, hn::Or(hn::IsNaN(al), hn::IsNaN(ah)));
        });
        break;
      case Op::Sqrt:
        Lanes([&](D dd, int j) {
          const V al = hn::Load(dd, alo + j), ah = hn::Load(dd, ahi + j);
          store(dd, j, hn::Sqrt(al), hn::Sqrt(ah), hn::Not(al >= zero));
        });
        break;
      case Op::Abs:
        Lanes([&](D dd, int j) {
          const V al = hn::Load(dd, alo + j), ah = hn::Load(dd, ahi + j);
          const M pos = al >= zero, neg = ah <= zero;
          const V rl = hn::IfThenElse(pos, al, hn::IfThenElse(neg, hn::Neg(ah), zero));
          const V rh = hn::IfThenElse(pos, ah, hn::IfThenElse(neg, hn::Neg(al), hn::Max(hn::Neg(al), ah)));
          store(dd, j, rl, rh, hn::Or(hn::IsNaN(al), hn::IsNaN(ah)));
        });
        break;
      case Op::Min:
      case Op::Max: {
        const bool is_min = ins.op == Op::Min;
        if (is_min) {
          // Comparisons with NaN are false, so unknown lanes make no choice.
          Lanes([&](D dd, int j) {
            const V al = hn::Load(dd, alo + j), ah = hn::Load(dd, ahi + j);
            const V bl = hn::Load(dd, blo + j), bh = hn::Load(dd, bhi + j);
            lbits |= Bits(dd, ah < bl) << j;
            rbits |= Bits(dd, bh < al) << j;
          });
          // The arguments' bounds, for caps, where a box to simplify keeps both sides (before
          // the result may overwrite an argument).
          if (caps::min_bounds_recorded(lbits, rbits, fold_lanes)) {
            Lanes([&](D dd, int j) {
              hn::Store(hn::Load(dd, alo + j), dd, mins + 0 * L + j);
              hn::Store(hn::Load(dd, ahi + j), dd, mins + 1 * L + j);
              hn::Store(hn::Load(dd, blo + j), dd, mins + 2 * L + j);
              hn::Store(hn::Load(dd, bhi + j), dd, mins + 3 * L + j);
            });
            mins += 4 * L;
          }
        }
        Lanes([&](D dd, int j) {
          const V al = hn::Load(dd, alo + j), ah = hn::Load(dd, ahi + j);
          const V bl = hn::Load(dd, blo + j), bh = hn::Load(dd, bhi + j);
          const M unknown = hn::Or(hn::Or(hn::IsNaN(al), hn::IsNaN(ah)), hn::Or(hn::IsNaN(bl), hn::IsNaN(bh)));
          if (is_min) {
            store(dd, j, hn::Min(al, bl), hn::Min(ah, bh), unknown);
          } else {
            lbits |= Bits(dd, al > bh) << j;
            rbits |= Bits(dd, bl > ah) << j;
            store(dd, j, hn::Max(al, bl), hn::Max(ah, bh), unknown);
          }
        });
        break;
      }
      default: {
        const bool binary = op_arity(ins.op) == 2;
        for (int k = 0; k < L; ++k) {
          Choice c;
          const Interval r = ival::op_generic(ins.op, {alo[k], ahi[k]}, binary ? Interval{blo[k], bhi[k]} : Interval{}, &c);
          olo[k] = r.lo;
          ohi[k] = r.hi;
          if (c == Choice::Left) lbits |= 1u << k;
          if (c == Choice::Right) rbits |= 1u << k;
        }
      }
    }
    left[i] = static_cast<std::uint16_t>(lbits);
    right[i] = static_cast<std::uint16_t>(rbits);
    std::uint32_t fbits = 0;
    if (op_arity(ins.op) > 0) {
      // Single-valued lanes fold to a constant (a zero only where the op yields an exact +0).
      const bool zero_ok = ins.op == Op::Compare || ins.op == Op::Not;
      Lanes([&](D dd, int j) {
        const V l = hn::Load(dd, olo + j), h = hn::Load(dd, ohi + j);
        const M single = l == h;
        fbits |= Bits(dd, zero_ok ? single : hn::And(single, NotZero(l))) << j;
      });
      fbits &= fold_lanes;
      if (fbits) folds.insert(folds.end(), olo, olo + L);
    }
    fold[i] = static_cast<std::uint16_t>(fbits);
  }
  return static_cast<std::size_t>(mins - mins_begin) / (4 * L);
}

// The lanes j.. of a vector of d as a mask: those whose bit is set in `bits`.
template <class DD>
HWY_INLINE auto LaneMask(DD d, std::uint32_t bits, int j) {
  const hn::RebindToUnsigned<DD> du;
  const auto lane_bits = hn::Shl(hn::Set(du, 1u), hn::Iota(du, static_cast<std::uint32_t>(j)));
  return hn::RebindMask(d, hn::TestBit(hn::Set(du, bits), lane_bits));
}

// The backward pass of IntervalBatchEvaluator::simplify (see there for what it computes), SIMD
// across the boxes where caps are computed or kept.
void SimplifyBackward(const SimplifyPass& p) {
  constexpr int K = L;
  const D d;
  const SsaInstr* in = p.in;
  std::uint32_t* marks = p.marks;
  float* caps = p.caps;
  const V inf = hn::Set(d, caps::kNone);
  const auto use_uncapped = [&](std::uint32_t j, std::uint32_t bits) {
    marks[j] = (marks[j] | bits) & ~(bits << 16);
  };
  // Marks j live for the boxes of `bits` with caps c[k]: kept (the largest of its caps) only
  // where j is a min or max, the only instructions that read their cap.
  const auto use = [&](std::uint32_t j, std::uint32_t bits, const float* c) {
    if (!bits) return;
    const Op op = in[j].op;
    if (op != Op::Min && op != Op::Max) return use_uncapped(j, bits);
    std::uint32_t finite = 0;
    Lanes([&](D dd, int k) { finite |= Bits(dd, hn::Lt(hn::Load(dd, c + k), inf)) << k; });
    finite &= bits;
    const std::uint32_t lv = marks[j] & 0xFFFF, fn = marks[j] >> 16;
    const std::uint32_t fresh = finite & ~lv, raise = finite & lv & fn;
    if (fresh | raise) {
      float* slot = caps + choice_ordinal(in[j]) * K;
      Lanes([&](D dd, int k) {
        const V s = hn::Load(dd, slot + k), cv = hn::Load(dd, c + k);
        hn::Store(hn::IfThenElse(LaneMask(dd, fresh, k), cv, hn::IfThenElse(LaneMask(dd, raise, k), hn::Max(s, cv), s)),
                  dd, slot + k);
      });
    }
    marks[j] = (lv | bits) | ((fn & ~(bits & ~finite)) | fresh) << 16;
  };
  // Passes min or max i's own caps on to j for the boxes in `bits`.
  const auto pass = [&](std::size_t i, std::uint32_t j, std::uint32_t bits) {
    const std::uint32_t fi = marks[i] >> 16;
    use_uncapped(j, bits & ~fi);
    use(j, bits & fi, caps + choice_ordinal(in[i]) * K);
  };
  alignas(64) float cap_a[K], cap_b[K];
  std::size_t kc = p.code_size;
  const float* mins = p.mins_end;
  for (std::size_t i = p.n; i-- > 0;) {
    const SsaInstr& ins = in[i];
    const std::uint32_t m = marks[i] & 0xFFFF;
    if (p.kept)
      for (std::uint32_t bits = m; bits; bits &= bits - 1) ++p.kept[__builtin_ctz(bits)];
    if (ins.op == Op::Const) continue;
    --kc;
    if (ins.op == Op::Min && caps::min_bounds_recorded(p.left[kc], p.right[kc], p.simplifiable)) mins -= 4 * K;
    if (!m) continue;
    const int ar = op_arity(ins.op);
    if (ar == 0) continue;
    const std::uint32_t rest = m & ~static_cast<std::uint32_t>(p.fold[kc]);
    if (ins.op == Op::Min || ins.op == Op::Max) {
      const std::size_t o = choice_ordinal(ins);
      std::uint32_t l = rest & p.left[kc], r = rest & p.right[kc], both = rest & ~(l | r);
      std::uint32_t above = 0;  // boxes where it becomes a constant: in both sides' bits
      if (ins.op == Op::Min) {
        if (both) {
          // caps::min_caps on every lane: which side alone is enough, else the sides' caps.
          float* ci = caps + o * K;
          const std::uint32_t fi = marks[i] >> 16;
          std::uint32_t lb = 0, rb = 0, ab = 0;
          Lanes([&](D dd, int k) {
            const V c = hn::IfThenElse(LaneMask(dd, fi, k), hn::Load(dd, ci + k), inf);
            const V alo = hn::Load(dd, mins + k), ahi = hn::Load(dd, mins + K + k);
            const V blo = hn::Load(dd, mins + 2 * K + k), bhi = hn::Load(dd, mins + 3 * K + k);
            // caps::upper: an unknown (NaN) interval caps nothing.
            const auto known_a = hn::Le(alo, ahi), known_b = hn::Le(blo, bhi);
            const V ua = hn::IfThenElse(known_a, ahi, inf), ub = hn::IfThenElse(known_b, bhi, inf);
            // Caps are only compared, so Min's choice between +0 and -0 does not matter.
            const V ca = hn::Min(c, ub), cb = hn::Min(c, ua);
            const auto above = hn::And(hn::And(known_a, known_b), hn::And(hn::Gt(alo, c), hn::Gt(blo, c)));
            const auto left = hn::AndNot(above, hn::Gt(blo, cb));
            ab |= Bits(dd, above) << k;
            lb |= Bits(dd, left) << k;
            rb |= Bits(dd, hn::AndNot(above, hn::AndNot(left, hn::Gt(alo, ca)))) << k;
            hn::Store(ca, dd, cap_a + k);
            hn::Store(cb, dd, cap_b + k);
          });
          l |= both & lb;
          r |= both & rb;
          above = both & ab;
          both &= ~(l | r | above);
          use(ins.a, both, cap_a);
          use(ins.b, both, cap_b);
          // Above its cap (caps::MinCaps::above): the constant goes where its cap was, read no more.
          for (std::uint32_t bits = above; bits; bits &= bits - 1) {
            const int k = __builtin_ctz(bits);
            ci[k] = caps::above_value(mins[k], mins[2 * K + k]);
          }
        }
      } else {
        pass(i, ins.a, both);
        pass(i, ins.b, both);
      }
      pass(i, ins.a, l);
      pass(i, ins.b, r);
      p.sides[2 * o] = static_cast<std::uint16_t>(l | above);
      p.sides[2 * o + 1] = static_cast<std::uint16_t>(r | above);
    } else if (op_is_choice(ins.op)) {
      const std::size_t o = choice_ordinal(ins);
      const std::uint32_t l = rest & p.left[kc], r = rest & p.right[kc], both = rest & ~(l | r);
      use_uncapped(ins.a, l | both);
      use_uncapped(ins.b, r | both);
      p.sides[2 * o] = static_cast<std::uint16_t>(l);
      p.sides[2 * o + 1] = static_cast<std::uint16_t>(r);
    } else {
      use_uncapped(ins.a, rest);
      if (ar == 2) use_uncapped(ins.b, rest);
    }
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace frep
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace frep {
HWY_EXPORT(EvalBoxes);
HWY_EXPORT(SimplifyBackward);

// Tapes up to this size are simplified into outputs sized for the whole tape (16 boxes x 4096
// instructions x 36 bytes: 2.4 MB per level and worker at most) without counting what each box
// keeps.
constexpr std::size_t kCountKeptAbove = 4096;

namespace interp {
namespace {

class IntervalBatch final : public IntervalBatchKernel {
 public:
  void eval(const Tape& tape, const float* box, int count, std::uint32_t fold_lanes, IntervalRecord& rec) override {
    constexpr int kLanes = IntervalRecord::kLanes;
    const std::size_t regs = std::max<std::size_t>(tape.num_registers(), 1);
    grow_scratch(regs_, 2 * regs * kLanes);
    float* const lo = regs_.data();
    float* const hi = lo + regs * kLanes;
    const std::size_t n = tape.code().size();
    size_interval_record(tape, rec);
    rec.folds.clear();
    rec.mins_count = HWY_DYNAMIC_DISPATCH(EvalBoxes)(tape.code().data(), n, lo, hi, rec.left.data(), rec.right.data(),
                                                     rec.fold.data(), rec.mins.data(), rec.folds, fold_lanes, box, count,
                                                     tape.oracles().get());
    const std::size_t root = static_cast<std::size_t>(tape.root_register()) * kLanes;
    std::copy(lo + root, lo + root + kLanes, rec.result_lo);
    std::copy(hi + root, hi + root + kLanes, rec.result_hi);
  }

 private:
  LargeVector<float> regs_;  // [register][lane] lower bounds, then upper bounds
};

}  // namespace

std::unique_ptr<IntervalBatchKernel> make_interval_batch_kernel() { return std::make_unique<IntervalBatch>(); }

}  // namespace interp

IntervalBatchEvaluator::IntervalBatchEvaluator(const Backend& backend) : kernel_(backend.interval_batch()) {}
IntervalBatchEvaluator::~IntervalBatchEvaluator() = default;

void IntervalBatchEvaluator::eval(const Tape& tape, const Interval* x, const Interval* y, const Interval* z,
                                  int count, int simplified) {
  FREP_ASSERT(count >= 1 && count <= kLanes, "between 1 and 16 boxes");
  FREP_ASSERT(simplified >= 0 && simplified <= kLanes, "at most 16 boxes to simplify");
  FREP_ASSERT(tape.size() > 0, "empty tape");
  FREP_ASSERT(!tape.code().empty(), "interval batches run register code");
  code_size_ = tape.code().size();
  size_ = tape.size();
  simplified_ = simplified;
  // Box bounds as six rows of 16 lanes; unused lanes repeat box 0.
  alignas(64) float box[6 * kLanes];
  for (int k = 0; k < kLanes; ++k) {
    const int s = k < count ? k : 0;
    box[0 * kLanes + k] = x[s].lo;
    box[1 * kLanes + k] = x[s].hi;
    box[2 * kLanes + k] = y[s].lo;
    box[3 * kLanes + k] = y[s].hi;
    box[4 * kLanes + k] = z[s].lo;
    box[5 * kLanes + k] = z[s].hi;
  }
  kernel_->eval(tape, box, count, (1u << simplified) - 1, record_);
}

std::uint32_t IntervalBatchEvaluator::simplify(const Tape& tape, std::uint32_t lanes, Tape* outs, double max_kept,
                                              bool leaves, float root_cap) {
  const std::size_t n = size_;
  FREP_ASSERT(tape.size() == n && tape.code().size() == code_size_, "simplify needs the tape of the last eval");
  const std::uint32_t simplifiable = (1u << simplified_) - 1;
  lanes &= simplifiable;
  if (!lanes) return 0;
  const SsaInstr* in = tape.ssa().data();
  const std::size_t choices = tape.choice_count();
  // Backward pass for all boxes at once: marks_[i] has a bit for each box that needs SSA
  // instruction i, and one (16 bits up) for each of those where its cap (eval/caps.hpp) is
  // finite. Caps are only read at min and max, so they are kept per choice (the choice's ordinal,
  // from the tape), as are the sides a choice keeps. Register code has one instruction per SSA
  // instruction that is not a constant, in the same order: `kc` walks it alongside.
  grow_scratch(marks_, n);
  std::fill(marks_.begin(), marks_.begin() + static_cast<std::ptrdiff_t>(n), 0u);
  grow_scratch(sides_, 2 * choices);
  grow_scratch(caps_, choices * kLanes);
  marks_[n - 1] = lanes;
  // A finite root cap, as the single-box pass gives it: only a min or max reads its cap.
  FREP_ASSERT(!std::isnan(root_cap), "a root cap is a number");
  if (root_cap < caps::kNone && (in[n - 1].op == Op::Min || in[n - 1].op == Op::Max)) {
    marks_[n - 1] |= lanes << 16;
    std::fill_n(caps_.begin() + static_cast<std::ptrdiff_t>(choice_ordinal(in[n - 1]) * kLanes), kLanes, root_cap);
  }
  std::size_t kept[kLanes] = {};  // per box: live instructions, the most its tape can keep
  // Counted only where it matters: to leave out boxes keeping most of the tape, or to size the
  // outputs of big tapes; a small tape's outputs may as well be sized for all of it (counting
  // costs a loop over the boxes of every instruction).
  const bool count_kept = max_kept < 1.0 || n > kCountKeptAbove;
  if (!count_kept) std::fill(kept, kept + kLanes, n);
  const SimplifyPass pass{in, n, code_size_, marks_.data(), sides_.data(), caps_.data(),
                          record_.left.data(), record_.right.data(), record_.fold.data(),
                          record_.mins.data() + record_.mins_count * 4 * kLanes, simplifiable,
                          count_kept ? kept : nullptr};
  HWY_DYNAMIC_DISPATCH(SimplifyBackward)(pass);
  for (std::uint32_t bits = lanes; bits; bits &= bits - 1) {
    const int k = __builtin_ctz(bits);
    if (static_cast<double>(kept[k]) > max_kept * static_cast<double>(n)) lanes &= ~(1u << k);
  }
  if (!lanes) return 0;
  // Forward pass: each box's builder sees only the instructions it needs; remaps are kept for
  // the boxes being built only, side by side ([instruction][box]).
  const int width = std::popcount(lanes);
  grow_scratch(remap_, n * static_cast<std::size_t>(width));
  std::optional<Tape::Builder> builders[kLanes];
  for (std::uint32_t bits = lanes, slot = 0; bits; bits &= bits - 1, ++slot) {
    const int k = __builtin_ctz(bits);
    builders[k].emplace(outs[k], n, true, kept[k], remap_.data() + slot, static_cast<std::size_t>(width));
    if (!leaves) builders[k]->trivial_registers_up_to(kMaxTrivialIntervalRegisters);
  }
  const float* folds = record_.folds.data();
  std::size_t kc = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const SsaInstr& ins = in[i];
    const std::uint32_t m = marks_[i] & lanes;
    if (ins.op == Op::Const) {
      for (std::uint32_t bits = m; bits; bits &= bits - 1) builders[__builtin_ctz(bits)]->keep(i, ins);
      continue;
    }
    const std::size_t k_code = kc++;
    const std::uint32_t fb = record_.fold[k_code];
    const float* fold_values = folds;
    if (fb) folds += kLanes;
    if (!m) continue;
    if (op_arity(ins.op) == 0) {
      for (std::uint32_t bits = m; bits; bits &= bits - 1) builders[__builtin_ctz(bits)]->keep(i, ins);
      continue;
    }
    const std::uint32_t f = m & fb;
    const std::uint32_t rest = m & ~f;
    const bool choice = op_is_choice(ins.op);
    const std::size_t o = choice ? choice_ordinal(ins) : 0;
    std::uint32_t l = choice ? rest & sides_[2 * o] : 0, r = choice ? rest & sides_[2 * o + 1] : 0;
    const std::uint32_t keep = rest & ~(l | r);
    // Both sides: a min above its cap, a constant kept in its cap slot.
    const std::uint32_t above = l & r;
    l &= ~above;
    r &= ~above;
    for (std::uint32_t bits = f; bits; bits &= bits - 1) {
      const int k = __builtin_ctz(bits);
      builders[k]->constant(i, fold_values[k]);
    }
    for (std::uint32_t bits = above; bits; bits &= bits - 1) {
      const int k = __builtin_ctz(bits);
      builders[k]->constant(i, caps_[o * kLanes + static_cast<std::size_t>(k)]);
    }
    for (std::uint32_t bits = l; bits; bits &= bits - 1) builders[__builtin_ctz(bits)]->alias(i, ins.a);
    for (std::uint32_t bits = r; bits; bits &= bits - 1) builders[__builtin_ctz(bits)]->alias(i, ins.b);
    for (std::uint32_t bits = keep; bits; bits &= bits - 1) builders[__builtin_ctz(bits)]->keep(i, ins);
  }
  for (std::uint32_t bits = lanes; bits; bits &= bits - 1) {
    const int k = __builtin_ctz(bits);
    builders[k]->finish(n - 1);
    outs[k].oracles_ = tape.oracles_;
  }
  return lanes;
}

}  // namespace frep
#endif  // HWY_ONCE
