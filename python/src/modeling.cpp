// The modeling API (frep/model: shapes, booleans, transforms) and the unit gradient field
// operations (frep/ugf) as functions on frep.Field, plus the axes, constants and the opcodes as
// math functions. Each calls the library's function, so facts follow its rules and a script
// building the same shapes builds the same expression.
#include <functional>

#include "common.hpp"
#include "frep/expr/expr.hpp"
#include "frep/model/csg.hpp"
#include "frep/model/shapes.hpp"
#include "frep/model/transform.hpp"
#include "frep/ugf/blend.hpp"
#include "frep/ugf/boolean.hpp"
#include "frep/ugf/chamfer.hpp"
#include "frep/ugf/gyroid.hpp"
#include "frep/ugf/normalize.hpp"
#include "frep/ugf/offset.hpp"
#include "frep/ugf/round.hpp"

namespace frep::python {
namespace {

using Two = std::function<Field(const Field&, const Field&)>;
// f(a, b) in one graph (copying one operand over when they come from different graphs).
PyField both(const PyField& a, const PyField& b, const Two& f) {
  const SameGraph s = same_graph(a, b);
  return PyField(s.graph, f(s.a, s.b));
}

// Any number of fields (or one sequence of them) in one graph, for union_of / intersection_of.
std::pair<std::shared_ptr<Graph>, std::vector<Field>> gathered(const py::args& args) {
  std::vector<PyField> in;
  if (args.size() == 1 && !py::isinstance<PyField>(args[0]))
    in = py::cast<std::vector<PyField>>(args[0]);
  else
    for (const auto& a : args) in.push_back(py::cast<PyField>(a));
  if (in.empty()) return {std::make_shared<Graph>(), {}};
  std::size_t largest = 0;
  for (std::size_t i = 1; i < in.size(); ++i)
    if (in[i].graph->size() > in[largest].graph->size()) largest = i;
  std::vector<Field> out;
  for (const PyField& f : in) out.push_back(f.in_graph_of(in[largest]));
  return {in[largest].graph, out};
}

ugf::Blend blend_kind(const std::string& s) {
  if (s == "quadratic") return ugf::Blend::Quadratic;
  if (s == "cubic") return ugf::Blend::Cubic;
  if (s == "exponential") return ugf::Blend::Exponential;
  if (s == "root") return ugf::Blend::Root;
  throw py::value_error("kind is 'quadratic', 'cubic', 'exponential' or 'root', got '" + s + "'");
}

ugf::EdgeOptions edge(float min_angle) {
  ugf::EdgeOptions o;
  o.min_angle_degrees = min_angle;
  return o;
}

// A chamfer size from exactly one of inset=, setback=, width=, setbacks=(sA, sB).
ugf::Chamfer chamfer_size(const std::optional<float>& inset, const std::optional<float>& setback,
                          const std::optional<float>& width, const std::optional<std::pair<float, float>>& setbacks,
                          bool exact) {
  const int given = int(bool(inset)) + int(bool(setback)) + int(bool(width)) + int(bool(setbacks));
  if (given != 1) throw py::value_error("give the chamfer's size as exactly one of inset=, setback=, width=, setbacks=(sA, sB)");
  ugf::Chamfer c = inset ? ugf::Chamfer::inset(*inset)
                   : setback ? ugf::Chamfer::setback(*setback)
                   : width ? ugf::Chamfer::width(*width)
                           : ugf::Chamfer::setbacks(setbacks->first, setbacks->second);
  if (!(c.a >= 0 && c.b >= 0)) throw py::value_error("chamfer sizes must be >= 0");
  return exact ? c.distance_preserving() : c;
}

// Expression-only operations (no facts known): the result of `e` on the fields' expressions.
PyField expr_of(const SameGraph& s, Expr e) { return PyField(s.graph, Field(e)); }

// A field or a number as a field in `like`'s graph.
Field lifted(const py::object& o, const PyField& like) {
  if (py::isinstance<PyField>(o)) return py::cast<const PyField&>(o).in_graph_of(like);
  return Field(like.graph->c(py::cast<float>(o)));
}

// A binary opcode on fields or numbers (at least one a field).
PyField binary_op(const py::object& a, const py::object& b, Expr (*op)(Expr, Expr), const char* name) {
  const bool fa = py::isinstance<PyField>(a), fb = py::isinstance<PyField>(b);
  if (!fa && !fb) throw py::type_error(std::string("frep.") + name + " needs at least one frep.Field");
  const PyField& like = fa ? py::cast<const PyField&>(a) : py::cast<const PyField&>(b);
  if (fa && fb) {
    const SameGraph s = same_graph(py::cast<const PyField&>(a), py::cast<const PyField&>(b));
    return expr_of(s, op(s.a.expr, s.b.expr));
  }
  return like.with(Field(op(lifted(a, like).expr, lifted(b, like).expr)));
}

}  // namespace

void bind_modeling(py::module_& m) {
  // The axes and constants.
  m.def("x", [] { return PyField::make([](Graph& g) { return Field(g.x()); }); }, "The field x.");
  m.def("y", [] { return PyField::make([](Graph& g) { return Field(g.y()); }); }, "The field y.");
  m.def("z", [] { return PyField::make([](Graph& g) { return Field(g.z()); }); }, "The field z.");
  m.def("constant", [](float v) { return PyField::make([v](Graph& g) { return Field(g.c(v)); }); }, py::arg("value"),
        "The constant field value (float32).");

  // Shapes (frep/model/shapes.hpp).
  m.def("sphere", [](const py::object& c, double r) {
    const Vec3 center = vec3_of(c, "center");
    return PyField::make([&](Graph& g) { return sphere(g, center, r); });
  }, py::arg("center") = py::make_tuple(0, 0, 0), py::arg("radius") = 1.0,
        "|p - center| - radius: the exact signed distance of a sphere (lipschitz 1, its box, growth 'distance').");
  m.def("box", [](const py::object& lo, const py::object& hi) {
    const Vec3 l = vec3_of(lo, "lower"), h = vec3_of(hi, "upper");
    return PyField::make([&](Graph& g) { return box(g, l, h); });
  }, py::arg("lower"), py::arg("upper"),
        "The box [lower, upper] as the max over axes of max(lower - p, p - upper) (exact inside, a bound near "
        "edges and corners outside; growth 'box').");
  m.def("circle", [](const std::pair<double, double>& c, double r) {
    return PyField::make([&](Graph& g) { return circle(g, c.first, c.second, r); });
  }, py::arg("center") = std::make_pair(0.0, 0.0), py::arg("radius") = 1.0,
        "A disc of the xy plane (an infinite cylinder along z): sqrt((x - cx)^2 + (y - cy)^2) - radius.");
  m.def("rectangle", [](const std::pair<double, double>& lo, const std::pair<double, double>& hi) {
    return PyField::make([&](Graph& g) { return rectangle(g, lo.first, lo.second, hi.first, hi.second); });
  }, py::arg("lower"), py::arg("upper"), "The rectangle [x0, x1] x [y0, y1] of the xy plane (infinite along z).");
  m.def("plane", [](const py::object& axis, double offset) {
    const Vec3 a = vec3_of(axis, "axis");
    return PyField::make([&](Graph& g) { return plane(g, a, offset); });
  }, py::arg("axis"), py::arg("offset") = 0.0,
        "dot(axis, p) - offset: negative on the side opposite the axis (a signed distance for a unit axis).");

  // Booleans (frep/model/csg.hpp).
  m.def("unite", [](const PyField& a, const PyField& b) { return both(a, b, [](const Field& x, const Field& y) { return unite(x, y); }); },
        py::arg("a"), py::arg("b"), "The union min(a, b).");
  m.def("intersect", [](const PyField& a, const PyField& b) { return both(a, b, [](const Field& x, const Field& y) { return intersect(x, y); }); },
        py::arg("a"), py::arg("b"), "The intersection max(a, b).");
  m.def("subtract", [](const PyField& a, const PyField& b) { return both(a, b, [](const Field& x, const Field& y) { return subtract(x, y); }); },
        py::arg("a"), py::arg("b"), "The difference max(a, -b): a with b cut away.");
  m.def("inverse", [](const PyField& a) { return a.with(inverse(a.field)); }, py::arg("a"), "The complement -a.");
  m.def("union", [](const py::args& args) {
    auto [g, fields] = gathered(args);
    return PyField(g, union_of(*g, fields));
  }, "The union of any number of fields (or one list of them) as a balanced tree of min; none: the empty shape.");
  m.def("intersection", [](const py::args& args) {
    auto [g, fields] = gathered(args);
    return PyField(g, intersection_of(*g, fields));
  }, "The intersection of any number of fields (or one list) as a balanced tree of max; none: all of space.");
  m.def("blend", [](const PyField& a, const PyField& b, double r) {
    return both(a, b, [r](const Field& x, const Field& y) { return blend(x, y, r); });
  }, py::arg("a"), py::arg("b"), py::arg("radius"),
        "Fidget's blend: min(a, b) - max(radius - |a - b|, 0)^2 / (4 radius), a smooth union.");

  // Transforms (frep/model/transform.hpp).
  m.def("move", [](const PyField& f, const py::object& offset) { return f.with(move(f.field, vec3_of(offset, "offset"))); },
        py::arg("f"), py::arg("offset"), "The shape moved by offset: f(p - offset).");
  m.def("scale", [](const PyField& f, const py::object& s) {
    const Vec3 v = py::isinstance<py::float_>(s) || py::isinstance<py::int_>(s) ? Vec3{py::cast<double>(s), py::cast<double>(s), py::cast<double>(s)}
                                                                                : vec3_of(s, "scale");
    return f.with(scale(f.field, v));
  }, py::arg("f"), py::arg("scale"), "The shape scaled about the origin by a number or per axis (sx, sy, sz): f(p / s).");
  m.def("rotate", [](const PyField& f, const py::object& axis, double degrees, const py::object& center) {
    return f.with(rotate(f.field, vec3_of(axis, "axis"), degrees, vec3_of(center, "center")));
  }, py::arg("f"), py::arg("axis"), py::arg("degrees"), py::arg("center") = py::make_tuple(0, 0, 0),
        "The shape rotated by degrees about the unit axis through center (right-handed).");
  m.def("reflect", [](const PyField& f, const py::object& axis, double offset) {
    return f.with(reflect(f.field, vec3_of(axis, "axis"), offset));
  }, py::arg("f"), py::arg("axis"), py::arg("offset") = 0.0, "The shape mirrored in the plane dot(axis, p) = offset.");
  m.def("revolve_y", [](const PyField& f, double offset) { return f.with(revolve_y(f.field, offset)); }, py::arg("f"),
        py::arg("offset") = 0.0, "The xy section revolved about the y axis (moved by offset along x first).");
  m.def("extrude_z", [](const PyField& f, double lower, double upper) { return f.with(extrude_z(f.field, lower, upper)); },
        py::arg("f"), py::arg("lower") = 0.0, py::arg("upper") = 1.0,
        "The shape's z = 0 section extruded from z = lower to z = upper.");
  m.def("loft_z", [](const PyField& a, const PyField& b, double lower, double upper) {
    return both(a, b, [&](const Field& x, const Field& y) { return loft_z(x, y, lower, upper); });
  }, py::arg("a"), py::arg("b"), py::arg("lower") = 0.0, py::arg("upper") = 1.0,
        "Blended linearly from a's z = 0 section at z = lower to b's at z = upper, cut there.");
  m.def("remap", [](const PyField& f, const PyField& X, const PyField& Y, const PyField& Z) {
    return f.with(remap(f.field, X.in_graph_of(f).expr, Y.in_graph_of(f).expr, Z.in_graph_of(f).expr));
  }, py::arg("f"), py::arg("x"), py::arg("y"), py::arg("z"), "f(X, Y, Z): f with the axes replaced by fields.");

  // Unit gradient field operations (frep/ugf).
  py::module_ u = m.def_submodule("ugf", "Unit gradient field operations: offsets, shells, exact booleans, blends, chamfers, rounds.");
  u.def("offset", [](const PyField& f, float r) { return f.with(ugf::offset(f.field, r)); }, py::arg("f"), py::arg("r"),
        "f - r: the solid grown by r (shrunk for r < 0); exact outside for signed distances.");
  u.def("shell", [](const PyField& f, float t) { return f.with(ugf::shell(f.field, t)); }, py::arg("f"), py::arg("t"),
        "|f| - t/2: a wall of thickness t centred on f's surface.");
  u.def("shell_biased", [](const PyField& f, float t, float b) { return f.with(ugf::shell_biased(f.field, t, b)); },
        py::arg("f"), py::arg("t"), py::arg("bias"), "|f + b t/2| - t/2: a wall of thickness t, b = +1 inside f, -1 outside.");
  u.def("shell_inward", [](const PyField& f, float t) { return f.with(ugf::shell_inward(f.field, t)); }, py::arg("f"),
        py::arg("t"), "max(f, -f - t): the wall of thickness t just inside f's surface (hollowing).");
  u.def("shell_outward", [](const PyField& f, float t) { return f.with(ugf::shell_outward(f.field, t)); }, py::arg("f"),
        py::arg("t"), "max(-f, f - t): the wall of thickness t just outside f's surface.");
  u.def("normalize", [](const PyField& f) { return f.with(Field(ugf::normalize(f.field.expr))); }, py::arg("f"),
        "f / |grad f|: a unit gradient field near the surface (nothing known of the result).");
#define FREP_EXACT_BOOLEAN(name, doc)                                                                        \
  u.def(#name, [](const PyField& a, const PyField& b, float min_angle) {                                    \
    return both(a, b, [min_angle](const Field& x, const Field& y) { return ugf::name(x, y, edge(min_angle)); }); \
  }, py::arg("a"), py::arg("b"), py::arg("min_angle") = 1.0f, doc);
  FREP_EXACT_BOOLEAN(intersect_exact, "The distance-preserving intersection: the exact distance of a wedge of planes at any angle.")
  FREP_EXACT_BOOLEAN(unite_exact, "The distance-preserving union -intersect_exact(-a, -b).")
  FREP_EXACT_BOOLEAN(subtract_exact, "The distance-preserving difference intersect_exact(a, -b).")
#undef FREP_EXACT_BOOLEAN
  u.def("intersect_right_angle", [](const PyField& a, const PyField& b) {
    return both(a, b, [](const Field& x, const Field& y) { return ugf::intersect_right_angle(x, y); });
  }, py::arg("a"), py::arg("b"), "The intersection exact for perpendicular planes, without gradients.");
  u.def("unite_right_angle", [](const PyField& a, const PyField& b) {
    return both(a, b, [](const Field& x, const Field& y) { return ugf::unite_right_angle(x, y); });
  }, py::arg("a"), py::arg("b"), "The union exact for perpendicular planes.");
  u.def("subtract_right_angle", [](const PyField& a, const PyField& b) {
    return both(a, b, [](const Field& x, const Field& y) { return ugf::subtract_right_angle(x, y); });
  }, py::arg("a"), py::arg("b"), "The difference exact for perpendicular planes.");
#define FREP_SMOOTH(name, doc)                                                                           \
  u.def(#name, [](const PyField& a, const PyField& b, float k, const std::string& kind) {                \
    const ugf::Blend bk = blend_kind(kind);                                                              \
    return both(a, b, [k, bk](const Field& x, const Field& y) { return ugf::name(x, y, k, bk); });       \
  }, py::arg("a"), py::arg("b"), py::arg("k"), py::arg("kind") = "quadratic", doc);
  FREP_SMOOTH(smooth_union, "A smooth union of blend thickness k (at most min(a, b)); kind: quadratic, cubic, exponential, root.")
  FREP_SMOOTH(smooth_intersection, "A smooth intersection -smooth_union(-a, -b, k).")
  FREP_SMOOTH(smooth_difference, "A smooth difference smooth_intersection(a, -b, k).")
