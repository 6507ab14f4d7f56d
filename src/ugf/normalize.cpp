// Sampson normalization (normalize.hpp).
#include "frep/ugf/normalize.hpp"

#include "frep/expr/derivative.hpp"

namespace frep::ugf {

Expr normalize(Expr F, float min_gradient) { return F / max(length(grad(F)), min_gradient); }

}  // namespace frep::ugf
