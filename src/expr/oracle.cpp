// Oracles: the default box bounds (from the Lipschitz bound) and the transformed wrapper.
#include "frep/expr/oracle.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "frep/error.hpp"
#include "frep/expr/derivative.hpp"
#include "frep/expr/remap.hpp"

namespace frep {

void Oracle::bounds(const Interval* x, const Interval* y, const Interval* z, Interval* out, std::size_t n) const {
  const double lip = lipschitz();
  constexpr std::size_t kMax = 64;
  // Centres in groups; equal centres (a box and the box's centre) are evaluated once.
  for (std::size_t base = 0; base < n; base += kMax) {
    const std::size_t m = std::min(kMax, n - base);
    BoxCentre bc[kMax];
    float cx[kMax], cy[kMax], cz[kMax], cv[kMax];
    std::size_t slot[kMax], unique = 0;
    for (std::size_t k = 0; k < m; ++k) {
      bc[k] = box_centre(x[base + k], y[base + k], z[base + k]);
      std::size_t u = 0;
      while (u < unique && !(cx[u] == bc[k].c[0] && cy[u] == bc[k].c[1] && cz[u] == bc[k].c[2])) ++u;
      if (u == unique) {
        cx[u] = bc[k].c[0];
        cy[u] = bc[k].c[1];
        cz[u] = bc[k].c[2];
        ++unique;
      }
      slot[k] = u;
    }
    values(cx, cy, cz, cv, unique);
    for (std::size_t k = 0; k < m; ++k) {
      const float c = cv[slot[k]];
      Interval& o = out[base + k];
      if (std::isnan(c) || !(lip > 0)) {
        o = Interval::unknown();
      } else if (bc[k].half_diagonal == 0) {
        o = Interval::point(c);
      } else {
        constexpr float kInf = std::numeric_limits<float>::infinity();
        o = lipschitz_bound({-kInf, kInf}, Interval::point(c), lip, bc[k].half_diagonal, bc[k].scale);
      }
    }
  }
}

std::optional<Oracle::RayHit> Oracle::first_hit(const Vec3&, const Vec3&, double) const { return std::nullopt; }

std::shared_ptr<const Oracle> Oracle::transformed(const Affine3& a) const {
  if (a.is_identity()) return shared_from_this();
  return std::make_shared<TransformedOracle>(shared_from_this(), a);
}

TransformedOracle::TransformedOracle(std::shared_ptr<const Oracle> base, const Affine3& a)
    : base_(std::move(base)), map_(a), lipschitz_(base_->lipschitz() * a.stretch_bound()) {
  FREP_ASSERT(a.finite(), "a transformed oracle needs a finite map");
}

void TransformedOracle::map_points(const float* x, const float* y, const float* z, float* qx, float* qy, float* qz,
                                   std::size_t n) const {
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 q = map_.apply({x[i], y[i], z[i]});
    qx[i] = static_cast<float>(q.x);
    qy[i] = static_cast<float>(q.y);
    qz[i] = static_cast<float>(q.z);
  }
}

void TransformedOracle::values(const float* x, const float* y, const float* z, float* out, std::size_t n) const {
  float qx[kChunk], qy[kChunk], qz[kChunk];
  for (std::size_t b = 0; b < n; b += kChunk) {
    const std::size_t m = std::min(kChunk, n - b);
    map_points(x + b, y + b, z + b, qx, qy, qz, m);
    base_->values(qx, qy, qz, out + b, m);
  }
}

void TransformedOracle::gradients(const float* x, const float* y, const float* z, Grad* out, std::size_t n) const {
  float qx[kChunk], qy[kChunk], qz[kChunk];
  for (std::size_t b = 0; b < n; b += kChunk) {
    const std::size_t m = std::min(kChunk, n - b);
    map_points(x + b, y + b, z + b, qx, qy, qz, m);
    base_->gradients(qx, qy, qz, out + b, m);
    for (std::size_t i = 0; i < m; ++i) {
      Grad& g = out[b + i];
      const Vec3 d = map_.apply_transposed({g.dx, g.dy, g.dz});
      g.dx = static_cast<float>(d.x);
      g.dy = static_cast<float>(d.y);
      g.dz = static_cast<float>(d.z);
    }
  }
}

void TransformedOracle::bounds(const Interval* x, const Interval* y, const Interval* z, Interval* out,
                               std::size_t n) const {
  const double lip = base_->lipschitz(), stretch = map_.stretch_bound();
  float qx[kChunk], qy[kChunk], qz[kChunk], v[kChunk];
  double radius[kChunk], scale[kChunk];
  for (std::size_t b = 0; b < n; b += kChunk) {
    const std::size_t m = std::min(kChunk, n - b);
    for (std::size_t k = 0; k < m; ++k) {
      const BoxCentre c = box_centre(x[b + k], y[b + k], z[b + k]);
      const Vec3 q = map_.apply({c.c[0], c.c[1], c.c[2]});
      qx[k] = static_cast<float>(q.x);
      qy[k] = static_cast<float>(q.y);
      qz[k] = static_cast<float>(q.z);
      const double r = stretch * c.half_diagonal;
      scale[k] = std::max({std::fabs(q.x), std::fabs(q.y), std::fabs(q.z)}) + r;
      // Each mapped point is off its exact image by half an ulp per coordinate, the centre too.
      radius[k] = r + 2 * std::sqrt(3.0) * 0x1p-24 * scale[k];
    }
    base_->values(qx, qy, qz, v, m);
    for (std::size_t k = 0; k < m; ++k) {
      constexpr float kInf = std::numeric_limits<float>::infinity();
      out[b + k] = std::isnan(v[k]) || !(lip > 0) || !std::isfinite(radius[k])
                       ? Interval::unknown()
                       : lipschitz_bound({-kInf, kInf}, Interval::point(v[k]), lip, radius[k], scale[k]);
    }
  }
}

