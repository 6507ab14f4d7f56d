// Rhai functions for the unit gradient field library (include/frep/ugf/*.hpp): every operation
// as a script function of the same name as in C++, calling the library (no formulas here).
// Argument conventions (docs/ugf.md, "Using it from Rhai"): shapes are anything that converts to
// an expression (trees, numbers, arrays of shapes); sizes are plain numbers; edge operations take
// an optional last map #{ min_angle: degrees }; chamfer sizes are maps; medial-axis tracking uses
// maps #{ f, m }, which offset, shell, negate, intersect, unite and subtract also accept.
#include <cmath>
#include <string>

#include "frep/model/csg.hpp"
#include "frep/ugf.hpp"
#include "rhai_interp.hpp"

namespace frep::rhai {

namespace {

using Args = std::span<Value>;

[[noreturn]] void usage(Interp& in, std::string_view name, Args a, std::uint32_t pos, const char* expected) {
  std::string got;
  for (const Value& v : a) got += (got.empty() ? "" : ", ") + std::string(type_name(v));
  in.fail(pos, "`" + std::string(name) + "` takes " + expected + ", not (" + got + ")");
}

Expr shape(Interp& in, const Value& v, std::uint32_t pos, std::string_view name, const char* what) {
  return Expr(in.graph(), in.to_expr(v, pos, "the " + std::string(what) + " of `" + std::string(name) + "`"));
}

// The same with the facts the library recorded for it (frep/model/field.hpp).
Field field(Interp& in, const Value& v, std::uint32_t pos, std::string_view name, const char* what) {
  return in.field(shape(in, v, pos, name, what).id());
}

float number(Interp& in, const Value& v, std::uint32_t pos, std::string_view name, const char* what) {
  if (!v.is_number())
    in.fail(pos, "`" + std::string(name) + "`: the " + what + " must be a number, not " + type_name(v));
  const double d = v.number();
  if (!std::isfinite(d)) in.fail(pos, "`" + std::string(name) + "`: the " + what + " must be finite");
  return static_cast<float>(d);
}

const Value* map_item(const Value& m, std::string_view key) {
  const auto& items = m.as<MapObj>().items;
  auto it = items.find(key);
  return it == items.end() ? nullptr : &it->second;
}

// Rejects keys other than `allowed` (a typo must not pass silently).
void check_keys(Interp& in, const Value& m, std::initializer_list<std::string_view> allowed, std::uint32_t pos,
                std::string_view name) {
  for (const auto& kv : m.as<MapObj>().items) {
    bool ok = false;
    for (std::string_view k : allowed) ok |= kv.first == k;
    if (!ok) {
      std::string list;
      for (std::string_view k : allowed) list += (list.empty() ? "" : ", ") + std::string(k);
      in.fail(pos, "`" + std::string(name) + "`: unknown option `" + kv.first + "` (options: " + list + ")");
    }
  }
}

// The trailing #{ min_angle: degrees } of edge operations, if present (then `n` shrinks by one).
ugf::EdgeOptions edge_options(Interp& in, Args a, std::size_t& n, std::uint32_t pos, std::string_view name) {
  ugf::EdgeOptions o;
  if (n > 0 && a[n - 1].kind() == Kind::Map) {
    const Value& m = a[n - 1];
    check_keys(in, m, {"min_angle"}, pos, name);
    if (const Value* v = map_item(m, "min_angle")) o.min_angle_degrees = number(in, *v, pos, name, "min_angle");
    if (!(o.min_angle_degrees > 0 && o.min_angle_degrees < 90))
      in.fail(pos, "`" + std::string(name) + "`: min_angle must be between 0 and 90 degrees");
    --n;
  }
  return o;
}

// ---------------------------------------------------------------------------------------------
// Medial-axis tracking values: #{ f: shape, m: distance to its creases }

bool is_tracked(const Value& v) {
  return v.kind() == Kind::Map && v.as<MapObj>().items.size() == 2 && map_item(v, "f") && map_item(v, "m");
}

ugf::Tracked tracked(Interp& in, const Value& v, std::uint32_t pos, std::string_view name) {
  return {shape(in, *map_item(v, "f"), pos, name, "tracked field f"), shape(in, *map_item(v, "m"), pos, name, "crease distance m")};
}

Value tracked_value(const ugf::Tracked& t) {
  auto* m = new MapObj();
  Value out = Value::heap(m);
  m->items.emplace("f", Value::expr(t.f.id()));
  m->items.emplace("m", Value::expr(t.m.id()));
  return out;
}

// ---------------------------------------------------------------------------------------------
// Offsets and shells

Value fn_offset(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 2) usage(in, "offset", a, pos, "(shape, distance)");
  const float r = number(in, a[1], pos, "offset", "distance");
  if (is_tracked(a[0])) return tracked_value(ugf::offset(tracked(in, a[0], pos, "offset"), r));
  return Value::expr(in.keep(ugf::offset(field(in, a[0], pos, "offset", "shape"), r)));
}

Value fn_shell(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 2) usage(in, "shell", a, pos, "(shape, thickness)");
  const float t = number(in, a[1], pos, "shell", "thickness");
  if (is_tracked(a[0])) return tracked_value(ugf::shell(tracked(in, a[0], pos, "shell"), t));
  return Value::expr(in.keep(ugf::shell(field(in, a[0], pos, "shell", "shape"), t)));
}

