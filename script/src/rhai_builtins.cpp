// Builtin functions of the Rhai reader: Fidget's tree functions (every opcode by name, remap,
// axes, draw), math on plain numbers, and the parts of Rhai's standard library that modeling
// scripts use (strings, arrays, maps, ranges). Fidget's shapes and types are in rhai_shapes.cpp.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include "frep/expr/semantics.hpp"
#include "rhai_interp.hpp"
#include "rhai_operators.hpp"
#include "frep/util/parse_number.hpp"

namespace frep::rhai {

namespace {

using Args = std::span<Value>;

[[noreturn]] void wrong_args(Interp& in, std::string_view name, Args a, std::uint32_t pos, const char* expected) {
  std::string got;
  constexpr std::size_t kShown = 8;  // a call with 100,000 arguments gets a short message
  for (std::size_t i = 0; i < a.size() && i < kShown; ++i) got += (got.empty() ? "" : ", ") + std::string(type_name(a[i]));
  if (a.size() > kShown) got += ", ... (" + std::to_string(a.size()) + " arguments)";
  in.fail(pos, "`" + std::string(name) + "` takes " + expected + ", not (" + got + ")");
}

void need(Interp& in, std::string_view name, Args a, std::size_t n, std::uint32_t pos, const char* expected) {
  if (a.size() != n) wrong_args(in, name, a, pos, expected);
}

double number(Interp& in, std::string_view name, Args a, std::size_t i, std::uint32_t pos) {
  if (!a[i].is_number()) wrong_args(in, name, a, pos, "numbers");
  return a[i].number();
}

// ---------------------------------------------------------------------------------------------
// Opcodes as functions. On expressions (or with an expression argument) they build nodes; on
// plain numbers they compute, with the opcode's semantics in f64.

template <Op OP>
Value unary_fn(Interp& in, Args a, std::uint32_t pos) {
  constexpr std::string_view name = op_name(OP);
  need(in, name, a, 1, pos, "one argument");
  const Value& v = a[0];
  switch (v.kind()) {
    case Kind::Expr:
    case Kind::Array:
    case Kind::Plane: return Value::expr(in.unary(OP, in.to_expr(v, pos, "the argument of `" + std::string(name) + "`")));
    case Kind::Int: {
      const std::int64_t i = v.as_int();
      if (OP == Op::Floor || OP == Op::Ceil || OP == Op::Round) return v;
      if (OP == Op::Abs) {
        if (i == INT64_MIN) in.fail(pos, "arithmetic overflow in `abs`");
        return Value::integer(i < 0 ? -i : i);
      }
      if (OP == Op::Neg) return negate(in, v, pos);
      if (OP == Op::Square) return Value::integer(int_arith(in, BinOp::Mul, i, i, pos));
      return Value::real(op_eval<double>(OP, static_cast<double>(i), 0.0));
    }
    case Kind::Float: return Value::real(op_eval<double>(OP, v.as_float(), 0.0));
    case Kind::Vec:
      if (OP == Op::Abs || OP == Op::Sqrt || OP == Op::Neg) {  // Fidget's vector functions
        const VecObj& o = v.as<VecObj>();
        double c[4];
        for (int k = 0; k < 4; ++k) c[k] = op_eval<double>(OP, o.c[k], 0.0);
        return make_vec(o.n, c[0], c[1], c[2], c[3]);
      }
      break;
    default: break;
  }
  wrong_args(in, name, a, pos, "a number or an expression");
}

template <Op OP>
Value binary_fn(Interp& in, Args a, std::uint32_t pos) {
  std::string_view name = op_name(OP);
  if (OP == Op::Atan2) name = "atan2";
  need(in, name, a, 2, pos, "two arguments");
  const Value &x = a[0], &y = a[1];
  if (x.kind() == Kind::Expr || y.kind() == Kind::Expr) {
    const NodeId p = in.to_expr(x, pos, "the first argument of `" + std::string(name) + "`");
    const NodeId q = in.to_expr(y, pos, "the second argument of `" + std::string(name) + "`");
    return Value::expr(in.binary(OP, p, q));
  }
  if (x.is_number() && y.is_number()) {
    if ((OP == Op::Min || OP == Op::Max) && x.kind() == Kind::Int && y.kind() == Kind::Int)
      return Value::integer(OP == Op::Min ? std::min(x.as_int(), y.as_int()) : std::max(x.as_int(), y.as_int()));
    return Value::real(op_eval<double>(OP, x.number(), y.number()));
  }
  if ((OP == Op::Min || OP == Op::Max) && (x.kind() == Kind::Vec || y.kind() == Kind::Vec)) {
    const bool vx = x.kind() == Kind::Vec, vy = y.kind() == Kind::Vec;
    const int n = vx ? x.as<VecObj>().n : y.as<VecObj>().n;
    if ((vx && vy && x.as<VecObj>().n != y.as<VecObj>().n) || (!vx && !x.is_number()) || (!vy && !y.is_number()))
      wrong_args(in, name, a, pos, "two vectors of the same size, or a vector and a number");
    double c[4] = {0, 0, 0, 0};
    for (int k = 0; k < n; ++k)
      c[k] = op_eval<double>(OP, vx ? x.as<VecObj>().c[k] : x.number(), vy ? y.as<VecObj>().c[k] : y.number());
    return make_vec(n, c[0], c[1], c[2], c[3]);
  }
  if (x.kind() == Kind::Array || y.kind() == Kind::Array)
    wrong_args(in, name, a, pos, "numbers or expressions (an array becomes the union of its shapes only next to an expression)");
  wrong_args(in, name, a, pos, "numbers or expressions");
}

// ---------------------------------------------------------------------------------------------
// Fidget's tree functions

Value fn_remap(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 3 && a.size() != 4) wrong_args(in, "remap", a, pos, "(shape, x, y) or (shape, x, y, z)");
  const NodeId e = in.to_expr(a[0], pos, "the shape to remap");
  const NodeId x = in.to_expr(a[1], pos, "the new x");
  const NodeId y = in.to_expr(a[2], pos, "the new y");
  const NodeId z = a.size() == 4 ? in.to_expr(a[3], pos, "the new z") : in.var(2);
  return Value::expr(in.remap(e, x, y, z));
}

// Older Fidget (and its own models/cabin.rhai and sponge.rhai) spells the 3-axis form remap_xyz.
Value fn_remap_xyz(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 4) wrong_args(in, "remap_xyz", a, pos, "(shape, x, y, z)");
  return fn_remap(in, a, pos);
}

