// Rhai's operators on values (see rhai_operators.hpp).
#include "rhai_operators.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "rhai_interp.hpp"

namespace frep::rhai {

namespace {

const char* op_symbol(BinOp op) {
  switch (op) {
    case BinOp::Add: return "+";
    case BinOp::Sub: return "-";
    case BinOp::Mul: return "*";
    case BinOp::Div: return "/";
    case BinOp::Rem: return "%";
    case BinOp::Pow: return "**";
    case BinOp::Shl: return "<<";
    case BinOp::Shr: return ">>";
    case BinOp::BitAnd: return "&";
    case BinOp::BitOr: return "|";
    case BinOp::BitXor: return "^";
    case BinOp::Eq: return "==";
    case BinOp::Ne: return "!=";
    case BinOp::Lt: return "<";
    case BinOp::Le: return "<=";
    case BinOp::Gt: return ">";
    case BinOp::Ge: return ">=";
    case BinOp::In: return "in";
  }
  return "?";
}

bool is_comparison(BinOp op) {
  return op == BinOp::Eq || op == BinOp::Ne || op == BinOp::Lt || op == BinOp::Le || op == BinOp::Gt || op == BinOp::Ge;
}

[[noreturn]] void not_defined(Interp& in, BinOp op, const Value& a, const Value& b, std::uint32_t pos) {
  in.fail(pos, std::string("`") + op_symbol(op) + "` is not defined for " + type_name(a) + " and " + type_name(b));
}

template <class T>
Value compare_values(BinOp op, const T& x, const T& y) {
  switch (op) {
    case BinOp::Eq: return Value::boolean(x == y);
    case BinOp::Ne: return Value::boolean(x != y);
    case BinOp::Lt: return Value::boolean(x < y);
    case BinOp::Le: return Value::boolean(x <= y);
    case BinOp::Gt: return Value::boolean(x > y);
    default: return Value::boolean(x >= y);
  }
}

Value expr_op(Interp& in, BinOp op, const Value& a, const Value& b, std::uint32_t pos) {
  Op o;
  switch (op) {
    case BinOp::Add: o = Op::Add; break;
    case BinOp::Sub: o = Op::Sub; break;
    case BinOp::Mul: o = Op::Mul; break;
    case BinOp::Div: o = Op::Div; break;
    case BinOp::Rem: o = Op::Mod; break;  // Fidget: `%` on trees is the (Euclidean) mod opcode
    default:
      if (is_comparison(op) || op == BinOp::In)
        in.fail(pos, std::string("cannot compare expressions with `") + op_symbol(op) +
                         "`: x, y, z are symbolic, so the answer would differ from point to point (Fidget refuses "
                         "this too); use compare(a, b), min, max, and, or");
      in.fail(pos, std::string("`") + op_symbol(op) + "` is not defined for expressions (Fidget has no such opcode)");
  }
  const NodeId x = in.to_expr(a, pos, "the left side of `" + std::string(op_symbol(op)) + "`");
  const NodeId y = in.to_expr(b, pos, "the right side of `" + std::string(op_symbol(op)) + "`");
  return Value::expr(in.binary(o, x, y));
}

Value float_op(Interp& in, BinOp op, const Value& a, const Value& b, std::uint32_t pos) {
  const double x = a.number(), y = b.number();
  switch (op) {
    case BinOp::Add: return Value::real(x + y);
    case BinOp::Sub: return Value::real(x - y);
    case BinOp::Mul: return Value::real(x * y);
    case BinOp::Div: return Value::real(x / y);
    case BinOp::Rem: return Value::real(std::fmod(x, y));  // Rust's `%` on floats
    case BinOp::Pow: return Value::real(std::pow(x, y));
    case BinOp::Eq:
    case BinOp::Ne:
    case BinOp::Lt:
    case BinOp::Le:
    case BinOp::Gt:
    case BinOp::Ge: return compare_values(op, x, y);
    default: not_defined(in, op, a, b, pos);
  }
}

std::int64_t int_pow(Interp& in, std::int64_t base, std::int64_t exp, std::uint32_t pos) {
  if (exp < 0) in.fail(pos, "integer raised to a negative power " + std::to_string(exp) + " (use a float)");
  std::int64_t r = 1;
  while (exp > 0) {
    if (exp & 1)
      if (__builtin_mul_overflow(r, base, &r)) in.fail(pos, "arithmetic overflow in `**`");
    exp >>= 1;
    if (exp > 0 && __builtin_mul_overflow(base, base, &base)) in.fail(pos, "arithmetic overflow in `**`");
  }
  return r;
}

Value vec_op(Interp& in, BinOp op, const Value& a, const Value& b, std::uint32_t pos) {
  const bool va = a.kind() == Kind::Vec, vb = b.kind() == Kind::Vec;
  const int n = va ? a.as<VecObj>().n : b.as<VecObj>().n;
  if ((va && vb && a.as<VecObj>().n != b.as<VecObj>().n) || (!va && !a.is_number()) || (!vb && !b.is_number()))
    not_defined(in, op, a, b, pos);
  double r[4] = {0, 0, 0, 0};
  for (int i = 0; i < n; ++i) {
    const double x = va ? a.as<VecObj>().c[i] : a.number();
    const double y = vb ? b.as<VecObj>().c[i] : b.number();
    switch (op) {
      case BinOp::Add: r[i] = x + y; break;
      case BinOp::Sub: r[i] = x - y; break;
      case BinOp::Mul: r[i] = x * y; break;
      case BinOp::Div: r[i] = x / y; break;
      default: not_defined(in, op, a, b, pos);
    }
  }
  return make_vec(n, r[0], r[1], r[2], r[3]);
}

}  // namespace

std::int64_t int_arith(Interp& in, BinOp op, std::int64_t a, std::int64_t b, std::uint32_t pos) {
  std::int64_t r = 0;
  switch (op) {
    case BinOp::Add:
      if (__builtin_add_overflow(a, b, &r)) in.fail(pos, "arithmetic overflow in `+`");
      return r;
    case BinOp::Sub:
      if (__builtin_sub_overflow(a, b, &r)) in.fail(pos, "arithmetic overflow in `-`");
      return r;
    case BinOp::Mul:
      if (__builtin_mul_overflow(a, b, &r)) in.fail(pos, "arithmetic overflow in `*`");
      return r;
    case BinOp::Div:
      if (b == 0) in.fail(pos, "integer division by zero");
      if (a == INT64_MIN && b == -1) in.fail(pos, "arithmetic overflow in `/`");
      return a / b;
    case BinOp::Rem:
      if (b == 0) in.fail(pos, "integer remainder by zero");
      if (a == INT64_MIN && b == -1) in.fail(pos, "arithmetic overflow in `%`");
      return a % b;
    case BinOp::Pow: return int_pow(in, a, b, pos);
    case BinOp::Shl:
    case BinOp::Shr: {
      // Rhai: a negative count shifts the other way; 64 bits or more is an error.
      const bool left = (op == BinOp::Shl) != (b < 0);
      if (b <= -64 || b >= 64) in.fail(pos, "bit shift by " + std::to_string(b) + " is out of range");
      const int s = static_cast<int>(b < 0 ? -b : b);
      return left ? static_cast<std::int64_t>(static_cast<std::uint64_t>(a) << s) : a >> s;
    }
    case BinOp::BitAnd: return a & b;
    case BinOp::BitOr: return a | b;
    case BinOp::BitXor: return a ^ b;
    default: break;
  }
  in.fail(pos, "internal: not an integer operator");
}

Value negate(Interp& in, const Value& v, std::uint32_t pos) {
  switch (v.kind()) {
    case Kind::Int:
      if (v.as_int() == INT64_MIN) in.fail(pos, "arithmetic overflow in unary `-`");
      return Value::integer(-v.as_int());
    case Kind::Float: return Value::real(-v.as_float());
    case Kind::Expr: return Value::expr(in.unary(Op::Neg, v.node()));
    case Kind::Vec: {
      const VecObj& o = v.as<VecObj>();
      return make_vec(o.n, -o.c[0], -o.c[1], -o.c[2], -o.c[3]);
    }
    default: in.fail(pos, std::string("unary `-` is not defined for ") + type_name(v));
  }
}

Value binary_op(Interp& in, BinOp op, const Value& a, const Value& b, std::uint32_t pos) {
  const Kind ka = a.kind(), kb = b.kind();
  if (ka == Kind::Expr || kb == Kind::Expr) return expr_op(in, op, a, b, pos);
  if (a.is_number() && b.is_number()) {
    if (ka == Kind::Float || kb == Kind::Float) return float_op(in, op, a, b, pos);
    const std::int64_t x = a.as_int(), y = b.as_int();
    if (is_comparison(op)) return compare_values(op, x, y);
    if (op == BinOp::In) not_defined(in, op, a, b, pos);
    return Value::integer(int_arith(in, op, x, y, pos));
  }
  if (op == BinOp::In) {
    switch (kb) {
      case Kind::Array:
        for (const Value& e : b.as<ArrayObj>().items) {
          if (e.kind() == Kind::Expr) expr_op(in, op, a, e, pos);  // errors, as comparing trees does
          if (in.equal(a, e)) return Value::boolean(true);
        }
        return Value::boolean(false);
      case Kind::Map:
        if (ka != Kind::Str) not_defined(in, op, a, b, pos);
        return Value::boolean(b.as<MapObj>().items.count(a.as<StrObj>().text) > 0);
      case Kind::Str:
        if (ka != Kind::Str) not_defined(in, op, a, b, pos);
        return Value::boolean(b.as<StrObj>().text.find(a.as<StrObj>().text) != std::string::npos);
      case Kind::Range: {
        if (ka != Kind::Int) not_defined(in, op, a, b, pos);
        const RangeObj& r = b.as<RangeObj>();
        return Value::boolean(a.as_int() >= r.lo && a.as_int() < r.hi);
      }
      default: not_defined(in, op, a, b, pos);
    }
  }
  if (ka == Kind::Str || kb == Kind::Str) {
    if (op == BinOp::Add) {
      std::string s = in.text_of(a);
      s += in.text_of(b);
      return make_string(std::move(s));
    }
    if (ka == Kind::Str && kb == Kind::Str && is_comparison(op))
      return compare_values(op, a.as<StrObj>().text, b.as<StrObj>().text);
  }
  if (ka == Kind::Vec || kb == Kind::Vec) {
    if (op == BinOp::Eq || op == BinOp::Ne) return Value::boolean(in.equal(a, b) == (op == BinOp::Eq));
    return vec_op(in, op, a, b, pos);
  }
  if (ka == Kind::Array && kb == Kind::Array && op == BinOp::Add) {
    Value out = a;
    ArrayObj& arr = in.own_array(out);
    const auto& more = b.as<ArrayObj>().items;
    in.charge(more.size());
    arr.items.insert(arr.items.end(), more.begin(), more.end());
    arr.depth = std::max(arr.depth, b.as<ArrayObj>().depth);
    return out;
  }
  if (ka == Kind::Bool && kb == Kind::Bool) {
    const bool x = a.as_bool(), y = b.as_bool();
    switch (op) {
      case BinOp::Eq: return Value::boolean(x == y);
      case BinOp::Ne: return Value::boolean(x != y);
      case BinOp::BitAnd: return Value::boolean(x && y);
      case BinOp::BitOr: return Value::boolean(x || y);
      case BinOp::BitXor: return Value::boolean(x != y);
      default: break;
    }
  }
  // Equality between any other values (different types are simply unequal, as in Rhai).
  if (op == BinOp::Eq) return Value::boolean(in.equal(a, b));
  if (op == BinOp::Ne) return Value::boolean(!in.equal(a, b));
  not_defined(in, op, a, b, pos);
}

void compound_assign(Interp& in, BinOp op, Value& target, const Value& v, std::uint32_t pos) {
  if (op == BinOp::Add && target.kind() == Kind::Array) {  // `arr += item` or `arr += [items]`
    ArrayObj& arr = in.own_array(target);
    if (v.kind() == Kind::Array) {
      const Value keep = v;  // `a += a`
      const auto& more = keep.as<ArrayObj>().items;
      in.charge(more.size());
      arr.items.insert(arr.items.end(), more.begin(), more.end());
      arr.depth = std::max(arr.depth, keep.as<ArrayObj>().depth);
    } else {
      arr.depth = std::max(arr.depth, value_depth(v) + 1);
      arr.items.push_back(v);
    }
    in.check_depth(arr.depth, pos);
    return;
  }
  if (op == BinOp::Add && target.kind() == Kind::Str && v.kind() != Kind::Expr) {
    const std::string more = in.text_of(v);
    in.own_string(target).text += more;
    return;
  }
  target = binary_op(in, op, target, v, pos);
}

Value index_value(Interp& in, const Value& base, const Value& key, std::uint32_t pos) {
  switch (base.kind()) {
    case Kind::Array: {
      if (key.kind() != Kind::Int) in.fail(pos, std::string("array index must be an integer, not ") + type_name(key));
      const auto& items = base.as<ArrayObj>().items;
      const auto size = static_cast<std::int64_t>(items.size());
      std::int64_t i = key.as_int();
      if (i < 0) i += size;  // Rhai: negative indices count from the end
      if (i < 0 || i >= size)
        in.fail(pos, "array index " + std::to_string(key.as_int()) + " out of bounds (length " + std::to_string(size) + ")");
      return items[static_cast<std::size_t>(i)];
    }
    case Kind::Map: {
      if (key.kind() != Kind::Str) in.fail(pos, std::string("map index must be a string, not ") + type_name(key));
      const auto& items = base.as<MapObj>().items;
      auto it = items.find(key.as<StrObj>().text);
      return it == items.end() ? Value() : it->second;
    }
    case Kind::Str: {
      if (key.kind() != Kind::Int) in.fail(pos, std::string("string index must be an integer, not ") + type_name(key));
      const std::string& s = base.as<StrObj>().text;
      in.charge(s.size() / 16);
      std::vector<std::size_t> starts;
      for (std::size_t i = 0; i < s.size(); ++i)
        if ((static_cast<unsigned char>(s[i]) & 0xC0) != 0x80) starts.push_back(i);
      const auto size = static_cast<std::int64_t>(starts.size());
      std::int64_t i = key.as_int();
      if (i < 0) i += size;
      if (i < 0 || i >= size)
        in.fail(pos, "string index " + std::to_string(key.as_int()) + " out of bounds (length " + std::to_string(size) + ")");
      const std::size_t b = starts[static_cast<std::size_t>(i)];
      const std::size_t e = static_cast<std::size_t>(i) + 1 < starts.size() ? starts[static_cast<std::size_t>(i) + 1] : s.size();
      return make_string(s.substr(b, e - b));
    }
    default: in.fail(pos, std::string("cannot index into ") + type_name(base));
  }
}

Value property_value(Interp& in, const Value& base, std::uint32_t sym, std::uint32_t pos) {
  const std::string_view name = in.symbol_name(sym);
  if (base.kind() == Kind::Map) {
    const auto& items = base.as<MapObj>().items;
    auto it = items.find(name);
    return it == items.end() ? Value() : it->second;  // Rhai: a missing property is ()
  }
  if (base.kind() == Kind::Vec && name.size() == 1) {
    const VecObj& o = base.as<VecObj>();
    const int c = name == "x" ? 0 : name == "y" ? 1 : name == "z" ? 2 : name == "w" ? 3 : 4;
    if (c < o.n) return Value::real(o.c[c]);
  }
  in.fail(pos, std::string(type_name(base)) + " has no property `" + std::string(name) + "`");
}

}  // namespace frep::rhai
