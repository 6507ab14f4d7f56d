// Medial-axis tracking through booleans (medial.hpp).
#include "frep/ugf/medial.hpp"

#include <limits>

#include "frep/expr/derivative.hpp"
#include "ugf/predicates.hpp"

namespace frep::ugf {

using namespace detail;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// |m1| <= |m2| ? m1 : m2 (the nearer crease).
Expr nearer(Expr m1, Expr m2) { return select(logical_not(max(compare(abs(m1), abs(m2)), 0.0f)), m1, m2); }

// `a_wins` is non-zero where the boolean returns a.f.
Tracked combine(const Tracked& a, const Tracked& b, Expr f, Expr a_wins) {
  Differentiator d(f.graph());
  const Gradient ga = d.grad(a.f), gb = d.grad(b.f);
  const Gradient diff{ga.x - gb.x, ga.y - gb.y, ga.z - gb.z};
  const Expr len = length(diff);
  constexpr float kTiny = 1e-12f;
  // Where the gradients coincide A - B is locally constant: no tie surface, no new crease.
  const Expr m_new = select(positive(len - kTiny), (a.f - b.f) / max(len, kTiny), f.graph().c(kInf));
  const Expr m_w = select(a_wins, a.m, b.m);
  return {f, nearer(m_w, m_new)};
}

}  // namespace

Tracked track_plane(Expr f) { return {f, f.graph().c(kInf)}; }
Tracked track(Expr f, Expr m) { return {f, m}; }

Tracked track_sphere(Graph& g, float cx, float cy, float cz, float r) {
  const Expr d = sqrt(square(g.x() - cx) + square(g.y() - cy) + square(g.z() - cz));
  return {d - r, d};
}

Tracked offset(const Tracked& a, float r) { return {a.f - r, a.m}; }
Tracked negate(const Tracked& a) { return {-a.f, a.m}; }
Tracked shell(const Tracked& a, float t) { return {abs(a.f) - 0.5f * t, nearer(a.m, a.f)}; }

// max returns a where a > b, min where a < b (b on ties), as the evaluators do.
Tracked intersect(const Tracked& a, const Tracked& b) {
  return combine(a, b, max(a.f, b.f), max(compare(a.f, b.f), 0.0f));
}
Tracked unite(const Tracked& a, const Tracked& b) {
  return combine(a, b, min(a.f, b.f), min(compare(a.f, b.f), 0.0f));
}
Tracked subtract(const Tracked& a, const Tracked& b) { return intersect(a, negate(b)); }

}  // namespace frep::ugf
