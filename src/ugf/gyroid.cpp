// The gyroid lattice (gyroid.hpp).
#include "frep/ugf/gyroid.hpp"

#include <cmath>

#include "frep/ugf/normalize.hpp"
#include "ugf/predicates.hpp"

namespace frep::ugf {

using namespace detail;

Expr gyroid(Graph& g, float period) {
  const float w = 2.0f * kPi / period;
  const Expr x = g.x() * w, y = g.y() * w, z = g.z() * w;
  return sin(x) * cos(y) + sin(y) * cos(z) + sin(z) * cos(x);
}

Expr gyroid_normalized(Graph& g, float period, GyroidScale scale) {
  const Expr raw = gyroid(g, period);
  if (scale == GyroidScale::Sampson) return normalize(raw);
  const float w = 2.0f * kPi / period;
  return raw / (std::sqrt(3.0f) * w);
}

Expr gyroid_network(Graph& g, float period, float bias, GyroidScale scale) {
  return gyroid_normalized(g, period, scale) - bias;
}

Expr gyroid_sheet(Graph& g, float period, float t, GyroidScale scale) {
  return abs(gyroid_normalized(g, period, scale)) - 0.5f * t;
}

}  // namespace frep::ugf
