#include <cmath>

#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/expr/oracle.hpp"
#include "frep/expr/semantics.hpp"

namespace frep {

float PointEvaluator::eval(const Tape& tape, float x, float y, float z) {
  const auto& code = tape.code();
  FREP_ASSERT(!code.empty(), "tape has no register code (simplified without registers)");
  if (regs_.size() < tape.num_registers()) regs_.resize(tape.num_registers());
  float* r = regs_.data();
  for (const RegInstr& ins : code) {
    switch (ins.op) {
      case Op::VarX: r[ins.out] = x; break;
      case Op::VarY: r[ins.out] = y; break;
      case Op::VarZ: r[ins.out] = z; break;
      case Op::Const: r[ins.out] = ins.imm; break;
      case Op::Oracle: tape.oracle(ins.imm).values(&x, &y, &z, &r[ins.out], 1); break;
      // The common ops get their own cases, so one switch decides everything for them.
#define FREP_POINT_BINARY(OP, expr)                                          \
  case Op::OP: {                                                             \
    const float a = (ins.mode & RegInstr::kImmA) ? ins.imm : r[ins.a];       \
    const float b = (ins.mode & RegInstr::kImmB) ? ins.imm : r[ins.b];       \
    r[ins.out] = (expr);                                                     \
    break;                                                                   \
  }
      FREP_POINT_BINARY(Add, a + b)
      FREP_POINT_BINARY(Sub, a - b)
      FREP_POINT_BINARY(Mul, a * b)
      FREP_POINT_BINARY(Min, op_min(a, b))
      FREP_POINT_BINARY(Max, op_max(a, b))
#undef FREP_POINT_BINARY
      case Op::Neg: r[ins.out] = -r[ins.a]; break;
      case Op::Square: r[ins.out] = r[ins.a] * r[ins.a]; break;
      case Op::Sqrt: r[ins.out] = std::sqrt(r[ins.a]); break;
      default: {
        const float a = (ins.mode & RegInstr::kImmA) ? ins.imm : r[ins.a];
        const float b = (ins.mode & RegInstr::kImmB) ? ins.imm : r[ins.b];
        r[ins.out] = op_eval<float>(ins.op, a, b);
      }
    }
  }
  return r[tape.root_register()];
}

}  // namespace frep
