// SsaBuilder: writes a tape's SSA by hand, for the code that builds one
// tape from another with x, y, z substituted (the renderer's view tape, the mesher's field closed
// at a box). Substitution lives here once, so that a fix to it reaches every such tape.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "frep/eval/tape.hpp"

namespace frep {

class SsaBuilder {
 public:
  // An instruction already written: its index in the SSA.
  using Ref = std::uint32_t;
  // The instructions standing for x, y and z.
  using Vars = std::array<Ref, 3>;

  // Appends op(a, b) (`value`: the constant, or an oracle's index bits) and returns it.
  Ref emit(Op op, Ref a = 0, Ref b = 0, float value = 0);
  Ref constant(float v) { return emit(Op::Const, 0, 0, v); }
  // x, y and z as new instructions (VarX, VarY, VarZ, in that order).
  Vars variables();

  // c[0] u + c[1] v + c[2] w + c[3] with (u, v, w) = `uvw`, summed left to right. Zero terms are
  // dropped and factors of +-1 written without a multiplication, so that a form with one unit
  // term and no constant is that variable itself, exactly.
  Ref affine(const std::array<float, 4>& c, const Vars& uvw);

  // Copies source instruction `s`: a variable becomes the instruction `vars` gives for it,
  // constants and oracles are written again as they are, and the arguments of other operations
  // are looked up in `map` (source index -> Ref, filled for every argument of `s`).
  Ref copy(const SsaInstr& s, const Vars& vars, std::span<const Ref> map);
  // Copies every instruction of `t` (as `copy` does) and returns its root: t(vars) in place of
  // t(x, y, z). Oracle indices are kept: the finished tape needs t's oracles, or ones indexed
  // alike.
  Ref append(const Tape& t, const Vars& vars);

  std::size_t size() const { return ssa_.size(); }
  std::span<const SsaInstr> ssa() const { return ssa_; }

  // The tape computing `root` (moved last with + 0 if something was written after it), its
  // Op::Oracle instructions indexing `oracles`. Leaves the builder empty.
  Tape finish(Ref root, std::shared_ptr<const OracleTable> oracles = nullptr);

 private:
  std::vector<SsaInstr> ssa_;
  std::vector<Ref> map_;  // append's scratch
};

}  // namespace frep
