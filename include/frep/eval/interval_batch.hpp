// Interval evaluation of one tape over up to 16 boxes at once, SIMD across the boxes, and
// simplification of the tape for each box in one shared pass. This is what tiled renderers and
// octree meshers use when a cell is split into children: every child is evaluated on the
// parent's tape in the same sweep.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "frep/eval/interval.hpp"
#include "frep/eval/tape.hpp"

namespace frep {

class IntervalBatchEvaluator {
 public:
  static constexpr int kLanes = 16;

  IntervalBatchEvaluator();
  ~IntervalBatchEvaluator();
  IntervalBatchEvaluator(const IntervalBatchEvaluator&) = delete;
  IntervalBatchEvaluator& operator=(const IntervalBatchEvaluator&) = delete;

  // Evaluates `tape` over boxes x[k] * y[k] * z[k] for k < count (1 <= count <= kLanes).
  // Same results as IntervalEvaluator box by box.
  void eval(const Tape& tape, const Interval* x, const Interval* y, const Interval* z, int count);

  // The root's interval over box `lane` of the last eval.
  Interval result(int lane) const { return value(size_ - 1, lane); }
  // Instruction i's interval over box `lane`.
  Interval value(std::size_t i, int lane) const {
    return {lo_[i * kLanes + lane], hi_[i * kLanes + lane]};
  }
  // Choice of instruction i over box `lane` (Both for ops that are not min/max/and/or).
  Choice choice(std::size_t i, int lane) const {
    if (left_[i] >> lane & 1) return Choice::Left;
    if (right_[i] >> lane & 1) return Choice::Right;
    return Choice::Both;
  }

  // Simplifies the last evaluated tape for every box whose bit is set in `lanes`, writing
  // outs[lane] (see Tape::simplify). `tape` must be the tape of the last eval. Boxes that would
  // keep more than `max_kept` of the tape's instructions are left out (`tape` serves them
  // nearly as well, and writing a copy costs more than evaluating the rest). Returns the boxes
  // whose tape was written.
  std::uint32_t simplify(const Tape& tape, std::uint32_t lanes, Tape* outs, bool registers = true,
                         double max_kept = 1.0);

 private:
  std::size_t size_ = 0;      // instructions of the last evaluated tape
  std::size_t capacity_ = 0;  // instructions the buffers hold
  float* lo_ = nullptr;       // [instruction][lane]
  float* hi_ = nullptr;
  std::vector<std::uint16_t> left_, right_, fold_;  // per instruction: lane bit masks
  std::uint32_t* scratch_ = nullptr;  // [instruction][lane], for simplify: caps, then remaps
  std::vector<std::uint16_t> live_, fin_;           // scratch for simplify
  std::vector<std::uint16_t> sides_;  // scratch for simplify: per instruction, boxes keeping only a, only b
};

}  // namespace frep
