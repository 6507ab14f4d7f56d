// The model tape in view coordinates: a prefix computing x, y, z from u, v, w, then the model's
// instructions with their variables replaced, then (for rotated views) the cut at the bounds.
#include "view_tape.hpp"

#include "frep/eval/ssa_builder.hpp"
#include "frep/expr/oracle.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

namespace frep {

Tape view_tape(const Tape& model, const Camera& cam, const Box3& bounds) {
  SsaBuilder ssa;
  const SsaBuilder::Vars uvw = ssa.variables();
  // c0 u + c1 v + c2 w + c3 with the coefficients rounded to float (SsaBuilder::affine keeps
  // axis-aligned views exact).
  const auto emit_linear = [&](const double (&c)[4]) {
    return ssa.affine({static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2]),
                       static_cast<float>(c[3])},
                      uvw);
  };
  // Model axis `axis` minus its center, and the model variable itself.
  std::uint32_t rel[3];
  SsaBuilder::Vars model_var;
  for (int axis = 0; axis < 3; ++axis) {
    rel[axis] = emit_linear({cam.right[axis], cam.up[axis], cam.toward[axis], 0});
    const float c = static_cast<float>(cam.center[axis]);
    model_var[axis] = c == 0 ? rel[axis] : ssa.emit(Op::Add, rel[axis], ssa.constant(c));
  }

  // The model's oracles, evaluated at the model point of (u, v, w): center + u right + v up +
  // w toward, in double (Oracle::transformed), same indices.
  std::shared_ptr<OracleTable> oracles;
  if (model.oracles()) {
    Affine3 view;
    for (int i = 0; i < 3; ++i) {
      view.m[i][0] = cam.right[i];
      view.m[i][1] = cam.up[i];
      view.m[i][2] = cam.toward[i];
      view.m[i][3] = cam.center[i];
    }
    oracles = std::make_shared<OracleTable>();
    for (const auto& o : *model.oracles()) oracles->push_back(o->transformed(view));
  }
  const auto src = model.ssa();
  std::uint32_t root;
  if (cam.axis_aligned) {
    root = ssa.append(model, model_var);
  } else {
    // Rotated views: every model value that is affine in x, y, z (planes, coordinate
    // differences, cross products with constant vectors...) is rewritten as one affine form in
    // u, v, w. Interval arithmetic bounds such a form exactly over a view box, whereas the same
    // value built from x, y, z sees each of them over the box's axis-aligned hull, and sums them
    // as if they were independent: up to 3x wider on converted meshes, which pruned far less.
    struct Affine {
      double c[4];  // coefficients of u, v, w, then the constant
    };
    std::vector<Affine> aff(src.size());
    std::vector<std::uint8_t> affine(src.size(), 0);
    std::vector<std::uint8_t> axes(src.size(), 0);  // affine values: bits of the model axes they depend on
    constexpr std::uint32_t kNotEmitted = UINT32_MAX;
    std::vector<std::uint32_t> map(src.size(), kNotEmitted);
    const auto constant = [](const Affine& f) { return f.c[0] == 0 && f.c[1] == 0 && f.c[2] == 0; };
    // The instruction computing source value j in the view tape. An affine value of one model
    // axis (such as x - a), or a scaled or shifted affine value, is bounded exactly from its
    // argument's interval: it is emitted as in the model, sharing the model's instructions.
    // Only a sum or difference of two varying values that combines axes becomes a u, v, w form.
    // Iterative: chains of affine values may be as long as the model.
    std::vector<std::uint32_t> pending;
    const auto get = [&](std::uint32_t root) -> std::uint32_t {
      pending.push_back(root);
      while (!pending.empty()) {
        const std::uint32_t j = pending.back();
        if (map[j] != kNotEmitted) {
          pending.pop_back();
          continue;
        }
        const SsaInstr& s = src[j];
        const int ar = op_arity(s.op);
        const bool combines = (s.op == Op::Add || s.op == Op::Sub) && !constant(aff[s.a]) && !constant(aff[s.b]);
        if (std::popcount(axes[j]) > 1 && combines) {
          map[j] = emit_linear(aff[j].c);
        } else if (ar == 0) {
          map[j] = ssa.copy(s, model_var, map);
        } else if (map[s.a] == kNotEmitted) {
          pending.push_back(s.a);
          continue;
        } else if (ar > 1 && map[s.b] == kNotEmitted) {
          pending.push_back(s.b);
          continue;
        } else {
          map[j] = ssa.copy(s, model_var, map);
        }
        pending.pop_back();
      }
      return map[root];
    };
    // A squared length |w|^2 = w_x^2 + w_y^2 + w_z^2 (in either association) of a vector
    //   w = alpha (p - a) + g c                  (g one value, c a constant vector), or
    //   w = alpha (g1 (p - a) + g2 (p - b))      (g1, g2 two values),
    // is the same in view coordinates: with p = center + R q, p - a = R (q - R^T (a - center)).
    // The first form is a squared distance to a point (c = 0) or, as converted meshes write it,
    // to a segment (g the clamped position along it); the second, a segment interpolated between
    // its ends (g1 = 1 - t, g2 = t). Bounded from u, v, w, each square sees the exact range of
    // its view coordinate instead of a model axis's hull over the box. Every form computes
    // alpha (q_j - a'_j) with the same instructions for the same point a, so a segment's value at
    // its end (g = 0, or g1 = 1 and g2 = 0) is bit for bit the end point's: converted meshes rely
    // on those exact ties (a vertex term must win them, its sign is the one that holds there).
    // Returns kNotEmitted unless source value i has one of these forms.
    const auto rotated_norm = [&](std::size_t i) -> std::uint32_t {
      std::uint32_t sq[3];
      const SsaInstr& s = src[i];
      const auto is_op = [&](std::uint32_t j, Op op) { return src[j].op == op; };
      if (is_op(s.a, Op::Add) && is_op(s.b, Op::Square)) {
        sq[0] = src[s.a].a, sq[1] = src[s.a].b, sq[2] = s.b;
      } else if (is_op(s.b, Op::Add) && is_op(s.a, Op::Square)) {
        sq[0] = s.a, sq[1] = src[s.b].a, sq[2] = src[s.b].b;
      } else {
        return kNotEmitted;
      }
      // The constant factor of a value: (g, c) for g * c, c * g or g itself.
      const auto scaled = [&](std::uint32_t j, std::uint32_t& g, double& c) {
        const SsaInstr& t = src[j];
        if (t.op == Op::Mul && affine[t.b] && constant(aff[t.b]) && !affine[t.a]) return g = t.a, c = aff[t.b].c[3], true;
        if (t.op == Op::Mul && affine[t.a] && constant(aff[t.a]) && !affine[t.b]) return g = t.b, c = aff[t.a].c[3], true;
        if (!affine[j]) return g = j, c = 1, true;
        return false;
      };
      // An affine value of one model axis k as alpha (x_k - a_k): its axis, alpha and a_k.
      const auto one_axis = [&](std::uint32_t o, int& k, double& alpha, double& at) {
        if (!affine[o] || std::popcount(axes[o]) != 1) return false;
        k = std::countr_zero(axes[o]);
        const Vec3 row{cam.right[k], cam.up[k], cam.toward[k]};  // u, v, w coefficients of x_k
        const Affine& f = aff[o];
        alpha = f.c[0] * row.x + f.c[1] * row.y + f.c[2] * row.z;
        if (!(alpha != 0) || std::fabs(f.c[0] - alpha * row.x) + std::fabs(f.c[1] - alpha * row.y) +
                                     std::fabs(f.c[2] - alpha * row.z) > 1e-12 * std::fabs(alpha))
          return false;
        // alpha x_k + beta = alpha (x_k - a_k), beta the constant at the model origin.
        at = -(f.c[3] - alpha * cam.center[k]) / alpha;
        return true;
      };
      const auto same = [](double x, double y) { return std::fabs(x - y) <= 1e-12 * std::fabs(y); };
      double scale = 0;
      Vec3 a, b, c;  // the points, and g's vector
      std::uint32_t g = kNotEmitted, g1 = kNotEmitted, g2 = kNotEmitted;
      std::uint8_t seen = 0;
      for (int n = 0; n < 3; ++n) {
        const std::uint32_t j = sq[n];
        if (!is_op(j, Op::Square)) return kNotEmitted;
        std::uint32_t o = src[j].a;
        int k = 0;
        double alpha = 0;
        const SsaInstr& t = src[o];
        // g1 A + g2 B, each product in either order, A and B affine in the same axis.
        const auto product = [&](std::uint32_t m, std::uint32_t& gm, std::uint32_t& v) {
          const SsaInstr& u = src[m];
          if (u.op != Op::Mul) return false;
          if (affine[u.b] && !affine[u.a]) return gm = u.a, v = u.b, true;
          if (affine[u.a] && !affine[u.b]) return gm = u.b, v = u.a, true;
          return false;
        };
        std::uint32_t ga, gb, va, vb;
        if (!affine[o] && t.op == Op::Add && product(t.a, ga, va) && product(t.b, gb, vb) && (n == 0 || g1 != kNotEmitted)) {
          int kb = 0;
          double alpha_b = 0, pa = 0, pb = 0;
          if (!one_axis(va, k, alpha, pa) || !one_axis(vb, kb, alpha_b, pb) || kb != k || !same(alpha_b, alpha))
            return kNotEmitted;
          if (n > 0 && (ga != g1 || gb != g2)) return kNotEmitted;
          g1 = ga, g2 = gb;
          a[k] = pa, b[k] = pb;
        } else {
          if (g1 != kNotEmitted) return kNotEmitted;
          std::uint32_t gk = kNotEmitted;
          double ck = 0;
          if (!affine[o]) {  // alpha (x_k - a_k) + g c_k
            if (t.op != Op::Add && t.op != Op::Sub) return kNotEmitted;
            if (!affine[t.a] || !scaled(t.b, gk, ck)) return kNotEmitted;
            if (t.op == Op::Sub) ck = -ck;
            if (g != kNotEmitted && gk != g) return kNotEmitted;
            g = gk;
            o = t.a;
          }
          double at = 0;
          if (!one_axis(o, k, alpha, at)) return kNotEmitted;
          a[k] = at;
          // The sign of alpha moves to c_k (the square does not see it).
          c[k] = alpha > 0 ? ck : -ck;
        }
        if (seen & (1u << k)) return kNotEmitted;
        seen = static_cast<std::uint8_t>(seen | (1u << k));
        // Equal scales up to the rounding of the rotation's rows (unit to about 1e-16).
        if (scale == 0) scale = std::fabs(alpha);
        else if (!same(std::fabs(alpha), scale)) return kNotEmitted;
      }
      const bool two = g1 != kNotEmitted;
      if (!std::isfinite(length2(a)) || !std::isfinite(length2(c)) || (two && !std::isfinite(length2(b))))
        return kNotEmitted;
      // alpha (q_j - a'_j) in view axis j, with a' = R^T (a - center): the same instructions for
      // the same point in every form.
      const auto offset = [&](const Vec3& point, int j) {
        const Vec3 d = point - cam.center;
        const double ap[3] = {dot(d, cam.right), dot(d, cam.up), dot(d, cam.toward)};
        const float off = static_cast<float>(-ap[j]);
        std::uint32_t r = off == 0 ? uvw[j] : ssa.emit(Op::Add, uvw[j], ssa.constant(off));
        if (scale != 1) r = ssa.emit(Op::Mul, r, ssa.constant(static_cast<float>(scale)));
        return r;
      };
      const double cp[3] = {dot(c, cam.right), dot(c, cam.up), dot(c, cam.toward)};
      const std::uint32_t ge = g == kNotEmitted ? 0 : map[g];
      std::uint32_t sum = 0;
      for (int j = 0; j < 3; ++j) {
        std::uint32_t r;
        if (two) {
          r = ssa.emit(Op::Add, ssa.emit(Op::Mul, map[g1], offset(a, j)), ssa.emit(Op::Mul, map[g2], offset(b, j)));
        } else {
          r = offset(a, j);
          const float cj = static_cast<float>(cp[j]);
          if (g != kNotEmitted && cj != 0) r = ssa.emit(Op::Add, r, cj == 1 ? ge : ssa.emit(Op::Mul, ge, ssa.constant(cj)));
        }
        const std::uint32_t r2 = ssa.emit(Op::Square, r);
        sum = j == 0 ? r2 : ssa.emit(Op::Add, sum, r2);
      }
      return sum;
    };
    for (std::size_t i = 0; i < src.size(); ++i) {
      const SsaInstr& s = src[i];
      const int ar = op_arity(s.op);
      Affine r{};
      bool ok = true;
      const Affine* a = ar > 0 && affine[s.a] ? &aff[s.a] : nullptr;
      const Affine* b = ar > 1 && affine[s.b] ? &aff[s.b] : nullptr;
      switch (s.op) {
        case Op::VarX:
        case Op::VarY:
        case Op::VarZ: {
          const int axis = static_cast<int>(s.op) - static_cast<int>(Op::VarX);
          r = {{cam.right[axis], cam.up[axis], cam.toward[axis], cam.center[axis]}};
          break;
        }
        case Op::Const: r.c[3] = s.value; break;
        case Op::Neg:
          ok = a;
          if (ok)
            for (int k = 0; k < 4; ++k) r.c[k] = -a->c[k];
          break;
        case Op::Add:
        case Op::Sub:
          ok = a && b;
          if (ok)
            for (int k = 0; k < 4; ++k) r.c[k] = s.op == Op::Add ? a->c[k] + b->c[k] : a->c[k] - b->c[k];
          break;
        case Op::Mul:
          ok = a && b && (constant(*a) || constant(*b));
          if (ok) {
            const Affine& v = constant(*a) ? *b : *a;
            const double f = constant(*a) ? a->c[3] : b->c[3];
            for (int k = 0; k < 4; ++k) r.c[k] = v.c[k] * f;
          }
          break;
        case Op::Div:
          ok = a && b && constant(*b) && b->c[3] != 0;
          if (ok)
            for (int k = 0; k < 4; ++k) r.c[k] = a->c[k] / b->c[3];
          break;
        default: ok = false;
      }
      for (int k = 0; k < 4 && ok; ++k) ok = std::isfinite(r.c[k]) && std::fabs(r.c[k]) <= 3.0e38;
      if (ok) {
        aff[i] = r;
        affine[i] = 1;
        if (s.op == Op::VarX || s.op == Op::VarY || s.op == Op::VarZ)
          axes[i] = static_cast<std::uint8_t>(1u << (static_cast<int>(s.op) - static_cast<int>(Op::VarX)));
        else
          axes[i] = static_cast<std::uint8_t>((ar > 0 ? axes[s.a] : 0) | (ar > 1 ? axes[s.b] : 0));
        continue;
      }
      if (ar == 0) {  // a constant the affine forms refuse (infinite, NaN or near the float limit)
        map[i] = ssa.copy(s, model_var, map);
        continue;
      }
      if (s.op == Op::Add) {
        const std::uint32_t norm = rotated_norm(i);
        if (norm != kNotEmitted) {
          map[i] = norm;
          continue;
        }
      }
      get(s.a);
      if (ar > 1) get(s.b);
      map[i] = ssa.copy(s, model_var, map);
    }
    root = get(static_cast<std::uint32_t>(src.size() - 1));
  }
  if (!cam.axis_aligned) {
    std::uint32_t box = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const float half = static_cast<float>(bounds.size()[axis] / 2);
      const std::uint32_t d = ssa.emit(Op::Sub, ssa.emit(Op::Abs, rel[axis]), ssa.constant(half));
      box = axis == 0 ? d : ssa.emit(Op::Max, box, d);
    }
    root = ssa.emit(Op::Max, root, box);
  }
  return ssa.finish(root, std::move(oracles));
}

}  // namespace frep