Value fn_shell_biased(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 3) usage(in, "shell_biased", a, pos, "(shape, thickness, bias in [-1, 1])");
  const float b = number(in, a[2], pos, "shell_biased", "bias");
  if (!(b >= -1 && b <= 1)) in.fail(pos, "`shell_biased`: the bias must be in [-1, 1] (+1: all inward)");
  return Value::expr(in.keep(
      ugf::shell_biased(field(in, a[0], pos, "shell_biased", "shape"), number(in, a[1], pos, "shell_biased", "thickness"), b)));
}

template <Field (*F)(const Field&, float)>
Value shape_number(Interp& in, Args a, std::uint32_t pos, std::string_view name, const char* what) {
  if (a.size() != 2) usage(in, name, a, pos, (std::string("(shape, ") + what + ")").c_str());
  return Value::expr(in.keep(F(field(in, a[0], pos, name, "shape"), number(in, a[1], pos, name, what))));
}
Value fn_shell_inward(Interp& in, Args a, std::uint32_t p) { return shape_number<ugf::shell_inward>(in, a, p, "shell_inward", "thickness"); }
Value fn_shell_outward(Interp& in, Args a, std::uint32_t p) { return shape_number<ugf::shell_outward>(in, a, p, "shell_outward", "thickness"); }

Value fn_shell_variable(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 2) usage(in, "shell_variable", a, pos, "(shape, thickness field)");
  return Value::expr(ugf::shell_variable(shape(in, a[0], pos, "shell_variable", "shape"),
                                         shape(in, a[1], pos, "shell_variable", "thickness field"))
                         .id());
}

// ---------------------------------------------------------------------------------------------
// Booleans

// Operations with no facts to carry build plain expressions.
template <Expr (*F)(Expr, Expr)>
Value two_exprs(Interp& in, Args a, std::uint32_t pos, std::string_view name) {
  if (a.size() != 2) usage(in, name, a, pos, "(a, b)");
  return Value::expr(F(shape(in, a[0], pos, name, "first shape"), shape(in, a[1], pos, name, "second shape")).id());
}

template <Field (*F)(const Field&, const Field&)>
Value two_shapes(Interp& in, Args a, std::uint32_t pos, std::string_view name) {
  if (a.size() != 2) usage(in, name, a, pos, "(a, b)");
  return Value::expr(in.keep(F(field(in, a[0], pos, name, "first shape"), field(in, a[1], pos, name, "second shape"))));
}

