// Gradient evaluator: forward mode, batched. Common ops run as SIMD loops (Highway, chosen at
// run time); the others go lane by lane through the scalar derivative table below.
#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS (HWY_SSSE3 | HWY_AVX3_DL)
#endif
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "eval/grad_eval.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "eval/simd_ops-inl.h"

#include <algorithm>
#include <cmath>

#include "frep/error.hpp"
#include "eval/interp_kernels.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/expr/oracle.hpp"
#include "frep/expr/semantics.hpp"

#include "eval/grad_partials.hpp"


HWY_BEFORE_NAMESPACE();
namespace frep {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
using D = hn::ScalableTag<float>;
using V = hn::Vec<D>;

// Channel c of register r: R + r * 4 * chunk + c * chunk (unaligned: a std::vector).
struct G {
  V v, dx, dy, dz;
};

HWY_INLINE G LoadArg(D d, const RegInstr& ins, bool first, const float* R, std::size_t chunk, std::size_t j) {
  const bool imm = first ? (ins.mode & RegInstr::kImmA) : (ins.mode & RegInstr::kImmB);
  if (imm) return {hn::Set(d, ins.imm), hn::Zero(d), hn::Zero(d), hn::Zero(d)};
  const float* p = R + (first ? ins.a : ins.b) * 4 * chunk + j;
  return {hn::LoadU(d, p), hn::LoadU(d, p + chunk), hn::LoadU(d, p + 2 * chunk), hn::LoadU(d, p + 3 * chunk)};
}

// p * dv, except that a zero partial gives 0 even where dv is infinite or NaN.
HWY_INLINE V Scaled(V p, V dv) { return hn::IfThenElseZero(NotZero(p), hn::Mul(p, dv)); }


// Returns false for ops it does not vectorize.
bool GradOp(const RegInstr& ins, float* R, std::size_t chunk, std::size_t count) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f), half = hn::Set(d, 0.5f), two = hn::Set(d, 2.0f);
  float* o = R + ins.out * 4 * chunk;
  auto run = [&](auto f) {
    for (std::size_t j = 0; j < count; j += N) {
      const G a = LoadArg(d, ins, true, R, chunk, j);
      const G b = op_arity(ins.op) == 2 ? LoadArg(d, ins, false, R, chunk, j) : G{zero, zero, zero, zero};
      const G r = f(a, b);
      hn::StoreU(r.v, d, o + j);
      hn::StoreU(r.dx, d, o + chunk + j);
      hn::StoreU(r.dy, d, o + 2 * chunk + j);
      hn::StoreU(r.dz, d, o + 3 * chunk + j);
    }
  };
  auto unary = [&](auto value, auto partial) {
    run([&](const G& a, const G&) {
      const V v = value(a.v);
      const V p = partial(a.v, v);
      return G{v, Scaled(p, a.dx), Scaled(p, a.dy), Scaled(p, a.dz)};
    });
  };
  switch (ins.op) {
    case Op::Add:
      run([](const G& a, const G& b) {
        return G{hn::Add(a.v, b.v), hn::Add(a.dx, b.dx), hn::Add(a.dy, b.dy), hn::Add(a.dz, b.dz)};
      });
      return true;
    case Op::Sub:
      run([](const G& a, const G& b) {
        return G{hn::Sub(a.v, b.v), hn::Sub(a.dx, b.dx), hn::Sub(a.dy, b.dy), hn::Sub(a.dz, b.dz)};
      });
      return true;
    case Op::Mul:
      run([](const G& a, const G& b) {
        auto ch = [&](V da, V db) { return hn::Add(Scaled(b.v, da), Scaled(a.v, db)); };
        return G{hn::Mul(a.v, b.v), ch(a.dx, b.dx), ch(a.dy, b.dy), ch(a.dz, b.dz)};
      });
      return true;
    case Op::Div:
      run([&](const G& a, const G& b) {
        const V pa = hn::Div(one, b.v), pb = hn::Neg(hn::Div(a.v, hn::Mul(b.v, b.v)));
        auto ch = [&](V da, V db) { return hn::Add(Scaled(pa, da), Scaled(pb, db)); };
        return G{hn::Div(a.v, b.v), ch(a.dx, b.dx), ch(a.dy, b.dy), ch(a.dz, b.dz)};
      });
      return true;
    case Op::Min:
    case Op::Max: {
      const bool is_min = ins.op == Op::Min;
      run([&](const G& a, const G& b) {
        const V v = is_min ? MinNaN(a.v, b.v) : MaxNaN(a.v, b.v);
        const auto take_a = is_min ? a.v < b.v : a.v > b.v;
        const auto nan = hn::IsNaN(v);
        auto ch = [&](V da, V db) { return hn::IfThenElse(nan, v, hn::IfThenElse(take_a, da, db)); };
        return G{v, ch(a.dx, b.dx), ch(a.dy, b.dy), ch(a.dz, b.dz)};
      });
      return true;
    }
    case Op::Neg:
      run([](const G& a, const G&) { return G{hn::Neg(a.v), hn::Neg(a.dx), hn::Neg(a.dy), hn::Neg(a.dz)}; });
      return true;
    case Op::Abs:
      run([&](const G& a, const G&) {
        const auto neg = a.v < zero;
        auto ch = [&](V da) { return hn::IfThenElse(neg, hn::Neg(da), da); };
        return G{hn::Abs(a.v), ch(a.dx), ch(a.dy), ch(a.dz)};
      });
      return true;
    case Op::Square:
      unary([](V x) { return hn::Mul(x, x); }, [&](V x, V) { return hn::Mul(two, x); });
      return true;
    case Op::Sqrt:  // sqrt'(0) = 0 by convention
      unary([](V x) { return hn::Sqrt(x); },
            [&](V, V v) { return hn::IfThenElseZero(NotZero(v), hn::Div(half, v)); });
      return true;
    default:
      return false;
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace frep
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace frep {
HWY_EXPORT(GradOp);
using grad_detail::grad_lane;

namespace interp {
namespace {

class GradKernelImpl final : public GradKernel {
 public:
  void eval(const Tape& tape, const float* xs, const float* ys, const float* zs, Grad* out, std::size_t n) override;

 private:
  std::vector<float> regs_;  // per register: 4 * kChunk floats (v, dx, dy, dz)
};

constexpr std::size_t kChunk = GradEvaluator::kChunk;

void GradKernelImpl::eval(const Tape& tape, const float* xs, const float* ys, const float* zs, Grad* out,
                          std::size_t n) {
  const auto& code = tape.code();
  FREP_ASSERT(!code.empty(), "tape has no register code (simplified without registers)");
  const std::size_t stride = 4 * kChunk;
  if (regs_.size() < tape.num_registers() * stride) regs_.resize(tape.num_registers() * stride);
  float* R = regs_.data();
  for (std::size_t base = 0; base < n; base += kChunk) {
    const std::size_t m = std::min(kChunk, n - base);
    for (const RegInstr& ins : code) {
      float* o = R + ins.out * stride;
      switch (ins.op) {
        case Op::VarX:
        case Op::VarY:
        case Op::VarZ: {
          const float* src = ins.op == Op::VarX ? xs : ins.op == Op::VarY ? ys : zs;
          const int axis = static_cast<int>(ins.op) - static_cast<int>(Op::VarX);
          for (std::size_t i = 0; i < m; ++i) {
            o[i] = src[base + i];
            o[kChunk + i] = axis == 0;
            o[2 * kChunk + i] = axis == 1;
            o[3 * kChunk + i] = axis == 2;
          }
          break;
        }
        case Op::Const:
          for (std::size_t i = 0; i < m; ++i) {
            o[i] = ins.imm;
            o[kChunk + i] = o[2 * kChunk + i] = o[3 * kChunk + i] = 0;
          }
          break;
        case Op::Oracle: {
          Grad g[kChunk];
          tape.oracle(ins.imm).gradients(xs + base, ys + base, zs + base, g, m);
          for (std::size_t i = 0; i < m; ++i) {
            o[i] = g[i].v;
            o[kChunk + i] = g[i].dx;
            o[2 * kChunk + i] = g[i].dy;
            o[3 * kChunk + i] = g[i].dz;
          }
          break;
        }
        default: {
          if (HWY_DYNAMIC_DISPATCH(GradOp)(ins, R, kChunk, (m + 15) / 16 * 16)) break;
          const bool ia = ins.mode & RegInstr::kImmA, ib = ins.mode & RegInstr::kImmB;
          const float* A = R + ins.a * stride;
          const float* B = R + ins.b * stride;
          const bool binary = op_arity(ins.op) == 2;
          for (std::size_t i = 0; i < m; ++i) {
            const float a = ia ? ins.imm : A[i];
            const float b = !binary ? 0.0f : (ib ? ins.imm : B[i]);
            const float da[3] = {A[kChunk + i], A[2 * kChunk + i], A[3 * kChunk + i]};
            const float db[3] = {B[kChunk + i], B[2 * kChunk + i], B[3 * kChunk + i]};
            float v, d[3];
            grad_lane(ins.op, a, da, !ia, b, db, binary && !ib, v, d);
            o[i] = v;
            o[kChunk + i] = d[0];
            o[2 * kChunk + i] = d[1];
            o[3 * kChunk + i] = d[2];
          }
        }
      }
    }
    const float* r = R + tape.root_register() * stride;
    for (std::size_t i = 0; i < m; ++i)
      out[base + i] = {r[i], r[kChunk + i], r[2 * kChunk + i], r[3 * kChunk + i]};
  }
}

}  // namespace

std::unique_ptr<GradKernel> make_grad_kernel() { return std::make_unique<GradKernelImpl>(); }

}  // namespace interp

}  // namespace frep
#endif  // HWY_ONCE
