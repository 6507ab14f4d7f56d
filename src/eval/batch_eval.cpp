// SIMD batch evaluator. Highway compiles this file once per instruction set and picks the best
// one for the CPU at run time, so the binary needs no -march flag.
#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS (HWY_SSSE3 | HWY_AVX3_DL)  // fewer copies, faster builds
#endif
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "eval/batch_eval.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "eval/simd_ops-inl.h"

#include <cstdlib>
#include <cstring>

#include "frep/error.hpp"
#include "eval/interp_kernels.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/expr/oracle.hpp"
#include "frep/expr/semantics.hpp"

HWY_BEFORE_NAMESPACE();
namespace frep {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<float>;
using V = hn::Vec<D>;

template <class F>
HWY_INLINE void Unary(const float* HWY_RESTRICT a, float* o, std::size_t count, F f) {
  const D d;
  for (std::size_t i = 0; i < count; i += hn::Lanes(d)) hn::Store(f(hn::Load(d, a + i)), d, o + i);
}

template <class F>
HWY_INLINE void Binary(const RegInstr& ins, const float* regs, float* o, std::size_t stride, std::size_t count,
                       F f) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  if (ins.mode == 0) {
    const float* HWY_RESTRICT a = regs + ins.a * stride;
    const float* HWY_RESTRICT b = regs + ins.b * stride;
    for (std::size_t i = 0; i < count; i += N) hn::Store(f(hn::Load(d, a + i), hn::Load(d, b + i)), d, o + i);
  } else if (ins.mode & RegInstr::kImmB) {
    const float* HWY_RESTRICT a = regs + ins.a * stride;
    const V b = hn::Set(d, ins.imm);
    for (std::size_t i = 0; i < count; i += N) hn::Store(f(hn::Load(d, a + i), b), d, o + i);
  } else {
    const V a = hn::Set(d, ins.imm);
    const float* HWY_RESTRICT b = regs + ins.b * stride;
    for (std::size_t i = 0; i < count; i += N) hn::Store(f(a, hn::Load(d, b + i)), d, o + i);
  }
}

// Ops without a SIMD form here (libm functions, fmod): scalar, with the reference semantics.
HWY_NOINLINE void ScalarOp(const RegInstr& ins, const float* regs, float* o, std::size_t stride,
                           std::size_t count) {
  const bool ia = ins.mode & RegInstr::kImmA, ib = ins.mode & RegInstr::kImmB;
  const float* a = ia ? &ins.imm : regs + ins.a * stride;
  const float* b = ib ? &ins.imm : regs + ins.b * stride;
  op_eval_lanes<float>(ins.op, o, a, ia ? 0 : 1, b, ib ? 0 : 1, count);
}