// intersect / unite / subtract: expressions, or tracked maps (medial.hpp) when both are.
template <Field (*F)(const Field&, const Field&), ugf::Tracked (*T)(const ugf::Tracked&, const ugf::Tracked&)>
Value plain_boolean(Interp& in, Args a, std::uint32_t pos, std::string_view name) {
  if (a.size() == 2 && (is_tracked(a[0]) || is_tracked(a[1]))) {
    if (!is_tracked(a[0]) || !is_tracked(a[1]))
      in.fail(pos, "`" + std::string(name) + "` of a tracked field #{ f, m } needs two tracked fields");
    return tracked_value(T(tracked(in, a[0], pos, name), tracked(in, a[1], pos, name)));
  }
  return two_shapes<F>(in, a, pos, name);
}
// The plain booleans are the modeling library's (frep/model/csg.hpp): the same min and max.
Value fn_intersect(Interp& in, Args a, std::uint32_t p) { return plain_boolean<frep::intersect, ugf::intersect>(in, a, p, "intersect"); }
Value fn_unite(Interp& in, Args a, std::uint32_t p) { return plain_boolean<frep::unite, ugf::unite>(in, a, p, "unite"); }
Value fn_subtract(Interp& in, Args a, std::uint32_t p) { return plain_boolean<frep::subtract, ugf::subtract>(in, a, p, "subtract"); }

template <Field (*F)(const Field&, const Field&, const ugf::EdgeOptions&)>
Value edge_boolean(Interp& in, Args a, std::uint32_t pos, std::string_view name) {
  std::size_t n = a.size();
  const ugf::EdgeOptions o = edge_options(in, a, n, pos, name);
  if (n != 2) usage(in, name, a, pos, "(a, b) or (a, b, #{ min_angle })");
  return Value::expr(in.keep(F(field(in, a[0], pos, name, "first shape"), field(in, a[1], pos, name, "second shape"), o)));
}
Value fn_intersect_exact(Interp& in, Args a, std::uint32_t p) { return edge_boolean<ugf::intersect_exact>(in, a, p, "intersect_exact"); }
Value fn_unite_exact(Interp& in, Args a, std::uint32_t p) { return edge_boolean<ugf::unite_exact>(in, a, p, "unite_exact"); }
Value fn_subtract_exact(Interp& in, Args a, std::uint32_t p) { return edge_boolean<ugf::subtract_exact>(in, a, p, "subtract_exact"); }
Value fn_intersect_right_angle(Interp& in, Args a, std::uint32_t p) { return two_shapes<ugf::intersect_right_angle>(in, a, p, "intersect_right_angle"); }
Value fn_unite_right_angle(Interp& in, Args a, std::uint32_t p) { return two_shapes<ugf::unite_right_angle>(in, a, p, "unite_right_angle"); }
Value fn_subtract_right_angle(Interp& in, Args a, std::uint32_t p) { return two_shapes<ugf::subtract_right_angle>(in, a, p, "subtract_right_angle"); }

// ---------------------------------------------------------------------------------------------
// Smooth blends: (a, b, k) or (a, b, k, "quadratic" | "cubic" | "exponential" | "root")

template <Field (*F)(const Field&, const Field&, float, ugf::Blend)>
Value blend_fn(Interp& in, Args a, std::uint32_t pos, std::string_view name) {
  if (a.size() != 3 && a.size() != 4) usage(in, name, a, pos, "(a, b, k) or (a, b, k, kind)");
  ugf::Blend kind = ugf::Blend::Quadratic;
  if (a.size() == 4) {
    const std::string s = a[3].kind() == Kind::Str ? a[3].as<StrObj>().text : "";
    if (s == "quadratic") kind = ugf::Blend::Quadratic;
    else if (s == "cubic") kind = ugf::Blend::Cubic;
    else if (s == "exponential") kind = ugf::Blend::Exponential;
    else if (s == "root") kind = ugf::Blend::Root;
    else in.fail(pos, "`" + std::string(name) + "`: the blend kind is \"quadratic\", \"cubic\", \"exponential\" or \"root\"");
  }
  const float k = number(in, a[2], pos, name, "blend thickness k");
  if (!(k > 0)) in.fail(pos, "`" + std::string(name) + "`: the blend thickness k must be > 0");
  return Value::expr(in.keep(F(field(in, a[0], pos, name, "first shape"), field(in, a[1], pos, name, "second shape"), k, kind)));
}
Value fn_smooth_union(Interp& in, Args a, std::uint32_t p) { return blend_fn<ugf::smooth_union>(in, a, p, "smooth_union"); }
Value fn_smooth_intersection(Interp& in, Args a, std::uint32_t p) { return blend_fn<ugf::smooth_intersection>(in, a, p, "smooth_intersection"); }
Value fn_smooth_difference(Interp& in, Args a, std::uint32_t p) { return blend_fn<ugf::smooth_difference>(in, a, p, "smooth_difference"); }

