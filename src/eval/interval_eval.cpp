#include "eval/interval_ops.hpp"
#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"

namespace frep {

Interval interval_op(Op op, Interval a, Interval b, Choice* choice) { return ival::op(op, a, b, choice); }

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
  for (std::size_t i = 0; i < n; ++i) {
    const SsaInstr& ins = ssa[i];
    switch (ins.op) {
      case Op::VarX: v[i] = x; c[i] = Choice::Both; break;
      case Op::VarY: v[i] = y; c[i] = Choice::Both; break;
      case Op::VarZ: v[i] = z; c[i] = Choice::Both; break;
      case Op::Const: v[i] = Interval::point(ins.value); c[i] = Choice::Both; break;
      default:
        v[i] = ival::op(ins.op, v[ins.a], op_arity(ins.op) == 2 ? v[ins.b] : Interval{}, &c[i]);
    }
  }
  return v[n - 1];
}

Interval IntervalEvaluator::simplify(const Tape& tape, Interval x, Interval y, Interval z, Tape& out) {
  const Interval r = eval(tape, x, y, z);
  tape.simplify(values_, choices_, out);
  return r;
}

}  // namespace frep