#undef FREP_SMOOTH
  auto chamfer = [](Expr (*op)(Expr, Expr, const ugf::Chamfer&, const ugf::EdgeOptions&)) {
    return [op](const PyField& a, const PyField& b, std::optional<float> inset, std::optional<float> setback,
                std::optional<float> width, std::optional<std::pair<float, float>> setbacks, bool exact, float min_angle) {
      const ugf::Chamfer c = chamfer_size(inset, setback, width, setbacks, exact);
      const SameGraph s = same_graph(a, b);
      return expr_of(s, op(s.a.expr, s.b.expr, c, edge(min_angle)));
    };
  };
  const char* chamfer_doc =
      "A chamfer of the edge between faces a and b, sized by exactly one of inset= (from the edge along the "
      "bisector), setback= (along each face), width= (of the chamfer face) or setbacks=(sA, sB); exact=True for "
      "the distance-preserving form. Nothing is known of the result (info is empty).";
  u.def("chamfer_intersection",
        chamfer(static_cast<Expr (*)(Expr, Expr, const ugf::Chamfer&, const ugf::EdgeOptions&)>(ugf::chamfer_intersection)),
        py::arg("a"), py::arg("b"), py::kw_only(), py::arg("inset") = py::none(), py::arg("setback") = py::none(),
        py::arg("width") = py::none(), py::arg("setbacks") = py::none(), py::arg("exact") = false,
        py::arg("min_angle") = 1.0f, chamfer_doc);
  u.def("chamfer_union",
        chamfer(static_cast<Expr (*)(Expr, Expr, const ugf::Chamfer&, const ugf::EdgeOptions&)>(ugf::chamfer_union)),
        py::arg("a"), py::arg("b"), py::kw_only(), py::arg("inset") = py::none(), py::arg("setback") = py::none(),
        py::arg("width") = py::none(), py::arg("setbacks") = py::none(), py::arg("exact") = false,
        py::arg("min_angle") = 1.0f, chamfer_doc);
  auto rounded = [](Expr (*op)(Expr, Expr, float, const ugf::EdgeOptions&)) {
    return [op](const PyField& a, const PyField& b, float r, float min_angle) {
      if (!(r >= 0)) throw py::value_error("the radius must be >= 0");
      const SameGraph s = same_graph(a, b);
      return expr_of(s, op(s.a.expr, s.b.expr, r, edge(min_angle)));
    };
  };
  u.def("round_intersection",
        rounded(static_cast<Expr (*)(Expr, Expr, float, const ugf::EdgeOptions&)>(ugf::round_intersection)),
        py::arg("a"), py::arg("b"), py::arg("r"), py::arg("min_angle") = 1.0f,
        "The intersection with its edge rounded to radius r (exact for planes at any angle).");
  u.def("round_union", rounded(static_cast<Expr (*)(Expr, Expr, float, const ugf::EdgeOptions&)>(ugf::round_union)),
        py::arg("a"), py::arg("b"), py::arg("r"), py::arg("min_angle") = 1.0f,
        "The union with a fillet of radius r in its concave edge (exact for planes at any angle).");
  u.def("gyroid", [](float period) { return PyField::make([period](Graph& g) { return Field(ugf::gyroid(g, period)); }); },
        py::arg("period"), "The gyroid sin x cos y + sin y cos z + sin z cos x with the given period.");

  // The opcodes as math functions on fields (numbers next to a field become constants).