// ---------------------------------------------------------------------------------------------
// The edge frame, chamfers, rounds, pencils. All take (a, b, ...) and build the frame inside
// (hash-consing makes repeated frames of one edge the same nodes).

ugf::EdgeFrame frame_of(Interp& in, Args a, std::uint32_t pos, std::string_view name, const ugf::EdgeOptions& o) {
  return ugf::edge_frame(shape(in, a[0], pos, name, "first face"), shape(in, a[1], pos, name, "second face"), o);
}

Value fn_edge_frame(Interp& in, Args a, std::uint32_t pos) {
  std::size_t n = a.size();
  const ugf::EdgeOptions o = edge_options(in, a, n, pos, "edge_frame");
  if (n != 2) usage(in, "edge_frame", a, pos, "(a, b) or (a, b, #{ min_angle })");
  const ugf::EdgeFrame f = frame_of(in, a, pos, "edge_frame", o);
  auto* m = new MapObj();
  Value out = Value::heap(m);
  const std::pair<const char*, Expr> items[] = {{"c", f.c},   {"cos_half", f.cos_half}, {"sin_half", f.sin_half},
                                                {"S", f.S},   {"D", f.D},               {"Sn", f.Sn},
                                                {"Dn", f.Dn}, {"valid", f.valid}};
  for (const auto& [k, e] : items) m->items.emplace(k, Value::expr(e.id()));
  return out;
}

// #{ inset: h } | #{ setback: s } | #{ width: w } | #{ setbacks: [sA, sB] }, with exact: bool and
// min_angle (degrees).
ugf::Chamfer chamfer_size(Interp& in, const Value& m, std::uint32_t pos, std::string_view name, ugf::EdgeOptions& o) {
  const char* expected = "a map: #{ inset: h }, #{ setback: s }, #{ width: w } or #{ setbacks: [sA, sB] }";
  if (m.kind() != Kind::Map) in.fail(pos, "`" + std::string(name) + "`: the size is " + expected);
  check_keys(in, m, {"inset", "setback", "width", "setbacks", "exact", "min_angle"}, pos, name);
  ugf::Chamfer c;
  int kinds = 0;
  if (const Value* v = map_item(m, "inset")) c = ugf::Chamfer::inset(number(in, *v, pos, name, "inset")), ++kinds;
  if (const Value* v = map_item(m, "setback")) c = ugf::Chamfer::setback(number(in, *v, pos, name, "setback")), ++kinds;
  if (const Value* v = map_item(m, "width")) c = ugf::Chamfer::width(number(in, *v, pos, name, "width")), ++kinds;
  if (const Value* v = map_item(m, "setbacks")) {
    if (v->kind() != Kind::Array || v->as<ArrayObj>().items.size() != 2)
      in.fail(pos, "`" + std::string(name) + "`: setbacks is an array [sA, sB]");
    const auto& s = v->as<ArrayObj>().items;
    c = ugf::Chamfer::setbacks(number(in, s[0], pos, name, "setback sA"), number(in, s[1], pos, name, "setback sB"));
    ++kinds;
  }
  if (kinds != 1) in.fail(pos, "`" + std::string(name) + "`: the size is " + expected + " (exactly one of them)");
  if (!(c.a >= 0 && c.b >= 0)) in.fail(pos, "`" + std::string(name) + "`: chamfer sizes must be >= 0");
  if (const Value* v = map_item(m, "exact")) {
    if (v->kind() != Kind::Bool) in.fail(pos, "`" + std::string(name) + "`: exact is true or false");
    c.exact = v->as_bool();
  }
  if (const Value* v = map_item(m, "min_angle")) {
    o.min_angle_degrees = number(in, *v, pos, name, "min_angle");
    if (!(o.min_angle_degrees > 0 && o.min_angle_degrees < 90))
      in.fail(pos, "`" + std::string(name) + "`: min_angle must be between 0 and 90 degrees");
  }
  return c;
}

