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
  const SsaInstr* code = ssa.data();
  // The common ops are inlined here; the rest go through ival::op.
  for (std::size_t i = 0; i < n; ++i) {
    const SsaInstr& ins = code[i];
    switch (ins.op) {
      case Op::VarX: v[i] = x; break;
      case Op::VarY: v[i] = y; break;
      case Op::VarZ: v[i] = z; break;
      case Op::Const: v[i] = Interval::point(ins.value); break;
      case Op::Add: {
        const Interval a = v[ins.a], b = v[ins.b];
        v[i] = ival::add_may_nan(a, b) ? Interval::unknown() : ival::checked(a.lo + b.lo, a.hi + b.hi);
        break;
      }
      case Op::Sub: {
        const Interval a = v[ins.a], b = v[ins.b];
        v[i] = ival::sub_may_nan(a, b) ? Interval::unknown() : ival::checked(a.lo - b.hi, a.hi - b.lo);
        break;
      }
      case Op::Neg: {
        const Interval a = v[ins.a];
        v[i] = {-a.hi, -a.lo};
        break;
      }
      case Op::Min: {
        const Interval a = v[ins.a], b = v[ins.b];
        if (a.is_unknown() || b.is_unknown()) {
          v[i] = Interval::unknown();
          c[i] = Choice::Both;
        } else if (a.hi < b.lo) {
          v[i] = a;
          c[i] = Choice::Left;
        } else if (b.hi < a.lo) {
          v[i] = b;
          c[i] = Choice::Right;
        } else {
          v[i] = {a.lo < b.lo ? a.lo : b.lo, a.hi < b.hi ? a.hi : b.hi};
          c[i] = Choice::Both;
        }
        break;
      }
      case Op::Max: {
        const Interval a = v[ins.a], b = v[ins.b];
        if (a.is_unknown() || b.is_unknown()) {
          v[i] = Interval::unknown();
          c[i] = Choice::Both;
        } else if (a.lo > b.hi) {
          v[i] = a;
          c[i] = Choice::Left;
        } else if (b.lo > a.hi) {
          v[i] = b;
          c[i] = Choice::Right;
        } else {
          v[i] = {a.lo > b.lo ? a.lo : b.lo, a.hi > b.hi ? a.hi : b.hi};
          c[i] = Choice::Both;
        }
        break;
      }
      case Op::Mul: {
        v[i] = ival::op(Op::Mul, v[ins.a], v[ins.b], &c[i]);
        break;
      }
      case Op::Square: {
        const Interval a = v[ins.a];
        if (a.lo >= 0) v[i] = {a.lo * a.lo, a.hi * a.hi};
        else if (a.hi <= 0) v[i] = {a.hi * a.hi, a.lo * a.lo};
        else if (a.is_unknown()) v[i] = a;
        else v[i] = {0.0f, std::max(a.lo * a.lo, a.hi * a.hi)};
        break;
      }
      case Op::Sqrt: {
        const Interval a = v[ins.a];
        v[i] = a.lo >= 0 ? Interval{std::sqrt(a.lo), std::sqrt(a.hi)} : Interval::unknown();
        break;
      }
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
