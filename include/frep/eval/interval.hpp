// Interval arithmetic on the engine's ops: the interval value type lives in frep/math/interval.hpp
// (shared by oracles and evaluators); this adds the per-op rule the interval evaluators use.
#pragma once

#include "frep/expr/opcode.hpp"
#include "frep/math/interval.hpp"

namespace frep {

// Evaluates one op on intervals; writes the choice for min/max/and/or (Both otherwise).
Interval interval_op(Op op, Interval a, Interval b, Choice* choice);

}  // namespace frep
