// Helpers for the UGF tests: independent double-precision references (2D profiles of segments and
// circular arcs with exact distances and a ray-crossing inside test), planes through an edge
// placed at a random position and orientation in 3D, field evaluation in f32 and double, and an
// error table the tests print for the report.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "frep/eval/evaluators.hpp"
#include "frep/eval/tape.hpp"
#include "frep/expr/expr.hpp"
#include "test_util.hpp"

namespace frep::ugf_test {

// ---------------------------------------------------------------------------------------------
// 2D geometry in double

struct V2 {
  double x = 0, y = 0;
};
inline V2 operator+(V2 a, V2 b) { return {a.x + b.x, a.y + b.y}; }
inline V2 operator-(V2 a, V2 b) { return {a.x - b.x, a.y - b.y}; }
inline V2 operator*(double s, V2 a) { return {s * a.x, s * a.y}; }
inline double dot(V2 a, V2 b) { return a.x * b.x + a.y * b.y; }
inline double cross(V2 a, V2 b) { return a.x * b.y - a.y * b.x; }
inline double norm(V2 a) { return std::sqrt(dot(a, a)); }
inline V2 unit_at(double angle) { return {std::cos(angle), std::sin(angle)}; }

inline double segment_distance(V2 q, V2 a, V2 b) {
  const V2 d = b - a;
  const double t = std::clamp(dot(q - a, d) / dot(d, d), 0.0, 1.0);
  return norm(q - a - t * d);
}

// A closed curve of segments and circular arcs; signed distance = distance to the curve,
// negative inside (inside by the parity of crossings of a skew ray).
class Profile {
 public:
  void segment(V2 a, V2 b) { pieces_.push_back({false, a, b, {}, 0, 0, 0}); }
  // Arc of radius r around c, from angle a0 turning by `sweep` (either sign, |sweep| < 2 pi).
  void arc(V2 c, double r, double a0, double sweep) { pieces_.push_back({true, {}, {}, c, r, a0, sweep}); }
  // A closed polyline.
  void polygon(const std::vector<V2>& pts) {
    for (std::size_t i = 0; i < pts.size(); ++i) segment(pts[i], pts[(i + 1) % pts.size()]);
  }

  double distance(V2 q) const {
    double best = 1e300;
    for (const Piece& p : pieces_) {
      if (!p.arc) {
        best = std::min(best, segment_distance(q, p.a, p.b));
        continue;
      }
      const V2 v = q - p.c;
      if (on_arc(p, std::atan2(v.y, v.x))) best = std::min(best, std::fabs(norm(v) - p.r));
      best = std::min({best, norm(q - arc_point(p, p.a0)), norm(q - arc_point(p, p.a0 + p.sweep))});
    }
    return best;
  }

  bool inside(V2 q) const {
    const V2 dir = unit_at(0.3141592653589793 * 1.2345);  // skew, to avoid passing through vertices
    int crossings = 0;
    for (const Piece& p : pieces_) {
      if (!p.arc) {
        // q + t dir = a + s (b - a), t > 0, s in [0, 1).
        const V2 e = p.b - p.a;
        const double den = cross(dir, e);
        if (den == 0) continue;
        const V2 w = p.a - q;
        const double t = cross(w, e) / den, s = cross(w, dir) / den;
        if (t > 0 && s >= 0 && s < 1) ++crossings;
        continue;
      }
      // |q + t dir - c| = r.
      const V2 w = q - p.c;
      const double b = dot(w, dir), cc = dot(w, w) - p.r * p.r, disc = b * b - cc;
      if (disc <= 0) continue;
      for (double t : {-b - std::sqrt(disc), -b + std::sqrt(disc)}) {
        if (t <= 0) continue;
        const V2 h = w + t * dir;
        if (on_arc(p, std::atan2(h.y, h.x))) ++crossings;
      }
    }
    return crossings % 2 == 1;
  }

  double sdf(V2 q) const { return inside(q) ? -distance(q) : distance(q); }

 private:
  struct Piece {
    bool arc;
    V2 a, b;  // segment
    V2 c;     // arc
    double r, a0, sweep;
  };
  static V2 arc_point(const Piece& p, double angle) { return p.c + p.r * unit_at(angle); }
  static bool on_arc(const Piece& p, double angle) {
    // Angle measured from a0 in the arc's direction, in [0, 2 pi).
    double t = (angle - p.a0) * (p.sweep >= 0 ? 1 : -1);
    t = std::fmod(t, 2 * M_PI);
    if (t < 0) t += 2 * M_PI;
    return t <= std::fabs(p.sweep);
  }
  std::vector<Piece> pieces_;
};

// ---------------------------------------------------------------------------------------------
// Two planes through an edge, placed in 3D

// A frame (u, v, e) and origin o: 2D cross-section coordinates (u, v), edge direction e.
struct Frame3 {
  std::array<double, 3> o, u, v, e;

