// Pencils of planes through an edge (pencil.hpp).
#include "frep/ugf/pencil.hpp"

#include <cmath>

#include "ugf/predicates.hpp"

namespace frep::ugf {

using namespace detail;

Expr pencil(const EdgeFrame& f, float theta) { return f.Sn * std::cos(theta) + f.Dn * std::sin(theta); }

Expr pencil_face(const EdgeFrame& f, float theta, float d) { return pencil(f, theta) - d; }

Expr pencil_chamfer(const EdgeFrame& f, float theta, float d) {
  const Expr m = max(f.A, f.B);
  return select(f.valid, max(m, pencil_face(f, theta, d)), m);
}

}  // namespace frep::ugf