Value fn_axes(Interp& in, Args a, std::uint32_t pos) {
  need(in, "axes", a, 0, pos, "no arguments");
  auto* m = new MapObj();
  Value out = Value::heap(m);
  m->items.emplace("x", Value::expr(in.var(0)));
  m->items.emplace("y", Value::expr(in.var(1)));
  m->items.emplace("z", Value::expr(in.var(2)));
  return out;
}

Value fn_draw(Interp& in, Args a, std::uint32_t pos) {
  need(in, "draw", a, 1, pos, "one shape");
  in.draw(in.to_expr(a[0], pos, "the shape to draw"));
  return Value();
}

Value fn_draw_rgb(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 4 || !a[1].is_number() || !a[2].is_number() || !a[3].is_number())
    wrong_args(in, "draw_rgb", a, pos, "(shape, r, g, b)");
  in.draw(in.to_expr(a[0], pos, "the shape to draw"));  // frep draws one field: the color is dropped
  return Value();
}

// ---------------------------------------------------------------------------------------------
// Numbers

template <double (*F)(double)>
Value real_fn(Interp& in, Args a, std::uint32_t pos, std::string_view name) {
  need(in, name, a, 1, pos, "one number");
  return Value::real(F(number(in, name, a, 0, pos)));
}

Value fn_log(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() == 1) return Value::real(std::log10(number(in, "log", a, 0, pos)));
  need(in, "log", a, 2, pos, "(number) or (number, base)");
  return Value::real(std::log(number(in, "log", a, 0, pos)) / std::log(number(in, "log", a, 1, pos)));
}

