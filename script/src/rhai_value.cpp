// Rhai values: type names, text, equality and copy on write (see rhai_value.hpp).
#include "rhai_value.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace frep::rhai {

std::uint32_t value_depth(const Value& v) {
  if (v.kind() == Kind::Array) return v.as<ArrayObj>().depth;
  if (v.kind() == Kind::Map) return v.as<MapObj>().depth;
  return 0;
}

const char* type_name(const Value& v) {
  switch (v.kind()) {
    case Kind::Unit: return "()";
    case Kind::Bool: return "bool";
    case Kind::Int: return "i64";
    case Kind::Float: return "f64";
    case Kind::Expr: return "Tree";
    case Kind::Str: return "string";
    case Kind::Array: return "array";
    case Kind::Map: return "map";
    case Kind::Range: return "range";
    case Kind::Vec: {
      static const char* names[] = {"Vec2", "Vec3", "Vec4"};
      return names[v.as<VecObj>().n - 2];
    }
    case Kind::Axis: return "Axis";
    case Kind::Plane: return "Plane";
  }
  return "?";
}

namespace {
std::string number_text(double d) {
  if (std::isnan(d)) return "NaN";
  if (std::isinf(d)) return d > 0 ? "inf" : "-inf";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", d);
  // Shortest text that reads back to the same double.
  for (int prec = 1; prec <= 17; ++prec) {
    char tmp[40];
    std::snprintf(tmp, sizeof tmp, "%.*g", prec, d);
    if (std::strtod(tmp, nullptr) == d) {
      std::snprintf(buf, sizeof buf, "%s", tmp);
      break;
    }
  }
  std::string s = buf;
  if (s.find_first_of(".eE") == std::string::npos) s += ".0";  // Rhai prints floats with a point
  return s;
}
}  // namespace

std::string to_text(const Value& v, const Graph& g, std::uint64_t& budget) {
  if (budget == 0) return "";
  --budget;
  switch (v.kind()) {
    case Kind::Unit: return "";
    case Kind::Bool: return v.as_bool() ? "true" : "false";
    case Kind::Int: return std::to_string(v.as_int());
    case Kind::Float: return number_text(v.as_float());
    case Kind::Expr:
      switch (g.node(v.node()).op) {
        case Op::VarX: return "x";
        case Op::VarY: return "y";
        case Op::VarZ: return "z";
        default: return "Tree(..)";
      }
    case Kind::Str: return v.as<StrObj>().text;
    case Kind::Array: {
      std::string s = "[";
      bool first = true;
      for (const Value& e : v.as<ArrayObj>().items) {
        if (!first) s += ", ";
        first = false;
        s += e.kind() == Kind::Str ? "\"" + e.as<StrObj>().text + "\"" : to_text(e, g, budget);
        if (budget == 0) break;
      }
      return s + "]";
    }
    case Kind::Map: {
      std::string s = "#{";
      bool first = true;
      for (const auto& [k, e] : v.as<MapObj>().items) {
        s += first ? "" : ", ";
        first = false;
        s += k + ": " + (e.kind() == Kind::Str ? "\"" + e.as<StrObj>().text + "\"" : to_text(e, g, budget));
        if (budget == 0) break;
      }
      return s + "}";
    }
    case Kind::Range: {
      const RangeObj& r = v.as<RangeObj>();
      return std::to_string(r.lo) + ".." + std::to_string(r.hi);
    }
    case Kind::Vec: {
      const VecObj& o = v.as<VecObj>();
      std::string s = "[";
      for (int i = 0; i < o.n; ++i) s += (i ? ", " : "") + number_text(o.c[i]);
      return s + "]";
    }
    case Kind::Axis: {
      const AxisObj& a = v.as<AxisObj>();
      return "axis([" + number_text(a.v[0]) + ", " + number_text(a.v[1]) + ", " + number_text(a.v[2]) + "])";
    }
    case Kind::Plane: {
      const PlaneObj& p = v.as<PlaneObj>();
      return "plane([" + number_text(p.axis[0]) + ", " + number_text(p.axis[1]) + ", " + number_text(p.axis[2]) +
             "], " + number_text(p.offset) + ")";
    }
  }
  return "";
}

bool values_equal(const Value& a, const Value& b, std::uint64_t& budget) {
  if (budget == 0) return false;
  --budget;
  if (a.is_number() && b.is_number()) {
    if (a.kind() == Kind::Int && b.kind() == Kind::Int) return a.as_int() == b.as_int();
    return a.number() == b.number();
  }
  if (a.kind() != b.kind()) return false;
  switch (a.kind()) {
    case Kind::Unit: return true;
    case Kind::Bool: return a.as_bool() == b.as_bool();
    case Kind::Expr: return a.node() == b.node();
    case Kind::Str: return a.as<StrObj>().text == b.as<StrObj>().text;
    case Kind::Array: {
      const auto& x = a.as<ArrayObj>().items;
      const auto& y = b.as<ArrayObj>().items;
      if (x.size() != y.size()) return false;
      for (std::size_t i = 0; i < x.size(); ++i)
        if (!values_equal(x[i], y[i], budget)) return false;
      return true;
    }
    case Kind::Map: {
      const auto& x = a.as<MapObj>().items;
      const auto& y = b.as<MapObj>().items;
      if (x.size() != y.size()) return false;
      for (auto i = x.begin(), j = y.begin(); i != x.end(); ++i, ++j)
        if (i->first != j->first || !values_equal(i->second, j->second, budget)) return false;
      return true;
    }
    case Kind::Range: {
      const RangeObj &x = a.as<RangeObj>(), &y = b.as<RangeObj>();
      return x.lo == y.lo && x.hi == y.hi && x.step == y.step;
    }
    case Kind::Vec: {
      const VecObj &x = a.as<VecObj>(), &y = b.as<VecObj>();
      if (x.n != y.n) return false;
      for (int i = 0; i < x.n; ++i)
        if (x.c[i] != y.c[i]) return false;
      return true;
    }
    case Kind::Axis: {
      const AxisObj &x = a.as<AxisObj>(), &y = b.as<AxisObj>();
      return x.v[0] == y.v[0] && x.v[1] == y.v[1] && x.v[2] == y.v[2];
    }
    case Kind::Plane: {
      const PlaneObj &x = a.as<PlaneObj>(), &y = b.as<PlaneObj>();
      return x.axis[0] == y.axis[0] && x.axis[1] == y.axis[1] && x.axis[2] == y.axis[2] && x.offset == y.offset;
    }
    default: return false;
  }
}

ArrayObj& mutable_array(Value& v) {
  if (!v.unique()) {
    auto* copy = new ArrayObj(v.as<ArrayObj>());
    copy->refs = 1;
    v = Value::heap(copy);
  }
  return v.as<ArrayObj>();
}

MapObj& mutable_map(Value& v) {
  if (!v.unique()) {
    auto* copy = new MapObj(v.as<MapObj>());
    copy->refs = 1;
    v = Value::heap(copy);
  }
  return v.as<MapObj>();
}

StrObj& mutable_string(Value& v) {
  if (!v.unique()) v = make_string(v.as<StrObj>().text);
  return v.as<StrObj>();
}

}  // namespace frep::rhai