#define FREP_UNARY(name, doc) \
  m.def(#name, [](const PyField& a) { return a.with(Field(frep::name(a.field.expr))); }, py::arg("a"), doc);
  FREP_UNARY(sqrt, "sqrt(a)") FREP_UNARY(square, "a * a") FREP_UNARY(sin, "sin(a)") FREP_UNARY(cos, "cos(a)")
  FREP_UNARY(tan, "tan(a)") FREP_UNARY(asin, "asin(a)") FREP_UNARY(acos, "acos(a)") FREP_UNARY(atan, "atan(a)")
  FREP_UNARY(exp, "exp(a)") FREP_UNARY(ln, "The natural logarithm of a.") FREP_UNARY(floor, "floor(a)")
  FREP_UNARY(ceil, "ceil(a)") FREP_UNARY(round, "a rounded to the nearest whole number.") FREP_UNARY(recip, "1 / a")
#undef FREP_UNARY
  m.def("abs", [](const PyField& a) { return a.with(Field(frep::abs(a.field.expr))); }, py::arg("a"), "|a|");
  m.def("min", [](const py::object& a, const py::object& b) {
    if (py::isinstance<PyField>(a) && py::isinstance<PyField>(b))
      return both(py::cast<const PyField&>(a), py::cast<const PyField&>(b), [](const Field& x, const Field& y) { return unite(x, y); });
    return binary_op(a, b, [](Expr x, Expr y) { return frep::min(x, y); }, "min");
  }, py::arg("a"), py::arg("b"), "min(a, b) (of two fields: the union, with its facts).");
  m.def("max", [](const py::object& a, const py::object& b) {
    if (py::isinstance<PyField>(a) && py::isinstance<PyField>(b))
      return both(py::cast<const PyField&>(a), py::cast<const PyField&>(b), [](const Field& x, const Field& y) { return intersect(x, y); });
    return binary_op(a, b, [](Expr x, Expr y) { return frep::max(x, y); }, "max");
  }, py::arg("a"), py::arg("b"), "max(a, b) (of two fields: the intersection, with its facts).");
  m.def("atan2", [](const py::object& a, const py::object& b) { return binary_op(a, b, [](Expr x, Expr y) { return frep::atan2(x, y); }, "atan2"); },
        py::arg("y"), py::arg("x"), "atan2(y, x)");
  m.def("mod", [](const py::object& a, const py::object& b) { return binary_op(a, b, [](Expr x, Expr y) { return frep::mod(x, y); }, "mod"); },
        py::arg("a"), py::arg("b"), "The Euclidean remainder of a by b (Fidget's mod).");
}

}  // namespace frep::python
