// Evaluating a large expression at many scattered points, with interval pruning: the points are
// sorted along a Morton curve and cut into chunks; each chunk's bounding box simplifies the tape,
// so dense points are evaluated with only the part of the expression near them. This is what makes `frep eval`, `frep sample --points` and accuracy tests
// cheap on converted meshes with millions of nodes, where every point on the full tape would
// cost millions of instructions. Results are bit-identical to BatchEvaluator on the full tape.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "frep/math/grad.hpp"
#include "frep/eval/tape.hpp"

namespace frep {

class ThreadPool;

struct PointCloudOptions {
  int threads = 0;                  // worker threads; 0 = all hardware threads
  std::size_t min_tape = 20000;     // smaller tapes are evaluated as they are (simplifying costs more)
  double max_box = 0.05;            // groups whose box exceeds this fraction of the cloud's are not simplified for
};

// Reusable: keeps its pool and per-worker scratch between calls.
class PointCloudEvaluator {
 public:
  explicit PointCloudEvaluator(PointCloudOptions options = {});
  ~PointCloudEvaluator();
  PointCloudEvaluator(const PointCloudEvaluator&) = delete;
  PointCloudEvaluator& operator=(const PointCloudEvaluator&) = delete;

  // out[i] = f(xs[i], ys[i], zs[i]) for i < n. `tape` needs register code (Tape::compile).
  void eval(const Tape& tape, const float* xs, const float* ys, const float* zs, float* out, std::size_t n);
  // The same with gradients (bit-identical to GradEvaluator on the full tape).
  void eval_grad(const Tape& tape, const float* xs, const float* ys, const float* zs, Grad* out, std::size_t n);

 private:
  struct Worker;
  template <class Out, class Leaf>
  void run(const Tape& tape, const float* xs, const float* ys, const float* zs, Out* out, std::size_t n, Leaf&& leaf);
  PointCloudOptions options_;
  std::unique_ptr<ThreadPool> pool_;
  std::vector<std::unique_ptr<Worker>> workers_;
};

// One-shot helper.
void eval_points(const Tape& tape, const float* xs, const float* ys, const float* zs, float* out, std::size_t n,
                 const PointCloudOptions& options = {});

}  // namespace frep
