// Newton steps along the gradient, batched over all points; gradients analytic or by central
// differences.
#include "frep/contour/snap.hpp"

#include <cmath>

#include "frep/error.hpp"

namespace frep {
namespace {

bool finite3(double x, double y, double z) { return std::isfinite(x) && std::isfinite(y) && std::isfinite(z); }
Vec3 clamp_to(const Box3& b, const Vec3& p) { return max(b.lo, min(b.hi, p)); }

}  // namespace

void SurfaceSnapper::snap(const Tape& tape, std::span<Vec3> points, std::span<const Box3> keep_in, double max_step,
                          const SnapOptions& options, std::vector<Vec3f>* normals) {
  FREP_ASSERT(points.size() == keep_in.size(), "one box per point");
  const std::size_t n = points.size();
  // Per point: value and gradient at the current position.
  std::vector<Grad>& g = g_;
  g.resize(n);
  const bool central = options.gradient == SnapGradient::CentralDifferences;
  const double d = options.difference_step * max_step;

  auto evaluate = [&] {
    xs_.resize(n * (central ? 7 : 1));
    ys_.resize(xs_.size());
    zs_.resize(xs_.size());
    for (std::size_t i = 0; i < n; ++i) {
      xs_[i] = static_cast<float>(points[i].x);
      ys_[i] = static_cast<float>(points[i].y);
      zs_[i] = static_cast<float>(points[i].z);
    }
    if (!central) {
      grads_.eval(tape, xs_.data(), ys_.data(), zs_.data(), g.data(), n);
      return;
    }
    // Six neighbours per point, kept inside the point's box (one-sided at its walls); the
    // actual spacing is used for the quotient.
    for (std::size_t i = 0; i < n; ++i)
      for (int a = 0; a < 3; ++a)
        for (int s = 0; s < 2; ++s) {
          Vec3 q = points[i];
          q[a] += s ? d : -d;
          q = clamp_to(keep_in[i], q);
          const std::size_t k = n * (1 + 2 * static_cast<std::size_t>(a) + static_cast<std::size_t>(s)) + i;
          xs_[k] = static_cast<float>(q.x);
          ys_[k] = static_cast<float>(q.y);
          zs_[k] = static_cast<float>(q.z);
        }
    out_.resize(xs_.size());
    values_.eval(tape, xs_.data(), ys_.data(), zs_.data(), out_.data(), xs_.size());
    for (std::size_t i = 0; i < n; ++i) {
      float dv[3];
      for (int a = 0; a < 3; ++a) {
        const std::size_t km = n * (1 + 2 * static_cast<std::size_t>(a)) + i, kp = km + n;
        const float* c[3] = {xs_.data(), ys_.data(), zs_.data()};
        const double span = static_cast<double>(c[a][kp]) - static_cast<double>(c[a][km]);
        dv[a] = span > 0 ? static_cast<float>((static_cast<double>(out_[kp]) - out_[km]) / span) : 0.0f;
      }
      g[i] = {out_[i], dv[0], dv[1], dv[2]};
    }
  };

  for (int it = 0; it < options.iterations; ++it) {
    evaluate();
    for (std::size_t i = 0; i < n; ++i) {
      const double f = g[i].v, gx = g[i].dx, gy = g[i].dy, gz = g[i].dz;
      const double g2 = gx * gx + gy * gy + gz * gz;
      if (!std::isfinite(f) || !finite3(gx, gy, gz) || !(g2 > 1e-30) || f == 0) continue;
      Vec3 step = Vec3{gx, gy, gz} * (-f / g2);
      const double len = length(step);
      if (!std::isfinite(len)) continue;
      if (len > max_step) step *= max_step / len;
      points[i] = clamp_to(keep_in[i], points[i] + step);
    }
  }
  if (normals) {
    evaluate();
    normals->resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double gx = g[i].dx, gy = g[i].dy, gz = g[i].dz;
      const double l = std::sqrt(gx * gx + gy * gy + gz * gz);
      (*normals)[i] = finite3(gx, gy, gz) && l > 1e-30 ? Vec3f(Vec3{gx / l, gy / l, gz / l}) : Vec3f{};
    }
  }
}

}  // namespace frep