Value fn_sinh(Interp& in, Args a, std::uint32_t p) { return real_fn<static_cast<double (*)(double)>(std::sinh)>(in, a, p, "sinh"); }
Value fn_cosh(Interp& in, Args a, std::uint32_t p) { return real_fn<static_cast<double (*)(double)>(std::cosh)>(in, a, p, "cosh"); }
Value fn_tanh(Interp& in, Args a, std::uint32_t p) { return real_fn<static_cast<double (*)(double)>(std::tanh)>(in, a, p, "tanh"); }
Value fn_fraction(Interp& in, Args a, std::uint32_t p) {
  need(in, "fraction", a, 1, p, "one number");
  const double v = number(in, "fraction", a, 0, p);
  return Value::real(v - std::trunc(v));
}

Value fn_sign(Interp& in, Args a, std::uint32_t pos) {
  need(in, "sign", a, 1, pos, "one number");
  if (a[0].kind() == Kind::Int) return Value::integer((a[0].as_int() > 0) - (a[0].as_int() < 0));
  const double v = number(in, "sign", a, 0, pos);
  if (std::isnan(v)) in.fail(pos, "`sign` of NaN");
  return Value::integer((v > 0) - (v < 0));
}

Value fn_is_nan(Interp& in, Args a, std::uint32_t pos) {
  need(in, "is_nan", a, 1, pos, "one number");
  return Value::boolean(std::isnan(number(in, "is_nan", a, 0, pos)));
}
Value fn_is_finite(Interp& in, Args a, std::uint32_t pos) {
  need(in, "is_finite", a, 1, pos, "one number");
  return Value::boolean(std::isfinite(number(in, "is_finite", a, 0, pos)));
}
Value fn_is_infinite(Interp& in, Args a, std::uint32_t pos) {
  need(in, "is_infinite", a, 1, pos, "one number");
  return Value::boolean(std::isinf(number(in, "is_infinite", a, 0, pos)));
}

Value fn_to_int(Interp& in, Args a, std::uint32_t pos) {
  need(in, "to_int", a, 1, pos, "one number");
  if (a[0].kind() == Kind::Int) return a[0];
  const double v = std::trunc(number(in, "to_int", a, 0, pos));
  if (!(v >= -9.2233720368547758e18 && v < 9.2233720368547758e18))
    in.fail(pos, "`to_int`: " + in.text_of(a[0]) + " is out of the integer range");
  return Value::integer(static_cast<std::int64_t>(v));
}

Value fn_to_float(Interp& in, Args a, std::uint32_t pos) {
  need(in, "to_float", a, 1, pos, "one number");
  return Value::real(number(in, "to_float", a, 0, pos));
}

Value fn_pi(Interp& in, Args a, std::uint32_t pos) {
  need(in, "PI", a, 0, pos, "no arguments");
  return Value::real(3.14159265358979323846);
}
Value fn_e(Interp& in, Args a, std::uint32_t pos) {
  need(in, "E", a, 0, pos, "no arguments");
  return Value::real(2.71828182845904523536);
}

// ---------------------------------------------------------------------------------------------
// Strings

Value fn_parse_float(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 1 || a[0].kind() != Kind::Str) wrong_args(in, "parse_float", a, pos, "one string");
  std::string_view s = a[0].as<StrObj>().text;
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\n' || s.front() == '\r')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\n' || s.back() == '\r')) s.remove_suffix(1);
  double v = 0;
  if (!parse_real(s, v)) in.fail(pos, "`parse_float`: \"" + std::string(a[0].as<StrObj>().text) + "\" is not a number");
  return Value::real(v);
}

