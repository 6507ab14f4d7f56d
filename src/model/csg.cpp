// Booleans and the blend, as Fidget's shape library writes them.
#include "frep/model/csg.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace frep {
namespace {

Graph& same_graph(const Field& a, const Field& b, const char* what) {
  if (&a.graph() != &b.graph())
    throw std::invalid_argument(std::string("frep: ") + what +
                                " of fields from two different graphs (copy one over with copy_expression)");
  return a.graph();
}

// Balanced, as Fidget reduces a list: halves first, so the depth is log2(n).
Field reduce(Graph& g, std::span<const Field> items, bool is_union) {
  if (items.empty()) {
    const float v = is_union ? std::numeric_limits<float>::infinity() : -std::numeric_limits<float>::infinity();
    return Field(g.c(v));
  }
  if (items.size() == 1) return items[0];
  const std::size_t half = items.size() / 2;
  const Field a = reduce(g, items.first(half), is_union);
  const Field b = reduce(g, items.subspan(half), is_union);
  return is_union ? unite(a, b) : intersect(a, b);
}

}  // namespace

Field unite(const Field& a, const Field& b) {
  Graph& g = same_graph(a, b, "union");
  return Field(g.expr(g.binary(Op::Min, a.id(), b.id())), union_info(a.info, b.info));
}

Field intersect(const Field& a, const Field& b) {
  Graph& g = same_graph(a, b, "intersection");
  return Field(g.expr(g.binary(Op::Max, a.id(), b.id())), intersection_info(a.info, b.info));
}

Field subtract(const Field& a, const Field& b) {
  Graph& g = same_graph(a, b, "difference");
  return Field(g.expr(g.binary(Op::Max, a.id(), g.unary(Op::Neg, b.id()))), difference_info(a.info, b.info));
}

Field inverse(const Field& a) { return Field(-a.expr, inverse_info(a.info)); }

Field union_of(Graph& g, std::span<const Field> fields) { return reduce(g, fields, true); }
Field intersection_of(Graph& g, std::span<const Field> fields) { return reduce(g, fields, false); }

Field blend(const Field& a, const Field& b, double radius) {
  Graph& g = same_graph(a, b, "blend");
  const NodeId m = g.binary(Op::Min, a.id(), b.id());
  if (!(radius > 0)) return Field(g.expr(m), union_info(a.info, b.info));
  const NodeId gap = g.binary(Op::Max, g.binary(Op::Sub, g.constant(static_cast<float>(radius)),
                                                g.unary(Op::Abs, g.binary(Op::Sub, a.id(), b.id()))),
                              g.constant(0));
  const NodeId r = g.binary(Op::Sub, m, g.binary(Op::Mul, g.constant(static_cast<float>(1.0 / (4.0 * radius))),
                                                 g.unary(Op::Square, gap)));
  // Between min(a, b) - radius / 4 and min(a, b); the gradient a convex combination of the two.
  const double bound = a.info.lipschitz > 0 && b.info.lipschitz > 0 ? std::max(a.info.lipschitz, b.info.lipschitz) : 0.0;
  return Field(g.expr(r), union_within_info(a.info, b.info, radius / 4 * (1 + 1e-6), bound));  // f32 constant
}

}  // namespace frep
