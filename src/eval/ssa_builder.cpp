#include "frep/eval/ssa_builder.hpp"

#include <utility>

#include "frep/error.hpp"

namespace frep {

SsaBuilder::Ref SsaBuilder::emit(Op op, Ref a, Ref b, float value) {
  ssa_.push_back({op, a, b, value});
  return static_cast<Ref>(ssa_.size() - 1);
}

SsaBuilder::Vars SsaBuilder::variables() {
  const Ref x = emit(Op::VarX), y = emit(Op::VarY), z = emit(Op::VarZ);
  return {x, y, z};
}

SsaBuilder::Ref SsaBuilder::affine(const std::array<float, 4>& c, const Vars& uvw) {
  Ref sum = 0;
  bool any = false;
  for (int k = 0; k < 3; ++k) {
    const float ck = c[k];
    if (ck == 0) continue;
    Ref term = uvw[k];
    if (ck == -1) {
      term = emit(Op::Neg, uvw[k]);
    } else if (ck != 1) {
      const Ref factor = constant(ck);
      term = emit(Op::Mul, factor, uvw[k]);
    }
    sum = any ? emit(Op::Add, sum, term) : term;
    any = true;
  }
  if (!any) return constant(c[3]);
  if (c[3] == 0) return sum;
  const Ref shift = constant(c[3]);
  return emit(Op::Add, sum, shift);
}

SsaBuilder::Ref SsaBuilder::copy(const SsaInstr& s, const Vars& vars, std::span<const Ref> map) {
  switch (op_arity(s.op)) {
    case 0:
      if (s.op == Op::Const || s.op == Op::Oracle) return emit(s.op, 0, 0, s.value);
      return vars[static_cast<int>(s.op) - static_cast<int>(Op::VarX)];
    case 1: return emit(s.op, map[s.a], 0, s.value);
    default: return emit(s.op, map[s.a], map[s.b], s.value);
  }
}

SsaBuilder::Ref SsaBuilder::append(const Tape& t, const Vars& vars) {
  const auto src = t.ssa();
  FREP_ASSERT(!src.empty(), "empty tape");
  map_.resize(src.size());
  for (std::size_t i = 0; i < src.size(); ++i) map_[i] = copy(src[i], vars, map_);
  return map_[src.size() - 1];
}

Tape SsaBuilder::finish(Ref root, std::shared_ptr<const OracleTable> oracles) {
  if (root != ssa_.size() - 1) {
    const Ref zero = constant(0.0f);
    emit(Op::Add, root, zero);
  }
  const std::vector<SsaInstr> ssa = std::move(ssa_);
  ssa_.clear();
  return Tape::from_ssa(ssa, std::move(oracles));
}

}  // namespace frep
