// A value with its gradient: what the gradient evaluator produces per point. A shared value type
// (like Interval), kept out of any one evaluator's header.
#pragma once

namespace frep {

struct Grad {
  float v = 0, dx = 0, dy = 0, dz = 0;  // f and its partial derivatives d/dx, d/dy, d/dz
};

}  // namespace frep
