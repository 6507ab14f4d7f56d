// Fidget's shape library and small types (vec2/vec3/vec4, axis, plane) for the Rhai reader: the
// call forms and conversions; the shapes themselves are the modeling library's.
//
// Facts relied on (Fidget, crates fidget-shapes and fidget-rhai, read in 2025):
// - Shapes are structs with named, typed fields (f64, Vec2, Vec3, Axis, Plane, Tree, Vec<Tree>)
//   and optional defaults; the function name is the snake_case struct name.
// - Call forms: a map `circle(#{ center: [1, 2], radius: 3 })` (defaults fill missing fields);
//   transforms (one Tree field, first) as `move(shape, #{ offset: [1, 1] })`; two-tree shapes
//   as `difference(a, b)`; single Vec<Tree> shapes as `union(a, b, c)` (up to 8) or one array;
//   shapes whose field types are all distinct take positional arguments in any order, matched
//   by type, optional ones omitted (`circle([1, 2], 3)`, `x.move([1, 1])`); the others take
//   all fields in order (`box([0, 0, 0], [1, 1, 1])`, `blend(a, b, 0.5)`).
// - Positional arguments are classified in the order f64, Vec2, Vec3, Vec4, Vec<Tree>, Tree,
//   Axis, Plane (first that converts). A Vec2 fills a Vec3 field when the shape has no Vec2
//   field and the Vec3 field has a default (z from the default); an Axis fills a Plane field
//   (offset 0) when the shape has no Axis field. A repeated type: the last one wins.
// - Arrays of 2/3/4 numbers convert to Vec2/Vec3/Vec4; a Vec2 converts to a Vec3 in maps, with
//   the field default's z (or 0). An Axis comes from an Axis, a vector (normalized; lengths
//   below 1e-8 or above 1e8 are errors), "x"/"y"/"z" (either case) or the tree x, y or z. A
//   Plane comes from a Plane, an axis (offset 0), or "xy"/"yz"/"zx" (either case); Fidget's
//   constants give "xy" and "zx" the Y axis and "yz" the X axis, reproduced as they are.
// - Formulas: those of the modeling library (frep/model/shapes.hpp, csg.hpp, transform.hpp),
//   which each builtin below calls; move, scale, rotate and the other affine transforms compose
//   into one map before the expression is built, as Fidget does.
// - Defaults: circle center [0, 0] radius 1; sphere center [0, 0, 0] radius 1; move offset 0;
//   scale [1, 1, 1]; scale_uniform 1; reflect plane "yz"; reflect_* offset 0; rotate axis z,
//   angle 0, center 0; rotate_* angle 0, center 0; revolve_y offset 0; extrude_z / loft_z
//   lower 0, upper 1. Rectangle, box, blend and difference have no defaults.
#include <array>
#include <cmath>
#include <utility>

#include "frep/model/csg.hpp"
#include "frep/model/shapes.hpp"
#include "frep/model/transform.hpp"
#include "rhai_interp.hpp"