template <Expr (*F)(Expr, Expr, const ugf::Chamfer&, const ugf::EdgeOptions&)>
Value chamfer_fn(Interp& in, Args a, std::uint32_t pos, std::string_view name) {
  if (a.size() != 3) usage(in, name, a, pos, "(a, b, #{ inset | setback | width | setbacks, exact, min_angle })");
  ugf::EdgeOptions o;
  const ugf::Chamfer c = chamfer_size(in, a[2], pos, name, o);
  return Value::expr(F(shape(in, a[0], pos, name, "first face"), shape(in, a[1], pos, name, "second face"), c, o).id());
}
Value fn_chamfer_intersection(Interp& in, Args a, std::uint32_t p) {
  return chamfer_fn<static_cast<Expr (*)(Expr, Expr, const ugf::Chamfer&, const ugf::EdgeOptions&)>(ugf::chamfer_intersection)>(
      in, a, p, "chamfer_intersection");
}
Value fn_chamfer_union(Interp& in, Args a, std::uint32_t p) {
  return chamfer_fn<static_cast<Expr (*)(Expr, Expr, const ugf::Chamfer&, const ugf::EdgeOptions&)>(ugf::chamfer_union)>(
      in, a, p, "chamfer_union");
}

template <Expr (*F)(Expr, Expr, float)>
Value two_shapes_number(Interp& in, Args a, std::uint32_t pos, std::string_view name, const char* what) {
  if (a.size() != 3) usage(in, name, a, pos, (std::string("(a, b, ") + what + ")").c_str());
  return Value::expr(
      F(shape(in, a[0], pos, name, "first shape"), shape(in, a[1], pos, name, "second shape"), number(in, a[2], pos, name, what))
          .id());
}
Value fn_chamfer_union_right_angle(Interp& in, Args a, std::uint32_t p) {
  return two_shapes_number<ugf::chamfer_union_right_angle>(in, a, p, "chamfer_union_right_angle", "setback r");
}
Value fn_chamfer_intersection_right_angle(Interp& in, Args a, std::uint32_t p) {
  return two_shapes_number<ugf::chamfer_intersection_right_angle>(in, a, p, "chamfer_intersection_right_angle", "setback r");
}

template <Expr (*F)(Expr, Expr, float, const ugf::EdgeOptions&)>
Value round_fn(Interp& in, Args a, std::uint32_t pos, std::string_view name) {
  std::size_t n = a.size();
  const ugf::EdgeOptions o = edge_options(in, a, n, pos, name);
  if (n != 3) usage(in, name, a, pos, "(a, b, r) or (a, b, r, #{ min_angle })");
  const float r = number(in, a[2], pos, name, "radius");
  if (!(r >= 0)) in.fail(pos, "`" + std::string(name) + "`: the radius must be >= 0");
  return Value::expr(F(shape(in, a[0], pos, name, "first face"), shape(in, a[1], pos, name, "second face"), r, o).id());
}
Value fn_round_intersection(Interp& in, Args a, std::uint32_t p) {
  return round_fn<static_cast<Expr (*)(Expr, Expr, float, const ugf::EdgeOptions&)>(ugf::round_intersection)>(
      in, a, p, "round_intersection");
}
Value fn_round_union(Interp& in, Args a, std::uint32_t p) {
  return round_fn<static_cast<Expr (*)(Expr, Expr, float, const ugf::EdgeOptions&)>(ugf::round_union)>(in, a, p,
                                                                                                      "round_union");
}

