// The model tape in view coordinates: a prefix computing x, y, z from u, v, w, then the model's
// instructions with their variables replaced, then (for rotated views) the cut at the bounds.
#include "view_tape.hpp"

#include <cstdint>
#include <vector>

namespace frep {

Tape view_tape(const Tape& model, const Camera& cam, const Box3& bounds) {
  std::vector<SsaInstr> ssa;
  auto emit = [&](Op op, std::uint32_t a = 0, std::uint32_t b = 0, float value = 0) {
    ssa.push_back({op, a, b, value});
    return static_cast<std::uint32_t>(ssa.size() - 1);
  };
  const std::uint32_t uvw[3] = {emit(Op::VarX), emit(Op::VarY), emit(Op::VarZ)};
  // Model axis `axis` minus its center: sum over view axes of coefficient * view variable, with
  // zero terms dropped and +-1 without a multiplication (so axis-aligned views stay exact).
  auto offset_from_center = [&](int axis) {
    const double coef[3] = {cam.right[axis], cam.up[axis], cam.toward[axis]};
    std::uint32_t sum = 0;
    bool any = false;
    for (int k = 0; k < 3; ++k) {
      if (coef[k] == 0) continue;
      std::uint32_t term;
      if (coef[k] == 1) term = uvw[k];
      else if (coef[k] == -1) term = emit(Op::Neg, uvw[k]);
      else term = emit(Op::Mul, emit(Op::Const, 0, 0, static_cast<float>(coef[k])), uvw[k]);
      sum = any ? emit(Op::Add, sum, term) : term;
      any = true;
    }
    if (!any) sum = emit(Op::Const, 0, 0, 0.0f);
    return sum;
  };
  std::uint32_t rel[3], model_var[3];
  for (int axis = 0; axis < 3; ++axis) {
    rel[axis] = offset_from_center(axis);
    const float c = static_cast<float>(cam.center[axis]);
    model_var[axis] = c == 0 ? rel[axis] : emit(Op::Add, rel[axis], emit(Op::Const, 0, 0, c));
  }

  const auto src = model.ssa();
  std::vector<std::uint32_t> map(src.size());
  for (std::size_t i = 0; i < src.size(); ++i) {
    const SsaInstr& s = src[i];
    switch (s.op) {
      case Op::VarX: map[i] = model_var[0]; break;
      case Op::VarY: map[i] = model_var[1]; break;
      case Op::VarZ: map[i] = model_var[2]; break;
      default: {
        const int ar = op_arity(s.op);
        map[i] = emit(s.op, ar > 0 ? map[s.a] : 0, ar > 1 ? map[s.b] : 0, s.value);
      }
    }
  }
  std::uint32_t root = map.back();
  if (!cam.axis_aligned) {
    std::uint32_t box = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const float half = static_cast<float>(bounds.size()[axis] / 2);
      const std::uint32_t d = emit(Op::Sub, emit(Op::Abs, rel[axis]), emit(Op::Const, 0, 0, half));
      box = axis == 0 ? d : emit(Op::Max, box, d);
    }
    root = emit(Op::Max, root, box);
  }
  if (root != ssa.size() - 1) emit(Op::Add, root, emit(Op::Const, 0, 0, 0.0f));  // root last (only for a bare variable)
  return Tape::from_ssa(ssa);
}

}  // namespace frep