Box3 TransformedOracle::inside_box() const {
  const Box3 b = base_->inside_box();
  if (b.empty()) return b;
  // The corners of the base's box mapped back through the inverse map.
  const std::optional<Affine3> inv = map_.inverse();
  if (!inv) return {};
  Box3 out;
  for (int c = 0; c < 8; ++c)
    out.add(inv->apply({(c & 1) ? b.hi.x : b.lo.x, (c & 2) ? b.hi.y : b.lo.y, (c & 4) ? b.hi.z : b.lo.z}));
  // The inverse is rounded: grow the box by a little of its size.
  const Vec3 s = out.size();
  const double pad = 1e-9 * (std::max({s.x, s.y, s.z}) + std::max({std::fabs(out.lo.x), std::fabs(out.lo.y), std::fabs(out.lo.z),
                                                                     std::fabs(out.hi.x), std::fabs(out.hi.y), std::fabs(out.hi.z)}));
  return out.inflated(pad);
}

std::string TransformedOracle::describe() const {
  char buf[400];
  std::snprintf(buf, sizeof buf, " at p -> [%.6g %.6g %.6g %.6g; %.6g %.6g %.6g %.6g; %.6g %.6g %.6g %.6g] p", map_.m[0][0],
                map_.m[0][1], map_.m[0][2], map_.m[0][3], map_.m[1][0], map_.m[1][1], map_.m[1][2], map_.m[1][3], map_.m[2][0],
                map_.m[2][1], map_.m[2][2], map_.m[2][3]);
  return base_->describe() + buf;
}

NodeId TransformedOracle::closed_form(Graph& g) const {
  const NodeId f = base_->closed_form(g);
  return remap(g, f, affine_row(g, map_, 0), affine_row(g, map_, 1), affine_row(g, map_, 2));
}

std::optional<Oracle::RayHit> TransformedOracle::first_hit(const Vec3& o, const Vec3& dir, double t_max) const {
  // a(o + t dir) = a(o) + t M dir: the same t along the mapped ray.
  const Vec3 mo = map_.apply(o);
  const Vec3 md = map_.apply(dir) - map_.apply({0, 0, 0});
  std::optional<RayHit> h = base_->first_hit(mo, md, t_max);
  if (h) {
    // The gradient of f(a(p)) is M^T times the base's.
    const Vec3 n = map_.apply_transposed(h->normal);
    const double l = length(n);
    h->normal = l > 0 ? n / l : Vec3{};
  }
  return h;
}

std::shared_ptr<const Oracle> TransformedOracle::transformed(const Affine3& a) const {
  const Affine3 total = map_ * a;  // f(M(a(p)))
  if (total.is_identity()) return base_;
  return std::make_shared<TransformedOracle>(base_, total);
}

GradientOracle::GradientOracle(std::shared_ptr<const Oracle> base, int axis) : base_(std::move(base)), axis_(axis) {
  FREP_ASSERT(axis >= 0 && axis < 3, "an axis is 0, 1 or 2");
}

void GradientOracle::values(const float* x, const float* y, const float* z, float* out, std::size_t n) const {
  Grad g[kChunk];
  for (std::size_t b = 0; b < n; b += kChunk) {
    const std::size_t m = std::min(kChunk, n - b);
    base_->gradients(x + b, y + b, z + b, g, m);
    for (std::size_t i = 0; i < m; ++i) out[b + i] = axis_ == 0 ? g[i].dx : axis_ == 1 ? g[i].dy : g[i].dz;
  }
}

void GradientOracle::gradients(const float* x, const float* y, const float* z, Grad* out, std::size_t n) const {
  // Second derivatives are not known: the values with a zero gradient (the convention of
  // piecewise-constant ops).
  float v[kChunk];
  for (std::size_t b = 0; b < n; b += kChunk) {
    const std::size_t m = std::min(kChunk, n - b);
    values(x + b, y + b, z + b, v, m);
    for (std::size_t i = 0; i < m; ++i) out[b + i] = {v[i], 0, 0, 0};
  }
}

void GradientOracle::bounds(const Interval*, const Interval*, const Interval*, Interval* out, std::size_t n) const {
  const double l = base_->lipschitz();
  const float b = static_cast<float>(l * (1 + 1e-6));
  for (std::size_t k = 0; k < n; ++k) out[k] = l > 0 ? Interval{-b, b} : Interval::unknown();
}

std::string GradientOracle::describe() const { return std::string("d/d") + "xyz"[axis_] + " of " + base_->describe(); }

NodeId GradientOracle::closed_form(Graph& g) const {
  Differentiator d(g);
  const Gradient gr = d.grad(base_->closed_form(g));
  return (axis_ == 0 ? gr.x : axis_ == 1 ? gr.y : gr.z).id();
}

}  // namespace frep
