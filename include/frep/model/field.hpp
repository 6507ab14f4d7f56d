// A field value: an expression together with what is known about it (FieldInfo: a Lipschitz
// bound, a box holding the inside, how the small values grow beyond it). The modeling functions
// (shapes.hpp, csg.hpp, transform.hpp) and the ugf operations that take a Field carry these facts
// through, by the rules below, so that whatever is built can be rendered, meshed and saved with
// true facts and no guessing.
#pragma once

#include "frep/expr/expr.hpp"
#include "frep/expr/model.hpp"
#include "frep/math/affine.hpp"

namespace frep {

struct Field {
  Expr expr;       // the field's value; a handle into a Graph that must outlive the Field
  FieldInfo info;  // what is known about it; every fact stated is true, unknown ones are 0 or empty
  // Set by transform() when expr = affine_source(affine(p)): a transform of this field then
  // remaps the source once by the composed map (fewer roundings, and Fidget's own lowering).
  NodeId affine_source = kNoNode;
  Affine3 affine;

  explicit Field(Expr e, const FieldInfo& i = {}) : expr(e), info(i) {}
  Graph& graph() const { return expr.graph(); }
  NodeId id() const { return expr.id(); }
};

// The model's shape with the model's facts (the handle points into m.graph).
Field field_of(const Model& m);

// The rules, each stating only what holds for any inputs with the given facts. Lipschitz bounds
// of 0 and empty boxes mean unknown and stay unknown where the rule needs them.

// min(a, b): the larger bound; the union of the boxes.
FieldInfo union_info(const FieldInfo& a, const FieldInfo& b);
// max(a, b): the larger bound; the intersection of the boxes that are known.
FieldInfo intersection_info(const FieldInfo& a, const FieldInfo& b);
// max(a, -b): the larger bound; a's box.
FieldInfo difference_info(const FieldInfo& a, const FieldInfo& b);
// -a: the same bound; no box (the outside of a bounded solid is unbounded).
FieldInfo inverse_info(const FieldInfo& a);
// a - r: the same bound; for r > 0 the box grows by r when the growth is known (else it is
// forgotten), for r <= 0 it stays.
FieldInfo offset_info(const FieldInfo& a, double r);
// A field g with min(a, b) - reach <= g <= ..., reach >= 0 (a smooth union, a blend): the larger
// bound `lipschitz` the caller proves; the union's box grown by `reach` when both growths are known.
FieldInfo union_within_info(const FieldInfo& a, const FieldInfo& b, double reach, double lipschitz);
// f(m(p)): the bound times the largest stretch of m's linear part; the box mapped back through
// m's inverse; Distance kept where m never shrinks distances (the shape moved, turned, mirrored
// or made smaller), Box where m^-1 maps boxes to boxes without enlarging them.
FieldInfo affine_info(const FieldInfo& a, const Affine3& m);

}  // namespace frep