Value fn_parse_int(Interp& in, Args a, std::uint32_t pos) {
  if (a.empty() || a.size() > 2 || a[0].kind() != Kind::Str || (a.size() == 2 && a[1].kind() != Kind::Int))
    wrong_args(in, "parse_int", a, pos, "(string) or (string, radix)");
  const int radix = a.size() == 2 ? static_cast<int>(a[1].as_int()) : 10;
  if (radix < 2 || radix > 36) in.fail(pos, "`parse_int`: radix must be between 2 and 36");
  std::string_view s = a[0].as<StrObj>().text;
  while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
  while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  std::int64_t v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v, radix);
  if (s.empty() || r.ec != std::errc() || r.ptr != s.data() + s.size())
    in.fail(pos, "`parse_int`: \"" + std::string(a[0].as<StrObj>().text) + "\" is not an integer");
  return Value::integer(v);
}

Value fn_to_string(Interp& in, Args a, std::uint32_t pos) {
  need(in, "to_string", a, 1, pos, "one value");
  return make_string(in.text_of(a[0]));
}

Value fn_type_of(Interp& in, Args a, std::uint32_t pos) {
  need(in, "type_of", a, 1, pos, "one value");
  return make_string(type_name(a[0]));
}

// print and debug write nothing: a reader must not write to the terminal.
Value fn_print(Interp&, Args, std::uint32_t) { return Value(); }

// ---------------------------------------------------------------------------------------------
// Arrays, maps, ranges

Value fn_len(Interp& in, Args a, std::uint32_t pos) {
  need(in, "len", a, 1, pos, "one array, map or string");
  switch (a[0].kind()) {
    case Kind::Array: return Value::integer(static_cast<std::int64_t>(a[0].as<ArrayObj>().items.size()));
    case Kind::Map: return Value::integer(static_cast<std::int64_t>(a[0].as<MapObj>().items.size()));
    case Kind::Str: {
      in.charge(a[0].as<StrObj>().text.size() / 16);
      std::int64_t n = 0;
      for (unsigned char c : a[0].as<StrObj>().text) n += (c & 0xC0) != 0x80;
      return Value::integer(n);
    }
    default: wrong_args(in, "len", a, pos, "an array, a map or a string");
  }
}

Value fn_is_empty(Interp& in, Args a, std::uint32_t pos) {
  const Value n = fn_len(in, a, pos);
  return Value::boolean(n.as_int() == 0);
}

Value fn_contains(Interp& in, Args a, std::uint32_t pos) {
  need(in, "contains", a, 2, pos, "(container, item)");
  return binary_op(in, BinOp::In, a[1], a[0], pos);
}

ArrayObj& array_arg(Interp& in, std::string_view name, Args a, std::uint32_t pos, const char* expected) {
  if (a.empty() || a[0].kind() != Kind::Array) wrong_args(in, name, a, pos, expected);
  return in.own_array(a[0]);
}

std::size_t index_arg(Interp& in, const Value& v, std::size_t size, bool allow_end, std::uint32_t pos) {
  if (v.kind() != Kind::Int) in.fail(pos, std::string("an array position must be an integer, not ") + type_name(v));
  std::int64_t i = v.as_int();
  const auto n = static_cast<std::int64_t>(size);
  if (i < 0) i += n;
  if (i < 0 || i > n || (!allow_end && i == n))
    in.fail(pos, "array position " + std::to_string(v.as_int()) + " out of bounds (length " + std::to_string(size) + ")");
  return static_cast<std::size_t>(i);
}

Value fn_push(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 2) wrong_args(in, "push", a, pos, "(array, item)");
  ArrayObj& arr = array_arg(in, "push", a, pos, "(array, item)");
  arr.depth = std::max(arr.depth, value_depth(a[1]) + 1);
  in.check_depth(arr.depth, pos);
  arr.items.push_back(a[1]);
  return Value();
}