namespace frep::rhai {

namespace {

using Args = std::span<Value>;

// Fidget's field types, in the order positional arguments are classified.
enum class FT : std::uint8_t { Float, Vec2, Vec3, Vec4, VecTree, Tree, Axis, Plane };
constexpr int kTypes = 8;

const char* ft_name(FT t) {
  static const char* names[] = {"f64", "Vec2", "Vec3", "Vec4", "Vec<Tree>", "Tree", "Axis", "Plane"};
  return names[static_cast<int>(t)];
}

// One argument, converted. v: Float v[0]; VecN v[0..N); Axis v[0..3); Plane axis v[0..3),
// offset v[3].
struct FV {
  FT type = FT::Float;
  double v[4] = {0, 0, 0, 0};
  NodeId tree = kNoNode;
  std::vector<NodeId> trees;
};

struct FieldDef {
  std::string_view name;
  FT type;
  bool has_default = false;
  std::array<double, 4> d = {0, 0, 0, 0};
};

using Build = NodeId (*)(Interp& in, const std::vector<FV>& f, std::uint32_t pos);

struct ShapeDef {
  std::string_view name;   // the Rhai function
  std::string_view title;  // Fidget's struct name, for messages
  std::array<FieldDef, 4> fields;
  int count;
  Build build;
};

// ---------------------------------------------------------------------------------------------
// Conversions (Fidget's FromDynamic)

bool to_float(const Value& v, double& out) {
  if (!v.is_number()) return false;
  out = v.number();
  return true;
}

bool numbers(const Value& v, std::size_t n, double* out) {
  if (v.kind() != Kind::Array) return false;
  const auto& items = v.as<ArrayObj>().items;
  if (items.size() != n) return false;
  for (std::size_t i = 0; i < n; ++i) {
    if (!items[i].is_number()) return false;
    out[i] = items[i].number();
  }
  return true;
}

bool to_vec(const Value& v, int n, double* out) {
  if (v.kind() == Kind::Vec && v.as<VecObj>().n == n) {
    for (int i = 0; i < n; ++i) out[i] = v.as<VecObj>().c[i];
    return true;
  }
  return numbers(v, static_cast<std::size_t>(n), out);
}

// Vec3 from a Vec2 (z from the default), a Vec3, or an array of 2 or 3 numbers.
bool to_vec3(const Value& v, double* out, double default_z) {
  if (to_vec(v, 2, out)) {
    out[2] = default_z;
    return true;
  }
  return to_vec(v, 3, out);
}

bool to_tree(Interp& in, const Value& v, NodeId& out, std::uint32_t pos);

bool to_tree_list(Interp& in, const Value& v, std::vector<NodeId>& out, std::uint32_t pos) {
  if (v.kind() != Kind::Array) return false;
  out.clear();
  in.charge(v.as<ArrayObj>().items.size());
  for (const Value& e : v.as<ArrayObj>().items) {
    NodeId t;
    if (!to_tree(in, e, t, pos)) return false;
    out.push_back(t);
  }
  return true;
}

bool to_tree(Interp& in, const Value& v, NodeId& out, std::uint32_t pos) {
  if (v.kind() == Kind::Expr) {
    out = v.node();
    return true;
  }
  if (v.is_number()) {
    out = in.constant(v.number());
    return true;
  }
  std::vector<NodeId> list;
  if (to_tree_list(in, v, list, pos)) {
    out = in.reduce(Op::Min, list);
    return true;
  }
  return false;
}

// Axis from an Axis, a vector (normalized), a name or the tree x/y/z. Bad lengths are errors.
bool to_axis(Interp& in, const Value& v, double* out, std::uint32_t pos) {
  if (v.kind() == Kind::Axis) {
    for (int i = 0; i < 3; ++i) out[i] = v.as<AxisObj>().v[i];
    return true;
  }
  double c[3];
  if (to_vec3(v, c, 0.0)) {
    const double norm = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    if (std::isnan(norm)) in.fail(pos, "an axis vector cannot have NaN length");
    if (norm < 1e-8) in.fail(pos, "an axis vector is too short (length " + in.text_of(Value::real(norm)) + ")");
    if (norm > 1e8) in.fail(pos, "an axis vector is too long (length " + in.text_of(Value::real(norm)) + ")");
    for (int i = 0; i < 3; ++i) out[i] = c[i] / norm;
    return true;
  }
  int axis = -1;
  if (v.kind() == Kind::Str) {
    const std::string& s = v.as<StrObj>().text;
    if (s == "x" || s == "X") axis = 0;
    if (s == "y" || s == "Y") axis = 1;
    if (s == "z" || s == "Z") axis = 2;
  } else if (v.kind() == Kind::Expr) {
    for (int i = 0; i < 3; ++i)
      if (v.node() == in.var(i)) axis = i;
  }
  if (axis < 0) return false;
  out[0] = out[1] = out[2] = 0;
  out[axis] = 1;
  return true;
}

bool to_plane(Interp& in, const Value& v, double* out, std::uint32_t pos) {
  if (v.kind() == Kind::Plane) {
    for (int i = 0; i < 3; ++i) out[i] = v.as<PlaneObj>().axis[i];
    out[3] = v.as<PlaneObj>().offset;
    return true;
  }
  if (to_axis(in, v, out, pos)) {
    out[3] = 0;
    return true;
  }
  if (v.kind() == Kind::Str) {
    const std::string& s = v.as<StrObj>().text;
    int axis = -1;
    if (s == "xy" || s == "XY") axis = 1;  // Fidget's Plane::XY (axis Y, as written there)
    if (s == "yz" || s == "YZ") axis = 0;
    if (s == "zx" || s == "ZX") axis = 1;
    if (axis < 0) return false;
    out[0] = out[1] = out[2] = out[3] = 0;
    out[axis] = 1;
    return true;
  }
  return false;
}

// Converts to a field's type (maps, transforms): false if the value does not convert.
bool convert(Interp& in, const Value& v, const FieldDef& f, FV& out, std::uint32_t pos) {
  out.type = f.type;
  switch (f.type) {
    case FT::Float: return to_float(v, out.v[0]);
    case FT::Vec2: return to_vec(v, 2, out.v);
    case FT::Vec3: return to_vec3(v, out.v, f.has_default ? f.d[2] : 0.0);
    case FT::Vec4: return to_vec(v, 4, out.v);
    case FT::Tree: return to_tree(in, v, out.tree, pos);
    case FT::VecTree: return to_tree_list(in, v, out.trees, pos);
    case FT::Axis: return to_axis(in, v, out.v, pos);
    case FT::Plane: return to_plane(in, v, out.v, pos);
  }
  return false;
}

// Fidget's value_from_dynamic: the first type the value converts to.
bool classify(Interp& in, const Value& v, FV& out, std::uint32_t pos) {
  if (to_float(v, out.v[0])) out.type = FT::Float;
  else if (to_vec(v, 2, out.v)) out.type = FT::Vec2;
  else if (to_vec(v, 3, out.v)) out.type = FT::Vec3;
  else if (to_vec(v, 4, out.v)) out.type = FT::Vec4;
  else if (to_tree_list(in, v, out.trees, pos)) out.type = FT::VecTree;
  else if (to_tree(in, v, out.tree, pos)) out.type = FT::Tree;
  else if (to_axis(in, v, out.v, pos)) out.type = FT::Axis;
  else if (to_plane(in, v, out.v, pos)) out.type = FT::Plane;
  else return false;
  return true;
}

FV default_of(const FieldDef& f) {
  FV r;
  r.type = f.type;
  for (int i = 0; i < 4; ++i) r.v[i] = f.d[i];
  return r;
}

// ---------------------------------------------------------------------------------------------
// Calling a shape

std::string signature(const ShapeDef& s) {
  std::string out = std::string(s.name) + "(";
  for (int i = 0; i < s.count; ++i) {
    out += (i ? ", " : "") + std::string(s.fields[i].name) + ": " + ft_name(s.fields[i].type);
    if (s.fields[i].has_default) out += " = default";
  }
  return out + ")";
}

Value call_shape(const ShapeDef& s, Interp& in, Args a, std::uint32_t pos) {
  const int n = s.count;
  int tree_fields = 0, defaults = 0, type_count[kTypes] = {};
  bool has_vectree = false;
  for (int i = 0; i < n; ++i) {
    tree_fields += s.fields[i].type == FT::Tree;
    has_vectree |= s.fields[i].type == FT::VecTree;
    defaults += s.fields[i].has_default;
    ++type_count[static_cast<int>(s.fields[i].type)];
  }
  const bool transform = tree_fields == 1 && s.fields[0].type == FT::Tree && !has_vectree;
  const bool binary = tree_fields == 2 && n == 2;
  const bool reduce = n == 1 && s.fields[0].type == FT::VecTree;
  bool unique = true;
  for (int c : type_count) unique &= c <= 1;

  std::vector<FV> f(static_cast<std::size_t>(n));
  auto bad_field = [&](const FieldDef& fd, const Value& v) {
    in.fail(pos, "`" + std::string(s.name) + "`: field `" + std::string(fd.name) + "` must be " + ft_name(fd.type) +
                     ", not " + type_name(v));
  };
  auto from_map = [&](const MapObj& m, int first) {
    for (int i = first; i < n; ++i) {
      const FieldDef& fd = s.fields[i];
      auto it = m.items.find(fd.name);
      if (it != m.items.end()) {
        if (!convert(in, it->second, fd, f[i], pos)) bad_field(fd, it->second);
      } else if (fd.has_default) {
        f[i] = default_of(fd);
      } else {
        in.fail(pos, "field `" + std::string(fd.name) + "` must be provided for " + std::string(s.title));
      }
    }
    for (const auto& kv : m.items) {
      bool known = false;
      for (int i = 0; i < n; ++i) known |= s.fields[i].name == kv.first;
      if (!known) in.fail(pos, "field `" + kv.first + "` is not present in " + std::string(s.title));
    }
  };

  if (a.size() == 1 && a[0].kind() == Kind::Map) {
    from_map(a[0].as<MapObj>(), 0);
  } else if (transform && a.size() == 2 && a[1].kind() == Kind::Map) {
    if (!convert(in, a[0], s.fields[0], f[0], pos)) bad_field(s.fields[0], a[0]);
    from_map(a[1].as<MapObj>(), 1);
  } else if (reduce) {
    if (a.empty()) in.fail(pos, "`" + std::string(s.name) + "` needs at least one shape");
    f[0].type = FT::VecTree;
    if (a.size() == 1 && a[0].kind() == Kind::Array) {
      if (!to_tree_list(in, a[0], f[0].trees, pos)) bad_field(s.fields[0], a[0]);
    } else {
      for (const Value& v : a) {
        NodeId t;
        if (!to_tree(in, v, t, pos)) in.fail(pos, "`" + std::string(s.name) + "` takes shapes, not " + type_name(v));
        f[0].trees.push_back(t);
      }
    }
  } else if (binary && a.size() == 2) {
    for (int i = 0; i < 2; ++i)
      if (!convert(in, a[static_cast<std::size_t>(i)], s.fields[i], f[i], pos)) bad_field(s.fields[i], a[static_cast<std::size_t>(i)]);
  } else if (unique && static_cast<int>(a.size()) >= n - defaults && static_cast<int>(a.size()) <= n) {
    FV slot[kTypes];
    bool have[kTypes] = {};
    for (const Value& v : a) {
      FV c;
      if (!classify(in, v, c, pos))
        in.fail(pos, "`" + std::string(s.name) + "`: cannot use " + type_name(v) + " as any of its argument types");
      const int t = static_cast<int>(c.type);
      slot[t] = std::move(c);  // a repeated type: the last one wins
      have[t] = true;
    }
    auto take = [&](FT t) {
      have[static_cast<int>(t)] = false;
      return std::move(slot[static_cast<int>(t)]);
    };
    for (int i = 0; i < n; ++i) {
      const FieldDef& fd = s.fields[i];
      const int t = static_cast<int>(fd.type);
      if (have[t]) {
        f[i] = take(fd.type);
      } else if (fd.type == FT::Vec3 && have[static_cast<int>(FT::Vec2)] && !type_count[static_cast<int>(FT::Vec2)] && fd.has_default) {
        f[i] = take(FT::Vec2);
        f[i].type = FT::Vec3;
        f[i].v[2] = fd.d[2];
      } else if (fd.type == FT::Plane && have[static_cast<int>(FT::Axis)] && !type_count[static_cast<int>(FT::Axis)]) {
        f[i] = take(FT::Axis);
        f[i].type = FT::Plane;
        f[i].v[3] = 0;
      } else if (fd.type == FT::Tree && have[static_cast<int>(FT::VecTree)] && !type_count[static_cast<int>(FT::VecTree)]) {
        FV list = take(FT::VecTree);  // frep: an array of shapes is their union, as in maps
        f[i].type = FT::Tree;
        f[i].tree = in.reduce(Op::Min, list.trees);
      } else if (fd.has_default) {
        f[i] = default_of(fd);
      } else {
        in.fail(pos, "`" + std::string(s.name) + "`: missing argument of type " + ft_name(fd.type) + " (" +
                         signature(s) + ")");
      }
    }
    for (int t = 0; t < kTypes; ++t)
      if (have[t])
        in.fail(pos, "`" + std::string(s.name) + "` has no argument of type " + ft_name(static_cast<FT>(t)) + " (" +
                         signature(s) + ")");
  } else if (!unique && !binary && !reduce && static_cast<int>(a.size()) == n) {
    for (int i = 0; i < n; ++i) {
      FV c;
      const Value& v = a[static_cast<std::size_t>(i)];
      if (!classify(in, v, c, pos) || c.type != s.fields[i].type)
        in.fail(pos, "`" + std::string(s.name) + "`: argument " + std::to_string(i + 1) + " must be " +
                         ft_name(s.fields[i].type) + ", not " + type_name(v) + " (" + signature(s) + ")");
      f[i] = std::move(c);
    }
  } else {
    in.fail(pos, "`" + std::string(s.name) + "` cannot take " + std::to_string(a.size()) + " argument(s) like these; use " +
                     signature(s) + ", a map of those fields" + (transform ? ", or (shape, map)" : ""));
  }
  return Value::expr(s.build(in, f, pos));
}

// ---------------------------------------------------------------------------------------------
// The shapes

// Each shape calls the modeling library (frep/model/*.hpp): no formulas here.

Vec3 vec3(const FV& f) { return {f.v[0], f.v[1], f.v[2]}; }

NodeId build_circle(Interp& in, const std::vector<FV>& f, std::uint32_t) {
  return in.keep(frep::circle(in.graph(), f[0].v[0], f[0].v[1], f[1].v[0]));
}
NodeId build_sphere(Interp& in, const std::vector<FV>& f, std::uint32_t) {
  return in.keep(frep::sphere(in.graph(), vec3(f[0]), f[1].v[0]));
}
NodeId build_rectangle(Interp& in, const std::vector<FV>& f, std::uint32_t) {
  return in.keep(frep::rectangle(in.graph(), f[0].v[0], f[0].v[1], f[1].v[0], f[1].v[1]));
}
NodeId build_box(Interp& in, const std::vector<FV>& f, std::uint32_t) {
  return in.keep(frep::box(in.graph(), vec3(f[0]), vec3(f[1])));
}

NodeId build_union(Interp& in, const std::vector<FV>& f, std::uint32_t) { return in.reduce(Op::Min, f[0].trees); }
NodeId build_intersection(Interp& in, const std::vector<FV>& f, std::uint32_t) { return in.reduce(Op::Max, f[0].trees); }
NodeId build_inverse(Interp& in, const std::vector<FV>& f, std::uint32_t) { return in.keep(frep::inverse(in.field(f[0].tree))); }
NodeId build_difference(Interp& in, const std::vector<FV>& f, std::uint32_t) {
  return in.keep(frep::subtract(in.field(f[0].tree), in.field(f[1].tree)));
}
NodeId build_blend(Interp& in, const std::vector<FV>& f, std::uint32_t) {
  return in.keep(frep::blend(in.field(f[0].tree), in.field(f[1].tree), f[2].v[0]));
}

// The transforms remap their shape: charged for the nodes they may copy, before copying.
template <class Fn>
NodeId transformed(Interp& in, NodeId tree, Fn&& fn) {
  const frep::Field shape = in.field(tree);
  in.charge_transform(shape);
  return in.keep(fn(shape));
}

NodeId build_move(Interp& in, const std::vector<FV>& f, std::uint32_t) {
  return transformed(in, f[0].tree, [&](const frep::Field& s) { return frep::move(s, vec3(f[1])); });
}
NodeId build_scale(Interp& in, const std::vector<FV>& f, std::uint32_t) {
  return transformed(in, f[0].tree, [&](const frep::Field& s) { return frep::scale(s, vec3(f[1])); });
}
NodeId build_scale_uniform(Interp& in, const std::vector<FV>& f, std::uint32_t) {
  const double k = f[1].v[0];
  return transformed(in, f[0].tree, [&](const frep::Field& s) { return frep::scale(s, {k, k, k}); });
}
NodeId build_reflect(Interp& in, const std::vector<FV>& f, std::uint32_t) {
  return transformed(in, f[0].tree, [&](const frep::Field& s) { return frep::reflect(s, vec3(f[1]), f[1].v[3]); });
}
template <int AXIS>
NodeId build_reflect_axis(Interp& in, const std::vector<FV>& f, std::uint32_t) {
  Vec3 a{0, 0, 0};
  a[AXIS] = 1;
  return transformed(in, f[0].tree, [&](const frep::Field& s) { return frep::reflect(s, a, f[1].v[0]); });
}
NodeId build_rotate(Interp& in, const std::vector<FV>& f, std::uint32_t) {
  return transformed(in, f[0].tree, [&](const frep::Field& s) { return frep::rotate(s, vec3(f[1]), f[2].v[0], vec3(f[3])); });
}
template <int AXIS>
NodeId build_rotate_axis(Interp& in, const std::vector<FV>& f, std::uint32_t) {
  Vec3 a{0, 0, 0};
  a[AXIS] = 1;
  return transformed(in, f[0].tree, [&](const frep::Field& s) { return frep::rotate(s, a, f[1].v[0], vec3(f[2])); });
}
NodeId build_revolve_y(Interp& in, const std::vector<FV>& f, std::uint32_t) {
  return transformed(in, f[0].tree, [&](const frep::Field& s) { return frep::revolve_y(s, f[1].v[0]); });
}
NodeId build_extrude_z(Interp& in, const std::vector<FV>& f, std::uint32_t) {
  return transformed(in, f[0].tree, [&](const frep::Field& s) { return frep::extrude_z(s, f[1].v[0], f[2].v[0]); });
}
NodeId build_loft_z(Interp& in, const std::vector<FV>& f, std::uint32_t) {
  const frep::Field b = in.field(f[1].tree);
  in.charge_transform(b);
  return transformed(in, f[0].tree, [&](const frep::Field& a) { return frep::loft_z(a, b, f[2].v[0], f[3].v[0]); });
}

constexpr FieldDef req(std::string_view n, FT t) { return {n, t, false, {0, 0, 0, 0}}; }
constexpr FieldDef opt(std::string_view n, FT t, double a, double b = 0, double c = 0, double d = 0) {
  return {n, t, true, {a, b, c, d}};
}

constexpr ShapeDef kShapes[] = {
    {"circle", "Circle", {opt("center", FT::Vec2, 0, 0), opt("radius", FT::Float, 1)}, 2, build_circle},
    {"rectangle", "Rectangle", {req("lower", FT::Vec2), req("upper", FT::Vec2)}, 2, build_rectangle},
    {"sphere", "Sphere", {opt("center", FT::Vec3, 0, 0, 0), opt("radius", FT::Float, 1)}, 2, build_sphere},
    {"box", "Box", {req("lower", FT::Vec3), req("upper", FT::Vec3)}, 2, build_box},
    {"move", "Move", {req("shape", FT::Tree), opt("offset", FT::Vec3, 0, 0, 0)}, 2, build_move},
    {"scale", "Scale", {req("shape", FT::Tree), opt("scale", FT::Vec3, 1, 1, 1)}, 2, build_scale},
    {"scale_uniform", "ScaleUniform", {req("shape", FT::Tree), opt("scale", FT::Float, 1)}, 2, build_scale_uniform},
    {"reflect", "Reflect", {req("shape", FT::Tree), opt("plane", FT::Plane, 1, 0, 0, 0)}, 2, build_reflect},
    {"reflect_x", "ReflectX", {req("shape", FT::Tree), opt("offset", FT::Float, 0)}, 2, build_reflect_axis<0>},
    {"reflect_y", "ReflectY", {req("shape", FT::Tree), opt("offset", FT::Float, 0)}, 2, build_reflect_axis<1>},
    {"reflect_z", "ReflectZ", {req("shape", FT::Tree), opt("offset", FT::Float, 0)}, 2, build_reflect_axis<2>},
    {"rotate", "Rotate",
     {req("shape", FT::Tree), opt("axis", FT::Axis, 0, 0, 1), opt("angle", FT::Float, 0), opt("center", FT::Vec3, 0, 0, 0)},
     4, build_rotate},
    {"rotate_x", "RotateX", {req("shape", FT::Tree), opt("angle", FT::Float, 0), opt("center", FT::Vec3, 0, 0, 0)}, 3, build_rotate_axis<0>},
    {"rotate_y", "RotateY", {req("shape", FT::Tree), opt("angle", FT::Float, 0), opt("center", FT::Vec3, 0, 0, 0)}, 3, build_rotate_axis<1>},
    {"rotate_z", "RotateZ", {req("shape", FT::Tree), opt("angle", FT::Float, 0), opt("center", FT::Vec3, 0, 0, 0)}, 3, build_rotate_axis<2>},
    {"revolve_y", "RevolveY", {req("shape", FT::Tree), opt("offset", FT::Float, 0)}, 2, build_revolve_y},
    {"extrude_z", "ExtrudeZ", {req("shape", FT::Tree), opt("lower", FT::Float, 0), opt("upper", FT::Float, 1)}, 3, build_extrude_z},
    {"loft_z", "LoftZ", {req("a", FT::Tree), req("b", FT::Tree), opt("lower", FT::Float, 0), opt("upper", FT::Float, 1)}, 4, build_loft_z},
    {"union", "Union", {req("input", FT::VecTree)}, 1, build_union},
    {"blend", "Blend", {req("a", FT::Tree), req("b", FT::Tree), req("radius", FT::Float)}, 3, build_blend},
    {"intersection", "Intersection", {req("input", FT::VecTree)}, 1, build_intersection},
    {"difference", "Difference", {req("shape", FT::Tree), req("cutout", FT::Tree)}, 2, build_difference},
    {"inverse", "Inverse", {req("shape", FT::Tree)}, 1, build_inverse},
};

template <int I>
Value shape_fn(Interp& in, Args a, std::uint32_t pos) {
  return call_shape(kShapes[I], in, a, pos);
}

// ---------------------------------------------------------------------------------------------
// Fidget's types

Value fn_vec(Interp& in, Args a, std::uint32_t pos, int n) {
  const std::string name = "vec" + std::to_string(n);
  double c[4] = {0, 0, 0, 0};
  if (a.size() == 1) {
    if ((n == 3 && to_vec3(a[0], c, 0.0)) || to_vec(a[0], n, c)) return make_vec(n, c[0], c[1], c[2], c[3]);
  } else if (static_cast<int>(a.size()) == n) {
    bool ok = true;
    for (int i = 0; i < n; ++i) ok &= to_float(a[static_cast<std::size_t>(i)], c[i]);
    if (ok) return make_vec(n, c[0], c[1], c[2], c[3]);
  }
  in.fail(pos, "`" + name + "` takes " + std::to_string(n) + " numbers or one array of them");
}
Value fn_vec2(Interp& in, Args a, std::uint32_t pos) { return fn_vec(in, a, pos, 2); }
Value fn_vec3(Interp& in, Args a, std::uint32_t pos) { return fn_vec(in, a, pos, 3); }
Value fn_vec4(Interp& in, Args a, std::uint32_t pos) { return fn_vec(in, a, pos, 4); }

Value fn_axis(Interp& in, Args a, std::uint32_t pos) {
  double v[3];
  if (a.size() != 1 || !to_axis(in, a[0], v, pos))
    in.fail(pos, "`axis` takes a vector, \"x\", \"y\", \"z\" or one of the trees x, y, z");
  return Value::heap(new AxisObj(v[0], v[1], v[2]));
}

// plane(axis-like or name), plane(axis-like, offset), plane(#{ axis, offset }), or the
// positional pair in either order. The result is a Plane value; where a tree is needed it
// becomes Fidget's plane shape x a.x + y a.y + z a.z - offset.
Value fn_plane(Interp& in, Args a, std::uint32_t pos) {
  double p[4];
  const char* usage = "`plane` takes an axis or plane name, (axis, offset), or #{ axis: ..., offset: ... }";
  if (a.size() == 1 && a[0].kind() == Kind::Map) {
    const auto& m = a[0].as<MapObj>().items;
    auto ax = m.find("axis");
    auto off = m.find("offset");
    if (ax == m.end() || off == m.end() || m.size() != 2 || !to_axis(in, ax->second, p, pos) || !to_float(off->second, p[3]))
      in.fail(pos, usage);
  } else if (a.size() == 1) {
    if (!to_plane(in, a[0], p, pos)) in.fail(pos, usage);
  } else if (a.size() == 2) {
    if (a[1].is_number() && to_plane(in, a[0], p, pos)) {
      p[3] = a[1].number();
    } else if (a[0].is_number() && to_axis(in, a[1], p, pos)) {
      p[3] = a[0].number();
    } else {
      in.fail(pos, usage);
    }
  } else {
    in.fail(pos, usage);
  }
  return Value::heap(new PlaneObj(p, p[3]));
}

// mesh("part.stl"): a mesh file's exact signed distance (frep's own; Fidget has no meshes).
Value fn_mesh(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 1 || a[0].kind() != Kind::Str) in.fail(pos, "`mesh` takes one string: the mesh file's name");
  return Value::expr(in.mesh(std::string(a[0].as<StrObj>().text), pos));
}

constexpr std::size_t kShapeCount = std::size(kShapes);

template <std::size_t... I>
constexpr std::array<Builtin, kShapeCount + 6> make_builtins(std::index_sequence<I...>) {
  return {Builtin{kShapes[I].name, shape_fn<static_cast<int>(I)>}..., Builtin{"vec2", fn_vec2}, Builtin{"vec3", fn_vec3},
          Builtin{"vec4", fn_vec4}, Builtin{"axis", fn_axis}, Builtin{"plane", fn_plane}, Builtin{"mesh", fn_mesh}};
}
constexpr auto kShapeBuiltins = make_builtins(std::make_index_sequence<kShapeCount>{});

}  // namespace

std::span<const Builtin> shape_builtins() { return kShapeBuiltins; }

}  // namespace frep::rhai