// pencil(a, b, theta), pencil_face(a, b, theta, d), pencil_chamfer(a, b, theta, d); theta in
// radians, like Fidget's sin and cos.
Value pencil_fn(Interp& in, Args a, std::uint32_t pos, std::string_view name, bool with_d) {
  std::size_t n = a.size();
  const ugf::EdgeOptions o = edge_options(in, a, n, pos, name);
  if (n != (with_d ? 4u : 3u)) usage(in, name, a, pos, with_d ? "(a, b, theta, d) or (a, b, theta, d, #{ min_angle })" : "(a, b, theta) or (a, b, theta, #{ min_angle })");
  const ugf::EdgeFrame f = frame_of(in, a, pos, name, o);
  const float theta = number(in, a[2], pos, name, "angle theta (radians)");
  if (!with_d) return Value::expr(ugf::pencil(f, theta).id());
  const float d = number(in, a[3], pos, name, "offset d");
  return Value::expr((name == "pencil_face" ? ugf::pencil_face(f, theta, d) : ugf::pencil_chamfer(f, theta, d)).id());
}
Value fn_pencil(Interp& in, Args a, std::uint32_t p) { return pencil_fn(in, a, p, "pencil", false); }
Value fn_pencil_face(Interp& in, Args a, std::uint32_t p) { return pencil_fn(in, a, p, "pencil_face", true); }
Value fn_pencil_chamfer(Interp& in, Args a, std::uint32_t p) { return pencil_fn(in, a, p, "pencil_chamfer", true); }

// ---------------------------------------------------------------------------------------------
// Two bodies and clearance

Value fn_two_body(Interp& in, Args a, std::uint32_t p) { return two_exprs<ugf::two_body>(in, a, p, "two_body"); }
Value fn_two_body_parameter(Interp& in, Args a, std::uint32_t p) { return two_exprs<ugf::two_body_parameter>(in, a, p, "two_body_parameter"); }
Value fn_midsurface(Interp& in, Args a, std::uint32_t p) { return two_exprs<ugf::midsurface>(in, a, p, "midsurface"); }
Value fn_clearance_field(Interp& in, Args a, std::uint32_t p) { return two_exprs<ugf::clearance_field>(in, a, p, "clearance_field"); }
Value fn_between(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 3) usage(in, "between", a, pos, "(a, b, t in [-1, 1])");
  const float t = number(in, a[2], pos, "between", "t");
  if (!(t >= -1 && t <= 1)) in.fail(pos, "`between`: t must be in [-1, 1] (-1: on a, +1: on b)");
  return Value::expr(ugf::between(shape(in, a[0], pos, "between", "first shape"), shape(in, a[1], pos, "between", "second shape"), t).id());
}

bool vec3_of(const Value& v, float out[3]) {
  if (v.kind() == Kind::Vec && v.as<VecObj>().n == 3) {
    for (int i = 0; i < 3; ++i) out[i] = static_cast<float>(v.as<VecObj>().c[i]);
    return true;
  }
  if (v.kind() != Kind::Array || v.as<ArrayObj>().items.size() != 3) return false;
  for (int i = 0; i < 3; ++i) {
    const Value& e = v.as<ArrayObj>().items[static_cast<std::size_t>(i)];
    if (!e.is_number() || !std::isfinite(e.number())) return false;
    out[i] = static_cast<float>(e.number());
  }
  return true;
}

// find_clearance(a, b, lower, upper[, #{ tolerance, max_boxes }]): a measurement, not a shape;
// returns #{ value, lower_bound, point: [x, y, z], boxes }.
Value fn_find_clearance(Interp& in, Args a, std::uint32_t pos) {
  const char* use = "(a, b, [x0, y0, z0], [x1, y1, z1]) or (a, b, lower, upper, #{ tolerance, max_boxes })";
  if (a.size() != 4 && a.size() != 5) usage(in, "find_clearance", a, pos, use);
  float lo[3], hi[3];
  if (!vec3_of(a[2], lo) || !vec3_of(a[3], hi)) usage(in, "find_clearance", a, pos, use);
  for (int i = 0; i < 3; ++i)
    if (!(lo[i] <= hi[i])) in.fail(pos, "`find_clearance`: the region is empty (lower > upper)");
  ugf::ClearanceOptions o;
  if (a.size() == 5) {
    if (a[4].kind() != Kind::Map) usage(in, "find_clearance", a, pos, use);
    check_keys(in, a[4], {"tolerance", "max_boxes"}, pos, "find_clearance");
    if (const Value* v = map_item(a[4], "tolerance")) o.tolerance = number(in, *v, pos, "find_clearance", "tolerance");
    if (const Value* v = map_item(a[4], "max_boxes")) {
      if (v->kind() != Kind::Int || v->as_int() < 1 || v->as_int() > 100'000'000)
        in.fail(pos, "`find_clearance`: max_boxes is an integer from 1 to 10^8");
      o.max_boxes = static_cast<std::size_t>(v->as_int());
    }
  }
  in.charge(o.max_boxes);  // the search's work, so that a loop of them stops like any runaway
  const ugf::ClearanceResult r =
      ugf::find_clearance(shape(in, a[0], pos, "find_clearance", "first shape"), shape(in, a[1], pos, "find_clearance", "second shape"),
                          {lo[0], hi[0]}, {lo[1], hi[1]}, {lo[2], hi[2]}, o);
  auto* m = new MapObj();
  Value out = Value::heap(m);
  m->depth = 2;
  m->items.emplace("value", Value::real(r.value));
  m->items.emplace("lower_bound", Value::real(r.lower_bound));
  auto* pt = new ArrayObj();
  Value point = Value::heap(pt);
  for (float c : {r.x, r.y, r.z}) pt->items.push_back(Value::real(c));
  m->items.emplace("point", point);
  m->items.emplace("boxes", Value::integer(static_cast<std::int64_t>(r.boxes)));
  return out;
}

