// Differential check of the JIT backend against the interpreter: bytes decode into a tape over
// every opcode (constants and points drawn from special values: NaN, +-0, infinities,
// denormals, halves, the largest floats, or raw bits) and the two backends' batch, gradient and
// interval-batch evaluators must agree bit for bit (NaN for NaN). Shared by the fuzz target (fuzz_jit.cpp) and the test that replays its corpus
// (tests/eval/jit_test.cpp).
#pragma once

#include <algorithm>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "frep/eval/backend.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/eval/jit.hpp"
#include "frep/eval/tape.hpp"
#include "frep/expr/opcode.hpp"

namespace frep::fuzz {

struct DiffCase {
  std::vector<SsaInstr> ssa;
  std::vector<float> xs, ys, zs;
};

inline const std::vector<float>& diff_special_values() {
  static const std::vector<float> v = {
      0.0f, -0.0f, 1.0f, -1.0f, 0.5f, -0.5f, 1.5f, -1.5f, 2.5f, -2.5f, 0.49999997f, 8388608.5f, 16777217.0f,
      std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
      std::numeric_limits<float>::quiet_NaN(), -std::numeric_limits<float>::quiet_NaN(),
      std::bit_cast<float>(0x7fa00001u),  // a signalling NaN with a payload
      std::bit_cast<float>(0xffc12345u),  // a negative quiet NaN with a payload
      std::numeric_limits<float>::denorm_min(), -std::numeric_limits<float>::denorm_min(), 1e-40f, -3e-39f,
      FLT_MIN, -FLT_MIN, FLT_MAX, -FLT_MAX, 1e30f, -1e30f, 3.14159265f, -1.5707964f, 88.7f, -103.9f, 7.0f, 1e-7f};
  return v;
}

// Reads bytes as the recipe of a case; past the end, reads zeros.
class ByteReader {
 public:
  ByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  float value() {
    const std::uint8_t k = byte();
    if (k < 160) return diff_special_values()[k % diff_special_values().size()];
    if (k < 224) return static_cast<float>(static_cast<int>(byte()) - 128) * 0.25f;
    std::uint32_t bits = 0;
    for (int i = 0; i < 4; ++i) bits = bits << 8 | byte();
    return std::bit_cast<float>(bits);
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

inline DiffCase decode_case(const std::uint8_t* data, std::size_t size) {
  // Every opcode of the engine but the oracle, which the JIT never compiles.
  static const std::vector<Op> ops = [] {
    std::vector<Op> v;
    for (int i = 0; i < kEngineOpCount; ++i)
      if (static_cast<Op>(i) != Op::Oracle) v.push_back(static_cast<Op>(i));
    return v;
  }();
  ByteReader r(data, size);
  DiffCase c;
  const int points = 1 + r.byte() % 40;
  const int count = 1 + r.byte() % 96;
  for (int i = 0; i < count; ++i) {
    Op op = ops[r.byte() % ops.size()];
    if (i == 0 && op_arity(op) > 0) op = Op::VarX;
    SsaInstr s{op};
    if (op == Op::Const) s.value = r.value();
    if (op_arity(op) >= 1) s.a = static_cast<std::uint32_t>(i - 1 - r.byte() % i);  // mostly recent values
    if (op_arity(op) >= 2) s.b = static_cast<std::uint32_t>(r.byte() % i);
    c.ssa.push_back(s);
  }
  for (int i = 0; i < points; ++i) {
    c.xs.push_back(r.value());
    c.ys.push_back(r.value());
    c.zs.push_back(r.value());
  }
  return c;
}

// The register code, one instruction a line.
inline std::string describe(const Tape& t) {
  std::string s;
  for (const RegInstr& r : t.code()) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "\n  r%u = %s %s%u %s%u  imm %a", r.out, std::string(op_name(r.op)).c_str(),
                  r.mode & RegInstr::kImmA ? "imm/" : "r", r.a, r.mode & RegInstr::kImmB ? "imm/" : "r", r.b,
                  static_cast<double>(r.imm));
    s += buf;
  }
  return s;
}

// Bits of a result as compared: every NaN alike. Which NaN an operation on two NaNs returns
// (x86 returns its first operand's) is not part of frep's semantics: the compiler may commute
// the interpreter's additions and multiplications, and no operation turns a NaN's sign or
// payload into a number.
inline std::uint32_t compared_bits(float v) { return std::isnan(v) ? 0x7fc00000u : std::bit_cast<std::uint32_t>(v); }

// The 16-box interval pass of `t` on both backends, over boxes spanned by the case's points
// (some degenerate, some with NaN or infinite bounds), for two sets of lanes to simplify: the
// whole record simplification reads must be bit-identical (NaN for NaN). Empty if it is, else
// what differs.
inline std::string check_intervals(const DiffCase& c, const Tape& t, JitIsa isa) {
  constexpr int L = IntervalRecord::kLanes;
  static thread_local std::unique_ptr<IntervalBatchKernel> interp = interpreter_backend().interval_batch();
  static thread_local std::unique_ptr<Backend> backends[2];
  static thread_local std::unique_ptr<IntervalBatchKernel> kernels[2];
  const int which = isa == JitIsa::Avx512;
  if (!kernels[which]) {
    backends[which] = make_jit_backend({.isa = isa, .compile_after_interval_passes = 0});
    kernels[which] = backends[which]->interval_batch();
  }
  const std::size_t n = c.xs.size();
  const int count = static_cast<int>(std::min<std::size_t>(n, L));
  alignas(64) float box[6 * L];
  const std::vector<float>* axes[3] = {&c.xs, &c.ys, &c.zs};
  for (int k = 0; k < L; ++k) {
    const std::size_t i = static_cast<std::size_t>(k < count ? k : 0);
    for (int axis = 0; axis < 3; ++axis) {
      const float p = (*axes[axis])[i], q = (*axes[axis])[(i + static_cast<std::size_t>(axis) + 1) % n];
      // Ordered where both are numbers; a NaN bound stays (an unknown box).
      box[2 * axis * L + k] = q < p ? q : p;
      box[(2 * axis + 1) * L + k] = q < p ? p : q;
    }
  }
  const std::size_t code = t.code().size();
  IntervalRecord ra, rb;
  for (const std::uint32_t lanes : {(1u << count) - 1, 0x5555u & ((1u << count) - 1)}) {
    interp->eval(t, box, count, lanes, ra);
    kernels[which]->eval(t, box, count, lanes, rb);
    const auto differ = [&](const std::string& what, float x, float y) {
      char buf[160];
      std::snprintf(buf, sizeof buf, " (lanes %#x): interpreter %a (0x%08x), jit %a (0x%08x)", lanes,
                    static_cast<double>(x), std::bit_cast<std::uint32_t>(x), static_cast<double>(y),
                    std::bit_cast<std::uint32_t>(y));
      return "intervals: " + what + buf + " on the tape" + describe(t);
    };
    for (int k = 0; k < L; ++k) {
      if (compared_bits(ra.result_lo[k]) != compared_bits(rb.result_lo[k]))
        return differ("lower bound of box " + std::to_string(k), ra.result_lo[k], rb.result_lo[k]);
      if (compared_bits(ra.result_hi[k]) != compared_bits(rb.result_hi[k]))
        return differ("upper bound of box " + std::to_string(k), ra.result_hi[k], rb.result_hi[k]);
    }
    std::size_t folded = 0;
    for (std::size_t i = 0; i < code; ++i) {
      const bool choice = op_is_choice(t.code()[i].op);  // only choices' sides are recorded
      if ((choice && (ra.left[i] != rb.left[i] || ra.right[i] != rb.right[i])) || ra.fold[i] != rb.fold[i]) {
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "intervals: instruction %zu (lanes %#x): left/right/fold bits interpreter %#x/%#x/%#x, jit %#x/%#x/%#x", i,
                      lanes, ra.left[i], ra.right[i], ra.fold[i], rb.left[i], rb.right[i], rb.fold[i]);
        return buf + (" on the tape" + describe(t));
      }
      folded += ra.fold[i] != 0;
    }
    if (ra.mins_count != rb.mins_count)
      return differ("recorded mins", static_cast<float>(ra.mins_count), static_cast<float>(rb.mins_count));
    for (std::size_t i = 0; i < ra.mins_count * 4 * L; ++i)
      if (compared_bits(ra.mins[i]) != compared_bits(rb.mins[i]))
        return differ("recorded min bound " + std::to_string(i), ra.mins[i], rb.mins[i]);
    for (std::size_t i = 0; i < folded * L; ++i)
      if (compared_bits(ra.folds[i]) != compared_bits(rb.folds[i]))
        return differ("folded value " + std::to_string(i), ra.folds[i], rb.folds[i]);
  }
  return {};
}

