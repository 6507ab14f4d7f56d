// Oracles: leaves of the graph whose value is computed by code rather than by an expression
// (libfive's name for them). The one frep ships is a mesh's exact signed distance
// (frep/convert/mesh_oracle.hpp), evaluated through its distance structure instead of the
// mesh's closed form of ~75 nodes per triangle.
//
// An oracle is a node like x or a constant (Graph::oracle). Every evaluator calls it: the point
// and batch evaluators for values, the gradient evaluator for values and gradients, the interval
// evaluators for bounds over boxes. So an expression that mixes oracles with anything else (a
// mesh minus a sphere, an offset, a union of two meshes) runs wherever expressions run, and a
// new evaluator backend only has to call out to the same three functions.
//
// File formats other tools read hold no oracles: writers replace each by its closed form
// (closed_form), which is the same field as an ordinary expression.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <string>

#include "frep/math/grad.hpp"
#include "frep/math/interval.hpp"
#include "frep/expr/graph.hpp"
#include "frep/math/affine.hpp"
#include "frep/math/vec.hpp"

namespace frep {

class Oracle : public std::enable_shared_from_this<Oracle> {
 public:
  virtual ~Oracle() = default;

  // f at n points, in float (the exact value rounded once). NaN coordinates give NaN. Called
  // from many threads at once.
  virtual void values(const float* x, const float* y, const float* z, float* out, std::size_t n) const = 0;
  // f and its gradient at n points (see the implementation for the convention where f has no
  // derivative).
  virtual void gradients(const float* x, const float* y, const float* z, Grad* out, std::size_t n) const = 0;
  // Intervals holding every value over the boxes x[k] * y[k] * z[k], k < n. This default: the
  // value at the box's centre +- lipschitz() times its half-diagonal (lipschitz_bound), or
  // unknown if lipschitz() is 0. Boxes with the same centre share one evaluation (the
  // subdivision driver evaluates boxes and their centres in one pass).
  virtual void bounds(const Interval* x, const Interval* y, const Interval* z, Interval* out, std::size_t n) const;

  // A bound L on |f(p) - f(q)| / |p - q| (1 for an exact distance), or 0 if unknown.
  virtual double lipschitz() const = 0;
  // A box holding every point where f is negative, or an empty box if unknown.
  virtual Box3 inside_box() const { return {}; }
  // One line for messages and frep info, such as "mesh part.stl (20,000 triangles)".
  virtual std::string describe() const = 0;
  // The same field as an ordinary expression of g's x, y and z, built in g: what writers of
  // expression files and exports write in its place. May take long (a mesh's closed form).
  virtual NodeId closed_form(Graph& g) const = 0;

  // The oracle evaluated at a(p) instead of p (moved, rotated, scaled). This default wraps it;
  // wrapping a wrapper composes the maps.
  virtual std::shared_ptr<const Oracle> transformed(const Affine3& a) const;

  // Rays, for oracles that can intersect them exactly (a mesh): the first point of o + t dir
  // with t in [0, t_max] on the surface f = 0, and the unit normal there (the direction of the
  // gradient). nullopt where the ray meets nothing, and always for oracles without rays
  // (casts_rays() false). Renderers cast rays through a model that is one such oracle instead of
  // searching its columns.
  struct RayHit {
    double t = 0;
    Vec3 normal;
  };
  virtual bool casts_rays() const { return false; }
  virtual std::optional<RayHit> first_hit(const Vec3& o, const Vec3& dir, double t_max) const;
};

// f(a(p)) for an oracle f: what moving, rotating or scaling an oracle gives.
class TransformedOracle final : public Oracle {
 public:
  // `a` must be finite.
  TransformedOracle(std::shared_ptr<const Oracle> base, const Affine3& a);

  const Oracle& base() const { return *base_; }
  const Affine3& map() const { return map_; }

  void values(const float* x, const float* y, const float* z, float* out, std::size_t n) const override;
  void gradients(const float* x, const float* y, const float* z, Grad* out, std::size_t n) const override;
  // The base's value at the mapped centre +- its bound times the mapped radius, which also covers
  // the rounding of mapped points to float (in the base's coordinates, far from the origin
  // maybe).
  void bounds(const Interval* x, const Interval* y, const Interval* z, Interval* out, std::size_t n) const override;
  double lipschitz() const override { return lipschitz_; }
  Box3 inside_box() const override;
  std::string describe() const override;
  NodeId closed_form(Graph& g) const override;
  std::shared_ptr<const Oracle> transformed(const Affine3& a) const override;
  bool casts_rays() const override { return base_->casts_rays(); }
  std::optional<RayHit> first_hit(const Vec3& o, const Vec3& dir, double t_max) const override;

 private:
  // The mapped points, in float (the base's coordinates), n at most kChunk at a time.
  static constexpr std::size_t kChunk = 256;
  void map_points(const float* x, const float* y, const float* z, float* qx, float* qy, float* qz, std::size_t n) const;
  std::shared_ptr<const Oracle> base_;
  Affine3 map_;
  double lipschitz_;
};

// One partial derivative of an oracle, d f / d axis, as an oracle of its own: what symbolic
// gradients (frep/expr/derivative.hpp) make of an oracle leaf, so that operations built on
// gradients (normalization, edge frames, medial surfaces) apply to meshes too. Its values are the
// base's gradients() component; its bounds are [-L, L] for the base's Lipschitz bound L (unknown
// without one); its closed form is the derivative of the base's closed form.
class GradientOracle final : public Oracle {
 public:
  GradientOracle(std::shared_ptr<const Oracle> base, int axis);

  void values(const float* x, const float* y, const float* z, float* out, std::size_t n) const override;
  void gradients(const float* x, const float* y, const float* z, Grad* out, std::size_t n) const override;
  void bounds(const Interval* x, const Interval* y, const Interval* z, Interval* out, std::size_t n) const override;
  double lipschitz() const override { return 0; }
  std::string describe() const override;
  NodeId closed_form(Graph& g) const override;

 private:
  static constexpr std::size_t kChunk = 256;
  std::shared_ptr<const Oracle> base_;
  int axis_;
};

}  // namespace frep