// ---------------------------------------------------------------------------------------------
// Normalization, gyroid, medial-axis tracking

Value fn_normalize(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 1 && a.size() != 2) usage(in, "normalize", a, pos, "(shape) or (shape, min_gradient)");
  const float floor = a.size() == 2 ? number(in, a[1], pos, "normalize", "min_gradient") : 1e-12f;
  if (!(floor > 0)) in.fail(pos, "`normalize`: min_gradient must be > 0");
  return Value::expr(ugf::normalize(shape(in, a[0], pos, "normalize", "shape"), floor).id());
}

ugf::GyroidScale gyroid_scale(Interp& in, const Value& v, std::uint32_t pos, std::string_view name) {
  const std::string s = v.kind() == Kind::Str ? v.as<StrObj>().text : "";
  if (s == "sampson") return ugf::GyroidScale::Sampson;
  if (s == "bound") return ugf::GyroidScale::Bound;
  in.fail(pos, "`" + std::string(name) + "`: the scale is \"sampson\" or \"bound\"");
}

float period_arg(Interp& in, const Value& v, std::uint32_t pos, std::string_view name) {
  const float p = number(in, v, pos, name, "period");
  if (!(p > 0)) in.fail(pos, "`" + std::string(name) + "`: the period must be > 0");
  return p;
}

Value fn_gyroid(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 1) usage(in, "gyroid", a, pos, "(period)");
  return Value::expr(ugf::gyroid(in.graph(), period_arg(in, a[0], pos, "gyroid")).id());
}
Value fn_gyroid_normalized(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 1 && a.size() != 2) usage(in, "gyroid_normalized", a, pos, "(period) or (period, \"sampson\" | \"bound\")");
  const auto s = a.size() == 2 ? gyroid_scale(in, a[1], pos, "gyroid_normalized") : ugf::GyroidScale::Sampson;
  return Value::expr(ugf::gyroid_normalized(in.graph(), period_arg(in, a[0], pos, "gyroid_normalized"), s).id());
}
template <Expr (*F)(Graph&, float, float, ugf::GyroidScale)>
Value gyroid_solid(Interp& in, Args a, std::uint32_t pos, std::string_view name, const char* what) {
  if (a.size() != 2 && a.size() != 3)
    usage(in, name, a, pos, (std::string("(period, ") + what + ") or (period, " + what + ", \"sampson\" | \"bound\")").c_str());
  const auto s = a.size() == 3 ? gyroid_scale(in, a[2], pos, name) : ugf::GyroidScale::Sampson;
  return Value::expr(F(in.graph(), period_arg(in, a[0], pos, name), number(in, a[1], pos, name, what), s).id());
}
Value fn_gyroid_network(Interp& in, Args a, std::uint32_t p) { return gyroid_solid<ugf::gyroid_network>(in, a, p, "gyroid_network", "bias"); }
Value fn_gyroid_sheet(Interp& in, Args a, std::uint32_t p) { return gyroid_solid<ugf::gyroid_sheet>(in, a, p, "gyroid_sheet", "thickness"); }

