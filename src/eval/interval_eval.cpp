#include "eval/interval_ops.hpp"
#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/expr/oracle.hpp"

namespace frep {

Interval interval_op(Op op, Interval a, Interval b, Choice* choice) { return ival::op_generic(op, a, b, choice); }

Interval IntervalEvaluator::eval(const Tape& tape, Interval x, Interval y, Interval z) {
  const auto& ssa = tape.ssa();
  const std::size_t n = ssa.size();
  FREP_ASSERT(n > 0, "empty tape");
  if (values_.size() < n) {
    values_.resize(n);
    choices_.resize(n);
  }
  Interval* v = values_.data();
  Choice* c = choices_.data();
  const SsaInstr* code = ssa.data();
  // The common ops get their own cases, each calling ival::op with a constant opcode, so that
  // the (always inlined) op reduces to just that op's code; the rest go through the general call.
#define FREP_INTERVAL_CASE(OP)                                                                \
  case Op::OP:                                                                                \
    v[i] = ival::op(Op::OP, v[ins.a], op_arity(Op::OP) == 2 ? v[ins.b] : Interval{}, &c[i]);  \
    break;
  for (std::size_t i = 0; i < n; ++i) {
    const SsaInstr& ins = code[i];
    switch (ins.op) {
      case Op::VarX: v[i] = x; break;
      case Op::VarY: v[i] = y; break;
      case Op::VarZ: v[i] = z; break;
      case Op::Const: v[i] = Interval::point(ins.value); break;
      case Op::Oracle: tape.oracle(ins.value).bounds(&x, &y, &z, &v[i], 1); break;
      FREP_INTERVAL_CASE(Add)
      FREP_INTERVAL_CASE(Sub)
      FREP_INTERVAL_CASE(Mul)
      FREP_INTERVAL_CASE(Neg)
      FREP_INTERVAL_CASE(Square)
      FREP_INTERVAL_CASE(Sqrt)
      FREP_INTERVAL_CASE(Min)
      FREP_INTERVAL_CASE(Max)
      default:
        v[i] = ival::op_generic(ins.op, v[ins.a], op_arity(ins.op) == 2 ? v[ins.b] : Interval{}, &c[i]);
    }
  }
#undef FREP_INTERVAL_CASE
  return v[n - 1];
}

Interval IntervalEvaluator::simplify(const Tape& tape, Interval x, Interval y, Interval z, Tape& out) {
  const Interval r = eval(tape, x, y, z);
  tape.simplify(values_, choices_, out);
  return r;
}

}  // namespace frep
