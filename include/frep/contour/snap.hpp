// Moving points onto the surface along the gradient: the vertex placement of the snap method
// (`frep mesh --method snap`), usable on its own. Each step is the Newton step for f = 0 along
// the gradient, p <- p - f(p) grad f(p) / |grad f(p)|^2.
#pragma once

#include <span>
#include <vector>

#include "frep/eval/evaluators.hpp"
#include "frep/eval/tape.hpp"
#include "frep/math/vec.hpp"

namespace frep {

enum class SnapGradient {
  Analytic,            // the gradient evaluator (forward mode, exact for the expression)
  CentralDifferences,  // (f(p + d e_i) - f(p - d e_i)) / 2d per axis, from the value evaluator
};

struct SnapOptions {
  int iterations = 4;                           // Newton steps per point
  SnapGradient gradient = SnapGradient::Analytic;
  double difference_step = 1e-3;                // central differences: d, as a fraction of max_step
};

// Reusable (keeps evaluator scratch); one per thread.
class SurfaceSnapper {
 public:
  // Moves each point (batched) by up to options.iterations steps. A step is at most `max_step`
  // long, and point i never leaves keep_in[i]; the tape must be valid in every keep_in box.
  // Where f or its gradient is not finite, or the gradient vanishes, the point stays where it is.
  // Returns the gradient at each final point in `normals` (unit, or zero where unusable).
  void snap(const Tape& tape, std::span<Vec3> points, std::span<const Box3> keep_in, double max_step,
            const SnapOptions& options, std::vector<Vec3f>* normals = nullptr);

 private:
  BatchEvaluator values_;
  GradEvaluator grads_;
  std::vector<float> xs_, ys_, zs_, out_;
  std::vector<Grad> g_;
};

}  // namespace frep
