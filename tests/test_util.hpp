// Shared helpers for the engine's test suite: data paths (with a clean skip when the shared data
// is absent), bit-exact float comparison, a reference SSA evaluator in any precision, a random
// expression generator over every opcode, random floats and points inside boxes.
#pragma once

#include <gtest/gtest.h>

#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <hwy/targets.h>

#include "frep/eval/evaluators.hpp"
#include "frep/eval/interval.hpp"
#include "frep/eval/tape.hpp"
#include "frep/expr/graph.hpp"
#include "frep/expr/oracle.hpp"
#include "frep/expr/opcode.hpp"
#include "frep/expr/semantics.hpp"

namespace frep::test {

// ---------------------------------------------------------------------------------------------
// Data files

inline std::string data_dir() { return std::string(FREP_SOURCE_DIR) + "/../shared/data/vm"; }
inline std::string data_file(const std::string& name) { return data_dir() + "/" + name; }
inline bool have_data(const std::string& name) { return std::filesystem::exists(data_file(name)); }

// Skips the current test (from the test body) when a shared data file is missing.
#define FREP_REQUIRE_DATA(name)                                                                  \
  do {                                                                                           \
    if (!::frep::test::have_data(name))                                                          \
      GTEST_SKIP() << "shared test data not found: " << ::frep::test::data_file(name)            \
                   << " (expected the data set at FREP_SOURCE_DIR/../shared/data/vm)";           \
  } while (0)

// ---------------------------------------------------------------------------------------------
// SIMD targets: the library dispatches at run time to the best instruction set the CPU has, so
// the others would never run. Tests force each one in turn.

// Every instruction set that the library was compiled for and this CPU can run, best first:
// those for which forcing it makes the library's dispatch report that very target.
inline const std::vector<std::int64_t>& simd_targets() {
  static const std::vector<std::int64_t> targets = [] {
    std::vector<std::int64_t> v;
    const std::int64_t cpu = hwy::SupportedTargets();
    for (std::int64_t bits = cpu; bits != 0; bits &= bits - 1) {
      const std::int64_t t = bits & -bits;
      hwy::SetSupportedTargetsForTest(t);
      if (std::string(BatchEvaluator::target_name()) == hwy::TargetName(t)) v.push_back(t);
    }
    hwy::SetSupportedTargetsForTest(0);
    return v;
  }();
  return targets;
}
inline std::string simd_target_name(std::int64_t t) { return hwy::TargetName(t); }
inline std::int64_t simd_target_by_name(const std::string& name) {
  for (std::int64_t t : simd_targets())
    if (simd_target_name(t) == name) return t;
  return 0;
}

// While alive, the library's SIMD code runs on target `t` (0: the best, as normally).
class ScopedSimdTarget {
 public:
  explicit ScopedSimdTarget(std::int64_t t) { hwy::SetSupportedTargetsForTest(t); }
  ~ScopedSimdTarget() { hwy::SetSupportedTargetsForTest(0); }
  ScopedSimdTarget(const ScopedSimdTarget&) = delete;
  ScopedSimdTarget& operator=(const ScopedSimdTarget&) = delete;
};

// Runs body() once per SIMD target, with a trace naming the target in failure messages.
template <class F>
void for_each_simd_target(F&& body) {
  ASSERT_FALSE(simd_targets().empty());
  for (std::int64_t t : simd_targets()) {
    SCOPED_TRACE("SIMD target " + simd_target_name(t));
    ScopedSimdTarget scoped(t);
    body();
  }
}

// ---------------------------------------------------------------------------------------------
// Exact comparison

inline bool same_bits(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }
// Bit-identical, or both NaN (NaN payloads and signs are not part of the semantics).
inline bool same_value(float a, float b) { return (std::isnan(a) && std::isnan(b)) || same_bits(a, b); }
inline bool same_value(double a, double b) {
  return (std::isnan(a) && std::isnan(b)) ||
         std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

inline std::string fstr(float v) {
  char buf[80];
  std::snprintf(buf, sizeof buf, "%.9g (0x%08x)", static_cast<double>(v), std::bit_cast<std::uint32_t>(v));
  return buf;
}
inline std::string istr(Interval i) {
  char buf[120];
  std::snprintf(buf, sizeof buf, "[%.9g, %.9g]", static_cast<double>(i.lo), static_cast<double>(i.hi));
  return buf;
}

// ---------------------------------------------------------------------------------------------
// Opcodes

inline std::vector<Op> all_ops() {
  std::vector<Op> v;
  for (int i = 0; i < kOpCount; ++i) v.push_back(static_cast<Op>(i));
  return v;
}
inline std::vector<Op> ops_of_arity(int arity) {
  std::vector<Op> v;
  for (Op op : all_ops())
    if (op_arity(op) == arity && op != Op::Const) v.push_back(op);
  return v;
}

// ---------------------------------------------------------------------------------------------
// Reference evaluation of an SSA list, in float (the reference semantics) or double (for finite
// differences). Returns the value of every instruction.

// Oracles (Op::Oracle) are evaluated by their values() at the point rounded to float.
template <class T>
void eval_ssa_all(std::span<const SsaInstr> ssa, T x, T y, T z, std::vector<T>& out,
                  const OracleTable* oracles = nullptr) {
  out.resize(ssa.size());
  for (std::size_t i = 0; i < ssa.size(); ++i) {
    const SsaInstr& s = ssa[i];
    switch (s.op) {
      case Op::VarX: out[i] = x; break;
      case Op::VarY: out[i] = y; break;
      case Op::VarZ: out[i] = z; break;
      case Op::Const: out[i] = static_cast<T>(s.value); break;
      case Op::Oracle: {
        const float px = static_cast<float>(x), py = static_cast<float>(y), pz = static_cast<float>(z);
        float v = 0;
        (*oracles)[oracle_index(s.value)]->values(&px, &py, &pz, &v, 1);
        out[i] = static_cast<T>(v);
        break;
      }
      default:
        out[i] = op_eval<T>(s.op, out[s.a], op_arity(s.op) == 2 ? out[s.b] : T(0));
    }
  }
}
template <class T>
T eval_ssa(std::span<const SsaInstr> ssa, T x, T y, T z, const OracleTable* oracles = nullptr) {
  std::vector<T> v;
  eval_ssa_all(ssa, x, y, z, v, oracles);
  return v.back();
}

// Reference evaluation straight from the graph (independent of Tape::compile).
template <class T>
T eval_graph(const Graph& g, NodeId root, T x, T y, T z) {
  std::vector<NodeId> order = reachable_nodes(g, root);
  std::vector<T> val(root + 1, T(0));
  for (NodeId id : order) {
    const Node& n = g.node(id);
    switch (n.op) {
      case Op::VarX: val[id] = x; break;
      case Op::VarY: val[id] = y; break;
      case Op::VarZ: val[id] = z; break;
      case Op::Const: val[id] = static_cast<T>(n.value); break;
      default: val[id] = op_eval<T>(n.op, val[n.a], op_arity(n.op) == 2 ? val[n.b] : T(0));
    }
  }
  return val[root];
}

// ---------------------------------------------------------------------------------------------
// ---------------------------------------------------------------------------------------------
// Special values

inline std::vector<float> special_floats() {
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float pi = 3.14159265358979f;
  std::vector<float> v = {
      0.0f, -0.0f, inf, -inf, nan, -nan,
      std::numeric_limits<float>::denorm_min(), -std::numeric_limits<float>::denorm_min(),
      1e-40f, -3e-39f,  // denormals
      FLT_MIN, -FLT_MIN, FLT_MAX, -FLT_MAX,
      1e-30f, -1e-30f, 1e30f, -1e30f, 1e-7f, 16777216.0f, 16777217.0f, 8388608.5f,
      0.5f, -0.5f, 1.5f, -1.5f, 2.5f, -2.5f, 0.49999997f, -0.49999997f, 4194304.5f,
      1.0f, -1.0f, 1.0000001f, -1.0000001f, 0.99999994f, -0.99999994f, 2.0f, -2.0f, 3.0f, -3.0f, 7.0f,
      pi, -pi, pi / 2, -pi / 2, 2 * pi, 3 * pi / 2, -3 * pi / 2, 100 * pi, 1e6f * pi,
      std::nextafter(pi / 2, 0.0f), std::nextafter(pi / 2, 4.0f),
      0.1f, -0.1f, 10.0f, -10.0f, 88.7f, -103.9f, 89.0f, 1e5f, -1e5f};
  return v;
}

// A float drawn from a mix of distributions: everyday values, wide magnitudes, raw bit patterns
// (which include NaN, infinities and denormals) and the special values above.
inline float random_float(std::mt19937_64& rng) {
  std::uniform_int_distribution<int> kind(0, 9);
  switch (kind(rng)) {
    case 0:
    case 1:
    case 2: return std::uniform_real_distribution<float>(-4.0f, 4.0f)(rng);
    case 3: return std::uniform_real_distribution<float>(-1000.0f, 1000.0f)(rng);
    case 4:
    case 5: {
      const double e = std::uniform_real_distribution<double>(-44, 38)(rng);
      const float m = static_cast<float>(std::pow(10.0, e));
      return (rng() & 1) ? m : -m;
    }
    case 6: return std::bit_cast<float>(static_cast<std::uint32_t>(rng()));
    case 7: return static_cast<float>(std::uniform_int_distribution<int>(-20, 20)(rng)) * 0.5f;
    default: {
      static const std::vector<float> sp = special_floats();
      return sp[std::uniform_int_distribution<std::size_t>(0, sp.size() - 1)(rng)];
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Random expressions

struct GenOptions {
  int max_depth = 6;            // depth of the tree (shared nodes make it a DAG)
  std::vector<Op> ops = {};     // non-leaf ops to draw from; empty = every unary and binary op
  int vars = 3;                 // 2 = x, y only; 3 = x, y, z
  double const_prob = 0.3;      // probability that a leaf is a constant
  double special_const_prob = 0.05;  // probability that a constant is inf, NaN, 0, ...
  double reuse_prob = 0.1;      // probability of reusing an earlier subexpression (sharing)
  double leaf_prob = 0.15;      // probability of stopping early at a non-maximal depth
  float const_range = 3.0f;
};

class ExprGen {
 public:
  ExprGen(Graph& g, std::mt19937_64& rng, GenOptions opt) : g_(g), rng_(rng), opt_(std::move(opt)) {
    if (opt_.ops.empty()) {
      for (Op op : all_ops())
        if (op_arity(op) > 0) opt_.ops.push_back(op);
    }
  }

  NodeId gen() { return gen(opt_.max_depth); }

  NodeId gen(int depth) {
    if (!made_.empty() && chance(opt_.reuse_prob)) return made_[pick(made_.size())];
    if (depth <= 0 || (depth < opt_.max_depth - 1 && chance(opt_.leaf_prob))) return leaf();
    const Op op = opt_.ops[pick(opt_.ops.size())];
    NodeId id;
    if (op_arity(op) == 1) {
      id = g_.unary(op, gen(depth - 1));
    } else {
      const NodeId a = gen(depth - 1);
      const NodeId b = gen(depth - 1);
      id = g_.binary(op, a, b);
    }
    made_.push_back(id);
    return id;
  }

  NodeId leaf() {
    if (chance(opt_.const_prob)) {
      if (chance(opt_.special_const_prob)) {
        static const std::vector<float> sp = special_floats();
        return g_.constant(sp[pick(sp.size())]);
      }
      if (chance(0.3)) return g_.constant(static_cast<float>(static_cast<int>(pick(9)) - 4) * 0.5f);
      return g_.constant(std::uniform_real_distribution<float>(-opt_.const_range, opt_.const_range)(rng_));
    }
    switch (pick(static_cast<std::size_t>(opt_.vars))) {
      case 0: return g_.var_x();
      case 1: return g_.var_y();
      default: return g_.var_z();
    }
  }

 private:
  bool chance(double p) { return std::uniform_real_distribution<double>(0, 1)(rng_) < p; }
  std::size_t pick(std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng_); }

  Graph& g_;
  std::mt19937_64& rng_;
  GenOptions opt_;
  std::vector<NodeId> made_;
};

// ---------------------------------------------------------------------------------------------
// Boxes and points

struct Box {
  Interval x, y, z;
};

// A random interval: everyday, tiny, huge, degenerate, or touching a special value.
inline Interval random_interval(std::mt19937_64& rng) {
  std::uniform_int_distribution<int> kind(0, 9);
  auto uni = [&](float a, float b) { return std::uniform_real_distribution<float>(a, b)(rng); };
  const float inf = std::numeric_limits<float>::infinity();
  switch (kind(rng)) {
    case 0: {  // degenerate
      const float v = uni(-4, 4);
      return {v, v};
    }
    case 1: {  // tiny
      const float c = uni(-4, 4), w = std::pow(10.0f, uni(-7, -3));
      return {c - w, c + w};
    }
    case 2: {  // huge
      const float c = uni(-1e6f, 1e6f), w = std::pow(10.0f, uni(3, 8));
      return {c - w, c + w};
    }
    case 3: {  // touching zero
      const float w = uni(0, 3);
      return (rng() & 1) ? Interval{0.0f, w} : Interval{-w, 0.0f};
    }
    case 4: {  // with an infinite end
      const float c = uni(-3, 3);
      return (rng() & 1) ? Interval{c, inf} : Interval{-inf, c};
    }
    default: {
      float a = uni(-4, 4), b = uni(-4, 4);
      if (a > b) std::swap(a, b);
      return {a, b};
    }
  }
}

// Samples inside [lo, hi]: the ends, neighbours of the ends, zero, special values that fall
// inside, and uniform / bit-pattern random values filtered to the interval.
inline std::vector<float> points_in(Interval iv, std::mt19937_64& rng, int random_count) {
  std::vector<float> v = {iv.lo, iv.hi};
  auto inside = [&](float p) { return !std::isnan(p) && p >= iv.lo && p <= iv.hi; };
  if (iv.lo < iv.hi) {
    v.push_back(std::nextafter(iv.lo, iv.hi));
    v.push_back(std::nextafter(iv.hi, iv.lo));
  }
  for (float s : {0.0f, -0.0f})
    if (inside(s)) v.push_back(s);
  static const std::vector<float> sp = special_floats();
  for (float s : sp)
    if (inside(s) && (rng() % 4 == 0)) v.push_back(s);
  const double lo = std::isfinite(iv.lo) ? iv.lo : -1e30, hi = std::isfinite(iv.hi) ? iv.hi : 1e30;
  for (int i = 0; i < random_count; ++i) {
    float p;
    if (i % 4 == 3) {
      p = random_float(rng);
      if (!inside(p)) p = static_cast<float>(std::uniform_real_distribution<double>(lo, hi)(rng));
    } else {
      p = static_cast<float>(lo + (hi - lo) * std::uniform_real_distribution<double>(0, 1)(rng));
    }
    if (inside(p)) v.push_back(p);
  }
  return v;
}

struct Point3 {
  float x, y, z;
};

// Corners, center and random points of a box (infinite ends are clamped for the random part).
inline std::vector<Point3> points_in(const Box& b, std::mt19937_64& rng, int random_count) {
  std::vector<Point3> pts;
  for (int c = 0; c < 8; ++c)
    pts.push_back({(c & 1) ? b.x.hi : b.x.lo, (c & 2) ? b.y.hi : b.y.lo, (c & 4) ? b.z.hi : b.z.lo});
  auto in = [](Interval i, float v) { return v >= i.lo && v <= i.hi; };
  if (in(b.x, 0) && in(b.y, 0) && in(b.z, 0)) pts.push_back({0, 0, 0});
  const std::vector<float> xs = points_in(b.x, rng, random_count), ys = points_in(b.y, rng, random_count),
                           zs = points_in(b.z, rng, random_count);
  for (int i = 0; i < random_count; ++i)
    pts.push_back({xs[rng() % xs.size()], ys[rng() % ys.size()], zs[rng() % zs.size()]});
  return pts;
}

}  // namespace frep::test