  static Frame3 random(std::mt19937_64& rng) {
    std::normal_distribution<double> n(0, 1);
    auto norm3 = [](std::array<double, 3> a) {
      const double l = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
      return std::array<double, 3>{a[0] / l, a[1] / l, a[2] / l};
    };
    Frame3 f;
    f.o = {std::uniform_real_distribution<double>(-1, 1)(rng), std::uniform_real_distribution<double>(-1, 1)(rng),
           std::uniform_real_distribution<double>(-1, 1)(rng)};
    f.u = norm3({n(rng), n(rng), n(rng)});
    std::array<double, 3> w = {n(rng), n(rng), n(rng)};
    const double d = w[0] * f.u[0] + w[1] * f.u[1] + w[2] * f.u[2];
    for (int k = 0; k < 3; ++k) w[k] -= d * f.u[k];
    f.v = norm3(w);
    f.e = {f.u[1] * f.v[2] - f.u[2] * f.v[1], f.u[2] * f.v[0] - f.u[0] * f.v[2], f.u[0] * f.v[1] - f.u[1] * f.v[0]};
    return f;
  }

  // The plane n . q - d = 0 of the cross-section, as a 3D signed distance expression.
  Expr plane(Graph& g, V2 n, double d) const {
    double n3[3], off = d;
    for (int k = 0; k < 3; ++k) n3[k] = n.x * u[k] + n.y * v[k];
    for (int k = 0; k < 3; ++k) off += n3[k] * o[k];
    return g.x() * static_cast<float>(n3[0]) + g.y() * static_cast<float>(n3[1]) + g.z() * static_cast<float>(n3[2]) -
           static_cast<float>(off);
  }

  // The 3D point (rounded to f32, or in double) with cross-section coordinates q, at t along the
  // edge; local() gives a rounded point's cross-section coordinates.
  std::array<float, 3> point(V2 q, double t) const {
    std::array<float, 3> p;
    for (int k = 0; k < 3; ++k) p[k] = static_cast<float>(o[k] + q.x * u[k] + q.y * v[k] + t * e[k]);
    return p;
  }
  std::array<double, 3> point_d(V2 q, double t) const {
    std::array<double, 3> p;
    for (int k = 0; k < 3; ++k) p[k] = o[k] + q.x * u[k] + q.y * v[k] + t * e[k];
    return p;
  }
  V2 local(const std::array<float, 3>& p) const {
    double d[3];
    for (int k = 0; k < 3; ++k) d[k] = double(p[k]) - o[k];
    return {d[0] * u[0] + d[1] * u[1] + d[2] * u[2], d[0] * v[0] + d[1] * v[1] + d[2] * v[2]};
  }
};

// The wedge {nA.q <= 0, nB.q <= 0} of two planes through the origin of the cross-section, phi
// the angle between the outward normals.
struct Wedge {
  V2 nA, nB;  // outward normals
  V2 dA, dB;  // directions of the faces' rays, from the edge along the solid's boundary
  double phi = 0;

  static Wedge from_normals(V2 nA, V2 nB) {
    Wedge w;
    w.nA = nA;
    w.nB = nB;
    w.dA = {-nA.y, nA.x};
    if (dot(nB, w.dA) > 0) w.dA = -1.0 * w.dA;
    w.dB = {-nB.y, nB.x};
    if (dot(nA, w.dB) > 0) w.dB = -1.0 * w.dB;
    w.phi = std::acos(std::clamp(dot(nA, nB), -1.0, 1.0));
    return w;
  }
  // Normals symmetric about +x, the solid around -x.
  static Wedge symmetric(double phi) { return from_normals(unit_at(phi / 2), unit_at(-phi / 2)); }
  // The complement of the wedge's union-side: {nA.q >= 0, nB.q >= 0}, the same face lines.
  Wedge flipped() const { return from_normals(-1.0 * nA, -1.0 * nB); }

