// The interpreter backend's kernels (private to src/eval): one per evaluator kind, each defined
// beside the SIMD code it runs (batch_eval.cpp, grad_eval.cpp, interval_batch.cpp).
#pragma once

#include <memory>

#include "frep/eval/backend.hpp"

namespace frep::interp {

std::unique_ptr<BatchKernel> make_batch_kernel();
std::unique_ptr<GradKernel> make_grad_kernel();
std::unique_ptr<IntervalBatchKernel> make_interval_batch_kernel();

}  // namespace frep::interp
