// Rounds of radius r (round.hpp), in the edge frame: the arc's center sits on the bisector at
// r / cos(phi/2) from the edge, and (Sr, Dn) are coordinates around it.
#include "frep/ugf/round.hpp"

#include "ugf/predicates.hpp"

namespace frep::ugf {

using namespace detail;

Expr round_intersection(const EdgeFrame& f, float r) {
  const Expr ch = max(f.cos_half, f.guard);
  const Expr Sr = f.Sn + r / ch;
  // |Dn| < Sr tan(phi/2), without dividing (it also implies Sr > 0).
  const Expr cone = positive(Sr * f.sin_half - abs(f.Dn) * ch);
  return select(both(f.valid, cone), length2(Sr, f.Dn) - r, max(f.A, f.B));
}

Expr round_union(const EdgeFrame& f, float r) {
  const Expr ch = max(f.cos_half, f.guard);
  const Expr Sr = r / ch - f.Sn;
  const Expr cone = positive(Sr * f.sin_half - abs(f.Dn) * ch);
  return select(both(f.valid, cone), r - length2(Sr, f.Dn), min(f.A, f.B));
}

Expr round_intersection(Expr A, Expr B, float r, const EdgeOptions& opt) {
  return round_intersection(edge_frame(A, B, opt), r);
}

Expr round_union(Expr A, Expr B, float r, const EdgeOptions& opt) { return round_union(edge_frame(A, B, opt), r); }

}  // namespace frep::ugf