  V2 nS() const { return (1.0 / norm(nA + nB)) * (nA + nB); }  // the bisector's normal
  V2 nD() const { return (1.0 / norm(nA - nB)) * (nA - nB); }
  // Outside, with the edge as the nearest point: q = a nA + b nB with a, b > 0.
  bool in_edge_cone(V2 q) const {
    const double det = cross(nA, nB);
    const double a = cross(q, nB) / det, b = cross(nA, q) / det;
    return a > 0 && b > 0;
  }
};

inline constexpr double kFar = 1000.0;

// The sharp wedge {nA.q <= 0, nB.q <= 0}.
inline Profile wedge_profile(const Wedge& w) {
  Profile p;
  p.polygon({kFar * w.dB, {0, 0}, kFar * w.dA});
  return p;
}
// The wedge chamfered at setbacks sA (along face A) and sB.
inline Profile chamfered_profile(const Wedge& w, double sA, double sB) {
  Profile p;
  p.polygon({kFar * w.dB, sB * w.dB, sA * w.dA, kFar * w.dA});
  return p;
}
// The wedge cut by the plane m.q - d = 0 (m unit), which must cross both face rays.
inline Profile cut_profile(const Wedge& w, V2 m, double d) {
  const double tA = d / dot(m, w.dA), tB = d / dot(m, w.dB);
  EXPECT_GT(tA, 0);
  EXPECT_GT(tB, 0);
  Profile p;
  p.polygon({kFar * w.dB, tB * w.dB, tA * w.dA, kFar * w.dA});
  return p;
}
// The wedge rounded with radius r: the arc's center is inside at distance r from both faces.
inline Profile rounded_profile(const Wedge& w, double r) {
  const V2 c = (-r / std::cos(w.phi / 2)) * w.nS();  // inside, at distance r from both faces
  const V2 tA = c + r * w.nA, tB = c + r * w.nB;
  Profile p;
  p.segment(kFar * w.dB, tB);
  const double aB = std::atan2(w.nB.y, w.nB.x), aA = std::atan2(w.nA.y, w.nA.x);
  double sweep = aA - aB;
  if (sweep > M_PI) sweep -= 2 * M_PI;
  if (sweep < -M_PI) sweep += 2 * M_PI;
  p.arc(c, r, aB, sweep);
  p.segment(tA, kFar * w.dA);
  p.segment(kFar * w.dA, kFar * w.dB);
  return p;
}

// ---------------------------------------------------------------------------------------------
// Evaluation

// f32 value (point evaluator), gradient (gradient evaluator), and double-precision value.
class Probe {
 public:
  explicit Probe(Expr e) : tape_(Tape::compile(e.graph(), e.id())) {}
  float operator()(const std::array<float, 3>& p) { return pe_.eval(tape_, p[0], p[1], p[2]); }
  Grad grad(const std::array<float, 3>& p) { return ge_.eval(tape_, p[0], p[1], p[2]); }
  // The same expression evaluated in double precision (the reference semantics).
  double exact(double x, double y, double z) const {
    test::eval_ssa_all<double>(tape_.ssa(), x, y, z, scratch_);
    return scratch_.back();
  }
  double exact(const std::array<double, 3>& p) const { return exact(p[0], p[1], p[2]); }
  // Central differences of the double-precision evaluation; NaN where two step sizes disagree
  // (a crease within reach).
  std::array<double, 3> fd_grad(const std::array<float, 3>& p, double h = 1e-5) const {
    std::array<double, 3> out;
    for (int k = 0; k < 3; ++k) {
      auto f = [&](double d) {
        double q[3] = {p[0], p[1], p[2]};
        q[k] += d;
        return exact(q[0], q[1], q[2]);
      };
      const double d1 = (f(h) - f(-h)) / (2 * h), d2 = (f(2 * h) - f(-2 * h)) / (4 * h);
      out[k] = std::fabs(d1 - d2) <= 1e-7 ? d1 : std::nan("");
    }
    return out;
  }
  std::size_t size() const { return tape_.size(); }

 private:
  Tape tape_;
  mutable std::vector<double> scratch_;
  PointEvaluator pe_;
  GradEvaluator ge_;
};

inline double length3(const std::array<double, 3>& g) { return std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]); }
inline double length3(const Grad& g) { return std::sqrt(double(g.dx) * g.dx + double(g.dy) * g.dy + double(g.dz) * g.dz); }

// ---------------------------------------------------------------------------------------------
// The error table: every test adds its worst error per operation; printed at the end of each
// test so `frep_tests --gtest_filter='Ugf*'` lists them all.

struct ErrorStat {
  double max_err = 0;
  long points = 0;
  std::string worst;  // where the maximum was seen, when the caller says
  void add(double e, const std::string& where = {}) {
    if (e > max_err) max_err = e, worst = where;
    ++points;
  }
};

inline void report(const std::string& what, const ErrorStat& s, const char* kind = "max |value - reference|") {
  std::printf("[ugf-error] %-52s %-26s %.3g over %ld points%s%s\n", what.c_str(), kind, s.max_err, s.points,
              s.worst.empty() ? "" : ", worst at ", s.worst.c_str());
}

}  // namespace frep::ugf_test