Value fn_append(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 2 || a[1].kind() != Kind::Array) wrong_args(in, "append", a, pos, "(array, array)");
  ArrayObj& arr = array_arg(in, "append", a, pos, "(array, array)");
  const Value more = a[1];
  in.charge(more.as<ArrayObj>().items.size());
  arr.items.insert(arr.items.end(), more.as<ArrayObj>().items.begin(), more.as<ArrayObj>().items.end());
  arr.depth = std::max(arr.depth, more.as<ArrayObj>().depth);
  return Value();
}

Value fn_pop(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 1) wrong_args(in, "pop", a, pos, "(array)");
  ArrayObj& arr = array_arg(in, "pop", a, pos, "(array)");
  if (arr.items.empty()) return Value();
  Value v = std::move(arr.items.back());
  arr.items.pop_back();
  return v;
}

Value fn_insert(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 3) wrong_args(in, "insert", a, pos, "(array, position, item)");
  ArrayObj& arr = array_arg(in, "insert", a, pos, "(array, position, item)");
  const std::size_t i = index_arg(in, a[1], arr.items.size(), true, pos);
  arr.depth = std::max(arr.depth, value_depth(a[2]) + 1);
  in.check_depth(arr.depth, pos);
  in.charge(arr.items.size() - i);
  arr.items.insert(arr.items.begin() + static_cast<std::ptrdiff_t>(i), a[2]);
  return Value();
}

Value fn_remove(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 2) wrong_args(in, "remove", a, pos, "(array, position) or (map, key)");
  if (a[0].kind() == Kind::Map) {
    if (a[1].kind() != Kind::Str) wrong_args(in, "remove", a, pos, "(map, key)");
    MapObj& m = in.own_map(a[0]);
    auto it = m.items.find(a[1].as<StrObj>().text);
    if (it == m.items.end()) return Value();
    Value v = std::move(it->second);
    m.items.erase(it);
    return v;
  }
  ArrayObj& arr = array_arg(in, "remove", a, pos, "(array, position) or (map, key)");
  const std::size_t i = index_arg(in, a[1], arr.items.size(), false, pos);
  in.charge(arr.items.size() - i);
  Value v = std::move(arr.items[i]);
  arr.items.erase(arr.items.begin() + static_cast<std::ptrdiff_t>(i));
  return v;
}

Value fn_clear(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() == 1 && a[0].kind() == Kind::Map) {
    in.own_map(a[0]).items.clear();
    return Value();
  }
  if (a.size() != 1) wrong_args(in, "clear", a, pos, "(array) or (map)");
  array_arg(in, "clear", a, pos, "(array) or (map)").items.clear();
  return Value();
}

Value fn_reverse(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 1) wrong_args(in, "reverse", a, pos, "(array)");
  ArrayObj& arr = array_arg(in, "reverse", a, pos, "(array)");
  in.charge(arr.items.size());
  std::reverse(arr.items.begin(), arr.items.end());
  return Value();
}

Value fn_truncate(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 2 || a[1].kind() != Kind::Int) wrong_args(in, "truncate", a, pos, "(array, length)");
  ArrayObj& arr = array_arg(in, "truncate", a, pos, "(array, length)");
  const std::int64_t n = std::max<std::int64_t>(a[1].as_int(), 0);
  if (static_cast<std::uint64_t>(n) < arr.items.size()) arr.items.resize(static_cast<std::size_t>(n));
  return Value();
}

Value fn_keys(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 1 || a[0].kind() != Kind::Map) wrong_args(in, "keys", a, pos, "(map)");
  auto* arr = new ArrayObj();
  Value out = Value::heap(arr);
  in.charge(a[0].as<MapObj>().items.size());
  for (const auto& kv : a[0].as<MapObj>().items) arr->items.push_back(make_string(kv.first));
  return out;
}

