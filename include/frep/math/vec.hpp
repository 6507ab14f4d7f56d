// The one small math header: 3-vectors and axis-aligned boxes, in double precision for mesh
// geometry (Vec3, Box3) and in single precision for the evaluators' space (Vec3f, Box3f).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace frep {

template <class T>
struct Vec3T {
  T x = 0, y = 0, z = 0;

  constexpr Vec3T() = default;
  constexpr Vec3T(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
  // Explicit conversion between precisions.
  template <class U>
  constexpr explicit Vec3T(const Vec3T<U>& o) : x(static_cast<T>(o.x)), y(static_cast<T>(o.y)), z(static_cast<T>(o.z)) {}

  constexpr T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr T& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  friend constexpr Vec3T operator+(Vec3T a, Vec3T b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  friend constexpr Vec3T operator-(Vec3T a, Vec3T b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  friend constexpr Vec3T operator-(Vec3T a) { return {-a.x, -a.y, -a.z}; }
  friend constexpr Vec3T operator*(Vec3T a, T s) { return {a.x * s, a.y * s, a.z * s}; }
  friend constexpr Vec3T operator*(T s, Vec3T a) { return {a.x * s, a.y * s, a.z * s}; }
  friend constexpr Vec3T operator/(Vec3T a, T s) { return {a.x / s, a.y / s, a.z / s}; }
  constexpr Vec3T& operator+=(Vec3T b) { x += b.x; y += b.y; z += b.z; return *this; }
  constexpr Vec3T& operator-=(Vec3T b) { x -= b.x; y -= b.y; z -= b.z; return *this; }
  constexpr Vec3T& operator*=(T s) { x *= s; y *= s; z *= s; return *this; }
  friend constexpr bool operator==(Vec3T a, Vec3T b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
};

using Vec3 = Vec3T<double>;
using Vec3f = Vec3T<float>;

template <class T> constexpr T dot(Vec3T<T> a, Vec3T<T> b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <class T> constexpr Vec3T<T> cross(Vec3T<T> a, Vec3T<T> b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T> constexpr T length2(Vec3T<T> a) { return dot(a, a); }
template <class T> T length(Vec3T<T> a) { return std::sqrt(dot(a, a)); }
// std::fmin and std::fmax as inline selections, answering as glibc's do (a NaN yields the other
// argument; of equal values, such as -0 and +0, the second): the library calls, which compilers
// do not inline, were a third of a hierarchy's build.
template <class T> constexpr T fmin_inline(T a, T b) {
  const T m = a < b ? a : b;
  return b != b ? a : m;
}
template <class T> constexpr T fmax_inline(T a, T b) {
  const T m = a > b ? a : b;
  return b != b ? a : m;
}
// Component-wise; a NaN component yields the other argument's (as fmin/fmax).
template <class T> constexpr Vec3T<T> min(Vec3T<T> a, Vec3T<T> b) { return {fmin_inline(a.x, b.x), fmin_inline(a.y, b.y), fmin_inline(a.z, b.z)}; }
template <class T> constexpr Vec3T<T> max(Vec3T<T> a, Vec3T<T> b) { return {fmax_inline(a.x, b.x), fmax_inline(a.y, b.y), fmax_inline(a.z, b.z)}; }

// Closed axis-aligned box. The default box is empty (lo > hi), and adding a point makes it that point.
template <class T>
struct Box3T {
  Vec3T<T> lo{std::numeric_limits<T>::max(), std::numeric_limits<T>::max(), std::numeric_limits<T>::max()};
  Vec3T<T> hi{std::numeric_limits<T>::lowest(), std::numeric_limits<T>::lowest(), std::numeric_limits<T>::lowest()};

  constexpr Box3T() = default;
  constexpr Box3T(Vec3T<T> lo_, Vec3T<T> hi_) : lo(lo_), hi(hi_) {}
  template <class U>
  constexpr explicit Box3T(const Box3T<U>& o) : lo(o.lo), hi(o.hi) {}

  void add(Vec3T<T> p) { lo = min(lo, p); hi = max(hi, p); }
  void add(const Box3T& b) { lo = min(lo, b.lo); hi = max(hi, b.hi); }
  constexpr bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
  constexpr Vec3T<T> center() const { return (lo + hi) * T(0.5); }
  constexpr Vec3T<T> size() const { return hi - lo; }
  constexpr bool contains(Vec3T<T> p) const {
    return lo.x <= p.x && p.x <= hi.x && lo.y <= p.y && p.y <= hi.y && lo.z <= p.z && p.z <= hi.z;
  }
  // True if the two closed boxes share a point.
  constexpr bool meets(const Box3T& o) const {
    return lo.x <= o.hi.x && o.lo.x <= hi.x && lo.y <= o.hi.y && o.lo.y <= hi.y && lo.z <= o.hi.z && o.lo.z <= hi.z;
  }
  // The box grown by `d` on every side.
  constexpr Box3T inflated(T d) const { return {lo - Vec3T<T>{d, d, d}, hi + Vec3T<T>{d, d, d}}; }
};

using Box3 = Box3T<double>;
using Box3f = Box3T<float>;

}  // namespace frep
