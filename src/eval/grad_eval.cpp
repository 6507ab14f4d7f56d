#include <algorithm>
#include <cmath>

#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/expr/semantics.hpp"

namespace frep {
namespace {

// Derivative of op at (a, b) given value v: returns (dv/da, dv/db).
inline void partials(Op op, float a, float b, float v, float& pa, float& pb) {
  pa = 0;
  pb = 0;
  switch (op) {
    case Op::Neg: pa = -1; break;
    case Op::Abs: pa = a < 0 ? -1.0f : 1.0f; break;
    case Op::Recip: pa = -1.0f / (a * a); break;
    case Op::Sqrt: pa = v == 0 ? 0.0f : 0.5f / v; break;
    case Op::Square: pa = 2 * a; break;
    case Op::Sin: pa = std::cos(a); break;
    case Op::Cos: pa = -std::sin(a); break;
    case Op::Tan: pa = 1 + v * v; break;
    case Op::Asin: pa = 1.0f / std::sqrt(1 - a * a); break;
    case Op::Acos: pa = -1.0f / std::sqrt(1 - a * a); break;
    case Op::Atan: pa = 1.0f / (1 + a * a); break;
    case Op::Exp: pa = v; break;
    case Op::Ln: pa = 1.0f / a; break;
    case Op::Add: pa = 1; pb = 1; break;
    case Op::Sub: pa = 1; pb = -1; break;
    case Op::Mul: pa = b; pb = a; break;
    case Op::Div: pa = 1.0f / b; pb = -a / (b * b); break;
    case Op::Atan2: {
      const float d = a * a + b * b;  // atan2(y = a, x = b)
      pa = b / d;
      pb = -a / d;
      break;
    }
    case Op::Min:
      if (std::isnan(v)) pa = pb = v;
      else if (a < b) pa = 1;
      else pb = 1;
      break;
    case Op::Max:
      if (std::isnan(v)) pa = pb = v;
      else if (a > b) pa = 1;
      else pb = 1;
      break;
    case Op::Mod:
      pa = 1;
      pb = -std::floor(a / std::fabs(b)) * (b < 0 ? -1.0f : 1.0f);
      break;
    case Op::And:
      if (a == 0) pa = 1; else pb = 1;
      break;
    case Op::Or:
      if (a != 0) pa = 1; else pb = 1;
      break;
    default:  // floor, ceil, round, compare, not: piecewise constant
      break;
  }
}

}  // namespace

void GradEvaluator::eval(const Tape& tape, const float* xs, const float* ys, const float* zs, Grad* out,
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
        default: {
          const bool ia = ins.mode & RegInstr::kImmA, ib = ins.mode & RegInstr::kImmB;
          const float* A = R + ins.a * stride;
          const float* B = R + ins.b * stride;
          const bool binary = op_arity(ins.op) == 2;
          for (std::size_t i = 0; i < m; ++i) {
            const float a = ia ? ins.imm : A[i];
            const float b = !binary ? 0.0f : (ib ? ins.imm : B[i]);
            const float v = op_eval<float>(ins.op, a, b);
            float pa, pb;
            partials(ins.op, a, b, v, pa, pb);
            float d[3];
            for (int k = 0; k < 3; ++k) {
              const std::size_t off = (k + 1) * kChunk + i;
              // A zero partial must not turn an infinite or NaN argument gradient into NaN.
              float t = 0;
              if (pa != 0 && !ia) t += pa * A[off];
              if (pb != 0 && binary && !ib) t += pb * B[off];
              d[k] = t;
            }
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

Grad GradEvaluator::eval(const Tape& tape, float x, float y, float z) {
  Grad g;
  eval(tape, &x, &y, &z, &g, 1);
  return g;
}

}  // namespace frep