void EvalChunk(const RegInstr* code, std::size_t ncode, float* regs, std::size_t stride, const float* x,
               const float* y, const float* z, std::size_t m, std::size_t count, const OracleTable* oracles) {
  const D d;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  for (std::size_t k = 0; k < ncode; ++k) {
    const RegInstr& ins = code[k];
    float* HWY_RESTRICT o = regs + ins.out * stride;
    const float* a = regs + ins.a * stride;
    switch (ins.op) {
      case Op::VarX:
      case Op::VarY:
      case Op::VarZ: {
        const float* src = ins.op == Op::VarX ? x : ins.op == Op::VarY ? y : z;
        std::memcpy(o, src, m * sizeof(float));
        for (std::size_t i = m; i < count; ++i) o[i] = 0;
        break;
      }
      case Op::Const:
        for (std::size_t i = 0; i < count; ++i) o[i] = ins.imm;
        break;
      case Op::Oracle:
        (*oracles)[oracle_index(ins.imm)]->values(x, y, z, o, m);
        for (std::size_t i = m; i < count; ++i) o[i] = 0;
        break;
      case Op::Neg: Unary(a, o, count, [](V v) { return hn::Neg(v); }); break;
      case Op::Abs: Unary(a, o, count, [](V v) { return hn::Abs(v); }); break;
      case Op::Recip: Unary(a, o, count, [&](V v) { return hn::Div(one, v); }); break;
      case Op::Sqrt: Unary(a, o, count, [](V v) { return hn::Sqrt(v); }); break;
      case Op::Square: Unary(a, o, count, [](V v) { return hn::Mul(v, v); }); break;
#if HWY_TARGET != HWY_SCALAR  // Highway's scalar Floor/Ceil lose the sign of zero: use libm there
      case Op::Floor: Unary(a, o, count, [](V v) { return hn::Floor(v); }); break;
      case Op::Ceil: Unary(a, o, count, [](V v) { return hn::Ceil(v); }); break;
      case Op::Round:  // halves away from zero
        Unary(a, o, count, [&](V v) {
          const V t = hn::Trunc(v);
          const auto away = hn::Abs(hn::Sub(v, t)) >= hn::Set(d, 0.5f);
          return hn::IfThenElse(away, hn::Add(t, hn::CopySign(one, v)), t);
        });
        break;
#endif
      case Op::Not: Unary(a, o, count, [&](V v) { return hn::IfThenElse(v == zero, one, zero); }); break;
      case Op::Add: Binary(ins, regs, o, stride, count, [](V p, V q) { return hn::Add(p, q); }); break;
      case Op::Sub: Binary(ins, regs, o, stride, count, [](V p, V q) { return hn::Sub(p, q); }); break;
      case Op::Mul: Binary(ins, regs, o, stride, count, [](V p, V q) { return hn::Mul(p, q); }); break;
      case Op::Div: Binary(ins, regs, o, stride, count, [](V p, V q) { return hn::Div(p, q); }); break;
      case Op::Min:  // NaN if either is NaN, else p < q ? p : q
        Binary(ins, regs, o, stride, count, [](V p, V q) { return MinNaN(p, q); });
        break;
      case Op::Max:
        Binary(ins, regs, o, stride, count, [](V p, V q) { return MaxNaN(p, q); });
        break;
      case Op::Compare:
        Binary(ins, regs, o, stride, count, [&](V p, V q) {
          const V r = hn::IfThenElse(p < q, hn::Neg(one), hn::IfThenElseZero(p > q, one));
          return hn::IfThenElse(hn::Or(hn::IsNaN(p), hn::IsNaN(q)), hn::Add(p, q), r);
        });
        break;
      case Op::And:  // p == 0 ? p : q
        Binary(ins, regs, o, stride, count, [&](V p, V q) { return hn::IfThenElse(p == zero, p, q); });
        break;
      case Op::Or:  // p != 0 ? p : q
        Binary(ins, regs, o, stride, count, [&](V p, V q) { return hn::IfThenElse(p == zero, q, p); });
        break;
      default:
        ScalarOp(ins, regs, o, stride, count);
    }
  }
}

const char* TargetNameHere() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace frep
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace frep {
HWY_EXPORT(EvalChunk);
HWY_EXPORT(TargetNameHere);

const char* BatchEvaluator::target_name() { return HWY_DYNAMIC_DISPATCH(TargetNameHere)(); }

namespace interp {
namespace {

class Batch final : public BatchKernel {
 public:
  ~Batch() override { std::free(regs_); }

  void eval(const Tape& tape, const float* xs, const float* ys, const float* zs, float* out, std::size_t n) override {
    const auto& code = tape.code();
    FREP_ASSERT(!code.empty(), "tape has no register code (simplified without registers)");
    // Size the scratch for this tape; a small batch uses a short stride to stay in cache.
    constexpr std::size_t kLanesMax = 16;
    const std::size_t stride = std::min<std::size_t>(BatchEvaluator::kChunk, (n + kLanesMax - 1) / kLanesMax * kLanesMax);
    const std::size_t need = tape.num_registers() * stride;
    if (need > capacity_) {
      std::free(regs_);
      regs_ = static_cast<float*>(std::aligned_alloc(64, (need * sizeof(float) + 63) / 64 * 64));
      if (!regs_) throw std::bad_alloc();
      capacity_ = need;
    }
    auto* fn = HWY_DYNAMIC_DISPATCH(EvalChunk);
    const float* root = regs_ + tape.root_register() * stride;
    for (std::size_t base = 0; base < n; base += stride) {
      const std::size_t m = std::min(stride, n - base);
      const std::size_t count = (m + kLanesMax - 1) / kLanesMax * kLanesMax;
      fn(code.data(), code.size(), regs_, stride, xs + base, ys + base, zs + base, m, count, tape.oracles().get());
      std::memcpy(out + base, root, m * sizeof(float));
    }
  }

 private:
  float* regs_ = nullptr;
  std::size_t capacity_ = 0;  // floats
};

}  // namespace

std::unique_ptr<BatchKernel> make_batch_kernel() { return std::make_unique<Batch>(); }

}  // namespace interp
}  // namespace frep
#endif  // HWY_ONCE