Value fn_track_plane(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 1) usage(in, "track_plane", a, pos, "(shape)");
  return tracked_value(ugf::track_plane(shape(in, a[0], pos, "track_plane", "shape")));
}
Value fn_track(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 2) usage(in, "track", a, pos, "(shape, crease distance)");
  return tracked_value(ugf::track(shape(in, a[0], pos, "track", "shape"), shape(in, a[1], pos, "track", "crease distance")));
}
Value fn_track_sphere(Interp& in, Args a, std::uint32_t pos) {
  float c[3];
  if (a.size() != 2 || !vec3_of(a[0], c)) usage(in, "track_sphere", a, pos, "([cx, cy, cz], radius)");
  return tracked_value(ugf::track_sphere(in.graph(), c[0], c[1], c[2], number(in, a[1], pos, "track_sphere", "radius")));
}
Value fn_negate(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 1) usage(in, "negate", a, pos, "(shape) or (#{ f, m })");
  if (is_tracked(a[0])) return tracked_value(ugf::negate(tracked(in, a[0], pos, "negate")));
  return Value::expr(in.keep(frep::inverse(field(in, a[0], pos, "negate", "shape"))));
}

// Every call is charged one step per node it adds (the symbolic gradients inside most of them
// build nodes in proportion to their arguments' size), so that the step and node limits bound
// scripts that nest them in loops.
template <BuiltinFn F>
Value charged(Interp& in, Args a, std::uint32_t pos) {
  const std::size_t before = in.graph().size();
  Value v = F(in, a, pos);
  in.charge(in.graph().size() - before);
  return v;
}

constexpr Builtin kUgf[] = {
    {"offset", charged<fn_offset>},
    {"shell", charged<fn_shell>},
    {"shell_biased", charged<fn_shell_biased>},
    {"shell_inward", charged<fn_shell_inward>},
    {"shell_outward", charged<fn_shell_outward>},
    {"shell_variable", charged<fn_shell_variable>},
    {"intersect", charged<fn_intersect>},
    {"unite", charged<fn_unite>},
    {"subtract", charged<fn_subtract>},
    {"intersect_exact", charged<fn_intersect_exact>},
    {"unite_exact", charged<fn_unite_exact>},
    {"subtract_exact", charged<fn_subtract_exact>},
    {"intersect_right_angle", charged<fn_intersect_right_angle>},
    {"unite_right_angle", charged<fn_unite_right_angle>},
    {"subtract_right_angle", charged<fn_subtract_right_angle>},
    {"smooth_union", charged<fn_smooth_union>},
    {"smooth_intersection", charged<fn_smooth_intersection>},
    {"smooth_difference", charged<fn_smooth_difference>},
    {"edge_frame", charged<fn_edge_frame>},
    {"chamfer_intersection", charged<fn_chamfer_intersection>},
    {"chamfer_union", charged<fn_chamfer_union>},
    {"chamfer_intersection_right_angle", charged<fn_chamfer_intersection_right_angle>},
    {"chamfer_union_right_angle", charged<fn_chamfer_union_right_angle>},
    {"round_intersection", charged<fn_round_intersection>},
    {"round_union", charged<fn_round_union>},
    {"pencil", charged<fn_pencil>},
    {"pencil_face", charged<fn_pencil_face>},
    {"pencil_chamfer", charged<fn_pencil_chamfer>},
    {"two_body", charged<fn_two_body>},
    {"two_body_parameter", charged<fn_two_body_parameter>},
    {"between", charged<fn_between>},
    {"midsurface", charged<fn_midsurface>},
    {"clearance_field", charged<fn_clearance_field>},
    {"find_clearance", charged<fn_find_clearance>},
    {"normalize", charged<fn_normalize>},
    {"gyroid", charged<fn_gyroid>},
    {"gyroid_normalized", charged<fn_gyroid_normalized>},
    {"gyroid_network", charged<fn_gyroid_network>},
    {"gyroid_sheet", charged<fn_gyroid_sheet>},
    {"track_plane", charged<fn_track_plane>},
    {"track", charged<fn_track>},
    {"track_sphere", charged<fn_track_sphere>},
    {"negate", charged<fn_negate>},
};

}  // namespace

std::span<const Builtin> ugf_builtins() { return kUgf; }

}  // namespace frep::rhai
