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
#include <cstdlib>
#include <cstring>
#include <optional>

#include "eval/simd_ops-inl.h"

#include "eval/caps.hpp"
#include "eval/interval_ops.hpp"
#include "frep/error.hpp"
#include "eval/tape_builder.hpp"
#include "frep/eval/interval_batch.hpp"

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

void EvalBoxes(const SsaInstr* code, std::size_t n, float* lo, float* hi, std::uint16_t* left,
               std::uint16_t* right, std::uint16_t* fold, const float* box) {
  const D d;
  const V nan = hn::Set(d, std::numeric_limits<float>::quiet_NaN());
  const V zero = hn::Zero(d);
  const V pinf = hn::Set(d, std::numeric_limits<float>::infinity()), ninf = hn::Neg(pinf);
  for (std::size_t i = 0; i < n; ++i) {
    const SsaInstr& ins = code[i];
    float* HWY_RESTRICT olo = lo + i * L;
    float* HWY_RESTRICT ohi = hi + i * L;
    const float* alo = lo + static_cast<std::size_t>(ins.a) * L;
    const float* ahi = hi + static_cast<std::size_t>(ins.a) * L;
    const float* blo = lo + static_cast<std::size_t>(ins.b) * L;
    const float* bhi = hi + static_cast<std::size_t>(ins.b) * L;
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
      case Op::Const:
        for (int j = 0; j < L; ++j) olo[j] = ohi[j] = ins.value;
        break;
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
          hn::Store(hn::Neg(hn::Load(dd, ahi + j)), dd, olo + j);
          hn::Store(hn::Neg(hn::Load(dd, alo + j)), dd, ohi + j);
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
        Lanes([&](D dd, int j) {
          const V al = hn::Load(dd, alo + j), ah = hn::Load(dd, ahi + j);
          const V bl = hn::Load(dd, blo + j), bh = hn::Load(dd, bhi + j);
          const M unknown = hn::Or(hn::Or(hn::IsNaN(al), hn::IsNaN(ah)), hn::Or(hn::IsNaN(bl), hn::IsNaN(bh)));
          // Comparisons with NaN are false, so unknown lanes make no choice.
          if (is_min) {
            lbits |= Bits(dd, ah < bl) << j;
            rbits |= Bits(dd, bh < al) << j;
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
    }
    fold[i] = static_cast<std::uint16_t>(fbits);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace frep
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace frep {
HWY_EXPORT(EvalBoxes);

IntervalBatchEvaluator::IntervalBatchEvaluator() = default;
IntervalBatchEvaluator::~IntervalBatchEvaluator() {
  std::free(lo_);
  std::free(hi_);
  std::free(scratch_);
}

void IntervalBatchEvaluator::eval(const Tape& tape, const Interval* x, const Interval* y, const Interval* z,
                                  int count) {
  FREP_ASSERT(count >= 1 && count <= kLanes, "between 1 and 16 boxes");
  const std::size_t n = tape.size();
  FREP_ASSERT(n > 0, "empty tape");
  if (n > capacity_) {
    std::free(lo_);
    std::free(hi_);
    std::free(scratch_);
    const std::size_t bytes = n * kLanes * sizeof(float);
    lo_ = static_cast<float*>(std::aligned_alloc(64, bytes));
    hi_ = static_cast<float*>(std::aligned_alloc(64, bytes));
    scratch_ = static_cast<std::uint32_t*>(std::aligned_alloc(64, bytes));
    if (!lo_ || !hi_ || !scratch_) throw std::bad_alloc();
    capacity_ = n;
    left_.resize(n);
    right_.resize(n);
    fold_.resize(n);
  }
  size_ = n;
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
  HWY_DYNAMIC_DISPATCH(EvalBoxes)(tape.ssa().data(), n, lo_, hi_, left_.data(), right_.data(), fold_.data(), box);
}

std::uint32_t IntervalBatchEvaluator::simplify(const Tape& tape, std::uint32_t lanes, Tape* outs, bool registers,
                                              double max_kept) {
  const std::size_t n = size_;
  FREP_ASSERT(tape.size() == n, "simplify needs the tape of the last eval");
  lanes &= (1u << kLanes) - 1;
  if (!lanes) return 0;
  const SsaInstr* in = tape.ssa().data();
  // Backward pass for all boxes at once: live_[i] has a bit for each box that needs instruction
  // i; fin_[i] a bit for each of those where its cap (eval/caps.hpp) is finite, held in scratch_.
  live_.assign(n, 0);
  if (fin_.size() < n) fin_.resize(n);
  if (sides_.size() < 2 * n) sides_.resize(2 * n);
  live_[n - 1] = static_cast<std::uint16_t>(lanes);
  fin_[n - 1] = 0;
  std::uint16_t* live = live_.data();
  std::uint16_t* fin = fin_.data();
  // Caps are kept as float bits in the scratch that the forward pass then uses for its remaps.
  std::uint32_t* caps = scratch_;
  const auto cap_of = [&](std::size_t j, int k) { return std::bit_cast<float>(caps[j * kLanes + static_cast<std::size_t>(k)]); };
  std::size_t kept[kLanes] = {};  // per box: live instructions, the most its tape can keep
  const auto use_uncapped = [&](std::uint32_t j, std::uint32_t bits) {
    fin[j] = static_cast<std::uint16_t>(fin[j] & ~bits);
    live[j] = static_cast<std::uint16_t>(live[j] | bits);
  };
  const auto use = [&](std::uint32_t j, int k, float c) {
    const std::uint32_t bit = 1u << k;
    if (!(c < caps::kNone)) return use_uncapped(j, bit);
    std::uint32_t& slot = caps[static_cast<std::size_t>(j) * kLanes + static_cast<std::size_t>(k)];
    if (!(live[j] & bit)) {
      slot = std::bit_cast<std::uint32_t>(c);
      fin[j] = static_cast<std::uint16_t>(fin[j] | bit);
    } else if (fin[j] & bit) {
      slot = std::bit_cast<std::uint32_t>(std::max(std::bit_cast<float>(slot), c));
    }
    live[j] = static_cast<std::uint16_t>(live[j] | bit);
  };
  // Passes instruction i's own caps on to j for the boxes in `bits`.
  const auto pass = [&](std::size_t i, std::uint32_t j, std::uint32_t bits) {
    use_uncapped(j, bits & ~static_cast<std::uint32_t>(fin[i]));
    for (std::uint32_t b = bits & fin[i]; b; b &= b - 1) {
      const int k = __builtin_ctz(b);
      use(j, k, cap_of(i, k));
    }
  };
  for (std::size_t i = n; i-- > 0;) {
    const std::uint32_t m = live[i];
    if (!m) continue;
    for (std::uint32_t bits = m; bits; bits &= bits - 1) ++kept[__builtin_ctz(bits)];
    const SsaInstr& ins = in[i];
    const int ar = op_arity(ins.op);
    if (ar == 0) continue;
    const std::uint32_t rest = m & ~static_cast<std::uint32_t>(fold_[i]);
    if (ins.op == Op::Min || ins.op == Op::Max) {
      std::uint32_t l = rest & left_[i], r = rest & right_[i], both = rest & ~(l | r);
      if (ins.op == Op::Min) {
        for (std::uint32_t bits = both; bits; bits &= bits - 1) {
          const int k = __builtin_ctz(bits);
          const std::size_t ak = static_cast<std::size_t>(ins.a) * kLanes + k;
          const std::size_t bk = static_cast<std::size_t>(ins.b) * kLanes + k;
          const float c = fin[i] >> k & 1 ? cap_of(i, k) : caps::kNone;
          const caps::MinCaps mc = caps::min_caps(c, lo_[ak], hi_[ak], lo_[bk], hi_[bk]);
          if (mc.choice == Choice::Left) {
            l |= 1u << k;
          } else if (mc.choice == Choice::Right) {
            r |= 1u << k;
          } else {
            use(ins.a, k, mc.cap_a);
            use(ins.b, k, mc.cap_b);
          }
        }
        both &= ~(l | r);
      } else {
        pass(i, ins.a, both);
        pass(i, ins.b, both);
      }
      pass(i, ins.a, l);
      pass(i, ins.b, r);
      sides_[2 * i] = static_cast<std::uint16_t>(l);
      sides_[2 * i + 1] = static_cast<std::uint16_t>(r);
    } else if (op_is_choice(ins.op)) {
      const std::uint32_t l = rest & left_[i], r = rest & right_[i], both = rest & ~(l | r);
      use_uncapped(ins.a, l | both);
      use_uncapped(ins.b, r | both);
      sides_[2 * i] = static_cast<std::uint16_t>(l);
      sides_[2 * i + 1] = static_cast<std::uint16_t>(r);
    } else {
      use_uncapped(ins.a, rest);
      if (ar == 2) use_uncapped(ins.b, rest);
    }
  }
  for (std::uint32_t bits = lanes; bits; bits &= bits - 1) {
    const int k = __builtin_ctz(bits);
    if (static_cast<double>(kept[k]) > max_kept * static_cast<double>(n)) lanes &= ~(1u << k);
  }
  if (!lanes) return 0;
  // Forward pass: each box's builder sees only the instructions it needs.
  std::optional<Tape::Builder> builders[kLanes];
  for (std::uint32_t bits = lanes; bits; bits &= bits - 1) {
    const int k = __builtin_ctz(bits);
    builders[k].emplace(outs[k], n, registers, kept[k], scratch_ + k, kLanes);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t m = live_[i] & lanes;
    if (!m) continue;
    const SsaInstr& ins = in[i];
    if (op_arity(ins.op) == 0) {
      for (std::uint32_t bits = m; bits; bits &= bits - 1) builders[__builtin_ctz(bits)]->keep(i, ins);
      continue;
    }
    const std::uint32_t f = m & fold_[i];
    const std::uint32_t rest = m & ~f;
    const bool choice = op_is_choice(ins.op);
    const std::uint32_t l = choice ? rest & sides_[2 * i] : 0, r = choice ? rest & sides_[2 * i + 1] : 0;
    const std::uint32_t keep = rest & ~(l | r);
    for (std::uint32_t bits = f; bits; bits &= bits - 1) {
      const int k = __builtin_ctz(bits);
      builders[k]->constant(i, lo_[i * kLanes + k]);
    }
    for (std::uint32_t bits = l; bits; bits &= bits - 1) builders[__builtin_ctz(bits)]->alias(i, ins.a);
    for (std::uint32_t bits = r; bits; bits &= bits - 1) builders[__builtin_ctz(bits)]->alias(i, ins.b);
    for (std::uint32_t bits = keep; bits; bits &= bits - 1) builders[__builtin_ctz(bits)]->keep(i, ins);
  }
  for (std::uint32_t bits = lanes; bits; bits &= bits - 1) builders[__builtin_ctz(bits)]->finish(n - 1);
  return lanes;
}

}  // namespace frep
#endif  // HWY_ONCE
