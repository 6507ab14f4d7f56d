// Interval evaluation of one tape over up to 16 boxes at once, SIMD across the boxes, and
// simplification of the tape for each box in one shared pass. This is what tiled renderers and
// octree meshers use when a cell is split into children: every child is evaluated on the
// parent's tape in the same sweep.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "frep/eval/backend.hpp"
#include "frep/eval/interval.hpp"
#include "frep/eval/tape.hpp"
#include "frep/util/large_allocator.hpp"

namespace frep {

class IntervalBatchEvaluator {
 public:
  static constexpr int kLanes = IntervalRecord::kLanes;

  // The interval pass runs on `backend` (backend.hpp); simplification is the same for all.
  explicit IntervalBatchEvaluator(const Backend& backend = default_backend());
  ~IntervalBatchEvaluator();
  IntervalBatchEvaluator(const IntervalBatchEvaluator&) = delete;
  IntervalBatchEvaluator& operator=(const IntervalBatchEvaluator&) = delete;

  // Evaluates `tape` (which must have register code) over boxes x[k] * y[k] * z[k] for k < count
  // (1 <= count <= kLanes). Same results as IntervalEvaluator box by box. Only the first
  // `simplified` boxes can be simplified for afterwards (the others only need their result).
  void eval(const Tape& tape, const Interval* x, const Interval* y, const Interval* z, int count,
            int simplified = kLanes);

  // The root's interval over box `lane` of the last eval.
  Interval result(int lane) const { return {record_.result_lo[lane], record_.result_hi[lane]}; }

  // Simplifies the last evaluated tape for every box whose bit is set in `lanes` (among the
  // first `simplified` of the last eval), writing
  // outs[lane] with register code (see Tape::simplify). `tape` must be the tape of the last
  // eval. Boxes that would keep more than `max_kept` of the tape's instructions are left out
  // (`tape` serves them nearly as well, and writing a copy costs more than evaluating the rest).
  // Returns the boxes whose tape was written. Without `leaves`, the outputs only run further
  // interval passes, which afford one register per value on bigger tapes (no allocation pass).
  // `root_cap`: as in Tape::simplify (0 for a consumer that reads only signs).
  std::uint32_t simplify(const Tape& tape, std::uint32_t lanes, Tape* outs, double max_kept = 1.0, bool leaves = true,
                         float root_cap = kExactValues);

 private:
  // The evaluation runs on registers (the kernel's), so its memory is the register file's, not
  // the tape's: what simplification needs later is recorded on the way (choices, folded values,
  // the arguments of every min for caps).
  std::unique_ptr<IntervalBatchKernel> kernel_;
  IntervalRecord record_;
  std::size_t size_ = 0;       // SSA instructions of the last evaluated tape
  std::size_t code_size_ = 0;  // and its register instructions
  int simplified_ = 0;         // boxes of the last eval that simplify may take
  // Scratch for simplify.
  LargeVector<std::uint32_t> marks_;       // per SSA instruction: boxes needing it, and (16 bits up) where it has a cap
  LargeVector<std::uint16_t> sides_;       // per choice: boxes keeping only a, only b (both: a constant)
  LargeVector<float> caps_;                // per choice and box: its cap, or that constant
  LargeVector<std::uint32_t> remap_;       // per SSA instruction and box built: its index in that box's tape
};

}  // namespace frep