// Runs the case on the interpreter and on the JIT in `isa`, values (batch evaluator),
// gradients and intervals (check_intervals); an empty string if every output is bit-identical (NaN for NaN), else what differs.
inline std::string check_case(const DiffCase& c, JitIsa isa) {
  const Tape t = Tape::from_ssa(c.ssa);
  static thread_local BatchEvaluator interp(interpreter_backend());
  static thread_local std::unique_ptr<Backend> jit_avx2, jit_avx512;
  auto& slot = isa == JitIsa::Avx512 ? jit_avx512 : jit_avx2;
  if (!slot) slot = make_jit_backend({.isa = isa, .compile_after_points = 0});
  static thread_local std::unique_ptr<BatchEvaluator> jit_ev[2];
  auto& ev = jit_ev[isa == JitIsa::Avx512];
  if (!ev) ev = std::make_unique<BatchEvaluator>(*slot);
  static thread_local GradEvaluator interp_grad(interpreter_backend());
  static thread_local std::unique_ptr<GradEvaluator> jit_grad[2];
  auto& gev = jit_grad[isa == JitIsa::Avx512];
  if (!gev) gev = std::make_unique<GradEvaluator>(*slot);
  const std::size_t n = c.xs.size();
  std::vector<float> a(n), b(n);
  interp.eval(t, c.xs.data(), c.ys.data(), c.zs.data(), a.data(), n);
  ev->eval(t, c.xs.data(), c.ys.data(), c.zs.data(), b.data(), n);
  std::vector<Grad> ga(n), gb(n);
  interp_grad.eval(t, c.xs.data(), c.ys.data(), c.zs.data(), ga.data(), n);
  gev->eval(t, c.xs.data(), c.ys.data(), c.zs.data(), gb.data(), n);
  // What differs at point i: `what` and the two results.
  const auto differ = [&](const std::string& what, std::size_t i, float x, float y) {
    char buf[200];
    std::snprintf(buf, sizeof buf, " at point %zu (%a, %a, %a): interpreter %a (0x%08x), jit %a (0x%08x)", i,
                  static_cast<double>(c.xs[i]), static_cast<double>(c.ys[i]), static_cast<double>(c.zs[i]),
                  static_cast<double>(x), std::bit_cast<std::uint32_t>(x), static_cast<double>(y),
                  std::bit_cast<std::uint32_t>(y));
    return what + buf + " on the tape" + describe(t);
  };
  for (std::size_t i = 0; i < n; ++i) {
    const float pa[4] = {ga[i].v, ga[i].dx, ga[i].dy, ga[i].dz}, pb[4] = {gb[i].v, gb[i].dx, gb[i].dy, gb[i].dz};
    for (int k = 0; k < 4; ++k)
      if (compared_bits(pa[k]) != compared_bits(pb[k])) return differ("gradient channel " + std::to_string(k), i, pa[k], pb[k]);
  }
  for (std::size_t i = 0; i < n; ++i)
    if (compared_bits(a[i]) != compared_bits(b[i])) return differ("value", i, a[i], b[i]);
  return check_intervals(c, t, isa);
}

}  // namespace frep::fuzz