Value fn_values(Interp& in, Args a, std::uint32_t pos) {
  if (a.size() != 1 || a[0].kind() != Kind::Map) wrong_args(in, "values", a, pos, "(map)");
  auto* arr = new ArrayObj();
  Value out = Value::heap(arr);
  in.charge(a[0].as<MapObj>().items.size());
  for (const auto& kv : a[0].as<MapObj>().items) arr->items.push_back(kv.second);
  arr->depth = a[0].as<MapObj>().depth;
  return out;
}

Value fn_range(Interp& in, Args a, std::uint32_t pos) {
  if ((a.size() != 2 && a.size() != 3) || a[0].kind() != Kind::Int || a[1].kind() != Kind::Int ||
      (a.size() == 3 && a[2].kind() != Kind::Int))
    wrong_args(in, "range", a, pos, "(from, to) or (from, to, step), integers");
  const std::int64_t step = a.size() == 3 ? a[2].as_int() : 1;
  if (step == 0) in.fail(pos, "`range` step cannot be zero");
  return Value::heap(new RangeObj(a[0].as_int(), a[1].as_int(), step));
}

constexpr Builtin kCore[] = {
    // Fidget's opcodes by name (neg, recip and mod are frep additions: Fidget writes -a, 1/a, a % b)
    {"abs", unary_fn<Op::Abs>},
    {"sqrt", unary_fn<Op::Sqrt>},
    {"square", unary_fn<Op::Square>},
    {"floor", unary_fn<Op::Floor>},
    {"ceil", unary_fn<Op::Ceil>},
    {"ceiling", unary_fn<Op::Ceil>},
    {"round", unary_fn<Op::Round>},
    {"sin", unary_fn<Op::Sin>},
    {"cos", unary_fn<Op::Cos>},
    {"tan", unary_fn<Op::Tan>},
    {"asin", unary_fn<Op::Asin>},
    {"acos", unary_fn<Op::Acos>},
    {"atan", unary_fn<Op::Atan>},
    {"exp", unary_fn<Op::Exp>},
    {"ln", unary_fn<Op::Ln>},
    {"not", unary_fn<Op::Not>},
    {"neg", unary_fn<Op::Neg>},
    {"recip", unary_fn<Op::Recip>},
    {"min", binary_fn<Op::Min>},
    {"max", binary_fn<Op::Max>},
    {"compare", binary_fn<Op::Compare>},
    {"and", binary_fn<Op::And>},
    {"or", binary_fn<Op::Or>},
    {"atan2", binary_fn<Op::Atan2>},
    {"mod", binary_fn<Op::Mod>},
    {"remap", fn_remap},
    {"remap_xyz", fn_remap_xyz},
    {"axes", fn_axes},
    {"draw", fn_draw},
    {"draw_rgb", fn_draw_rgb},
    // numbers
    {"log", fn_log},
    {"sinh", fn_sinh},
    {"cosh", fn_cosh},
    {"tanh", fn_tanh},
    {"fraction", fn_fraction},
    {"sign", fn_sign},
    {"is_nan", fn_is_nan},
    {"is_finite", fn_is_finite},
    {"is_infinite", fn_is_infinite},
    {"to_int", fn_to_int},
    {"to_float", fn_to_float},
    {"PI", fn_pi},
    {"E", fn_e},
    // strings and values
    {"parse_float", fn_parse_float},
    {"parse_int", fn_parse_int},
    {"to_string", fn_to_string},
    {"type_of", fn_type_of},
    {"print", fn_print},
    {"debug", fn_print},
    // arrays, maps, ranges
    {"len", fn_len},
    {"is_empty", fn_is_empty},
    {"contains", fn_contains},
    {"push", fn_push, true},
    {"append", fn_append, true},
    {"pop", fn_pop, true},
    {"insert", fn_insert, true},
    {"remove", fn_remove, true},
    {"clear", fn_clear, true},
    {"reverse", fn_reverse, true},
    {"truncate", fn_truncate, true},
    {"keys", fn_keys},
    {"values", fn_values},
    {"range", fn_range},
};

}  // namespace

std::span<const Builtin> core_builtins() { return kCore; }

}  // namespace frep::rhai
