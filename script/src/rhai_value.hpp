// Values of the Rhai interpreter: 16 bytes each; numbers, booleans and expressions (graph nodes)
// inline, strings, arrays, maps and Fidget's small types (vectors, axes, planes) in reference-
// counted heap objects that are copied on write, since Rhai values have value semantics.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "frep/expr/graph.hpp"

namespace frep::rhai {

enum class Kind : std::uint8_t { Unit, Bool, Int, Float, Expr, Str, Array, Map, Range, Vec, Axis, Plane };

// Arrays and maps nest at most this deep, so that comparing, printing and freeing values never
// recurses further than this.
inline constexpr std::uint32_t kMaxValueDepth = 128;

struct HeapObj {
  std::uint32_t refs = 1;
  explicit HeapObj(Kind k) : kind(k) {}
  virtual ~HeapObj() = default;
  Kind kind;
};

class Value {
 public:
  Value() : kind_(Kind::Unit) { u_.i = 0; }
  static Value boolean(bool b) { Value v; v.kind_ = Kind::Bool; v.u_.b = b; return v; }
  static Value integer(std::int64_t i) { Value v; v.kind_ = Kind::Int; v.u_.i = i; return v; }
  static Value real(double f) { Value v; v.kind_ = Kind::Float; v.u_.f = f; return v; }
  static Value expr(NodeId n) { Value v; v.kind_ = Kind::Expr; v.u_.node = n; return v; }
  // Takes ownership of one reference.
  static Value heap(HeapObj* o) { Value v; v.kind_ = o->kind; v.u_.obj = o; return v; }

  Value(const Value& o) : kind_(o.kind_), u_(o.u_) {
    if (is_heap()) ++u_.obj->refs;
  }
  Value(Value&& o) noexcept : kind_(o.kind_), u_(o.u_) { o.kind_ = Kind::Unit; }
  Value& operator=(const Value& o) {
    if (this != &o) {
      Value tmp(o);
      swap(tmp);
    }
    return *this;
  }
  Value& operator=(Value&& o) noexcept {
    if (this != &o) {
      release();
      kind_ = o.kind_;
      u_ = o.u_;
      o.kind_ = Kind::Unit;
    }
    return *this;
  }
  ~Value() { release(); }
  void swap(Value& o) noexcept {
    std::swap(kind_, o.kind_);
    std::swap(u_, o.u_);
  }

  Kind kind() const { return kind_; }
  bool is_heap() const { return kind_ >= Kind::Str; }
  bool is_number() const { return kind_ == Kind::Int || kind_ == Kind::Float; }
  bool as_bool() const { return u_.b; }
  std::int64_t as_int() const { return u_.i; }
  double as_float() const { return u_.f; }
  // Int or Float as a double.
  double number() const { return kind_ == Kind::Int ? static_cast<double>(u_.i) : u_.f; }
  NodeId node() const { return u_.node; }
  HeapObj* obj() const { return u_.obj; }
  template <class T>
  T& as() const { return *static_cast<T*>(u_.obj); }
  // True when this value holds the only reference to its heap object (mutation in place is safe).
  bool unique() const { return u_.obj->refs == 1; }

 private:
  void release() {
    if (is_heap() && --u_.obj->refs == 0) delete u_.obj;
  }
  Kind kind_;
  union {
    bool b;
    std::int64_t i;
    double f;
    NodeId node;
    HeapObj* obj;
  } u_;
};
static_assert(sizeof(Value) == 16);

struct StrObj : HeapObj {
  explicit StrObj(std::string s) : HeapObj(Kind::Str), text(std::move(s)) {}
  std::string text;
};
struct ArrayObj : HeapObj {
  ArrayObj() : HeapObj(Kind::Array) {}
  std::vector<Value> items;
  std::uint32_t depth = 1;  // 1 + the deepest nested array or map
};
struct MapObj : HeapObj {
  MapObj() : HeapObj(Kind::Map) {}
  std::map<std::string, Value, std::less<>> items;  // sorted by key, as Rhai's maps
  std::uint32_t depth = 1;
};
struct RangeObj : HeapObj {
  RangeObj(std::int64_t lo_, std::int64_t hi_, std::int64_t step_) : HeapObj(Kind::Range), lo(lo_), hi(hi_), step(step_) {}
  std::int64_t lo, hi, step;  // lo, lo + step, ... while < hi (or > hi for a negative step)
};
// Fidget's vec2, vec3 and vec4 (n = 2, 3, 4).
struct VecObj : HeapObj {
  VecObj(int n_, double x, double y, double z = 0, double w = 0) : HeapObj(Kind::Vec), n(n_), c{x, y, z, w} {}
  int n;
  double c[4];
};
// Fidget's Axis: a unit vector.
struct AxisObj : HeapObj {
  AxisObj(double x, double y, double z) : HeapObj(Kind::Axis), v{x, y, z} {}
  double v[3];
};
// Fidget's Plane: the points p with dot(axis, p) = offset.
struct PlaneObj : HeapObj {
  PlaneObj(const double a[3], double off) : HeapObj(Kind::Plane), axis{a[0], a[1], a[2]}, offset(off) {}
  double axis[3];
  double offset;
};

inline Value make_string(std::string s) { return Value::heap(new StrObj(std::move(s))); }
inline Value make_vec(int n, double x, double y, double z = 0, double w = 0) { return Value::heap(new VecObj(n, x, y, z, w)); }

// Nesting depth of a value (0 for scalars).
std::uint32_t value_depth(const Value& v);
// Rhai's type names (`type_of`); expressions are Fidget's "Tree".
const char* type_name(const Value& v);
// Rhai-style text of a value, for `to_string`, `print` and string concatenation. Expressions
// print as Fidget prints trees: "x", "y", "z" or "Tree(..)". Every element visited costs one unit
// of `budget`; when it runs out the text is cut short and `budget` is 0 (arrays that share their
// parts can be exponentially larger than the memory they take).
std::string to_text(const Value& v, const Graph& g, std::uint64_t& budget);
// Structural equality of plain data (numbers compare across Int and Float). Expressions compare
// by node; callers reject them first, as Fidget does. Costs `budget` as to_text does.
bool values_equal(const Value& a, const Value& b, std::uint64_t& budget);

// Makes the value's heap object unique (copy on write) and returns it.
ArrayObj& mutable_array(Value& v);
MapObj& mutable_map(Value& v);
StrObj& mutable_string(Value& v);

}  // namespace frep::rhai
