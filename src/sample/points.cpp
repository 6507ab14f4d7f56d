// Point sampling for learning: uniform and near-surface points with signed distances, from
// meshes (exact oracle) and expressions (pruned point-cloud evaluator).
#include "frep/sample/points.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "frep/error.hpp"
#include "frep/eval/point_cloud.hpp"
#include "frep/mesh/mesh_field.hpp"
#include "frep/util/memory_budget.hpp"
#include "frep/util/thread_pool.hpp"

namespace frep {
namespace {

// Counter-based random numbers: SplitMix64 of (seed, stream, index), so that every value
// depends only on where it is used.
std::uint64_t mix(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}
struct Rng {
  std::uint64_t state;
  Rng(std::uint64_t seed, std::uint64_t stream, std::uint64_t index)
      : state(mix(mix(seed ^ mix(stream)) ^ index)) {}
  std::uint64_t next() { return mix(state += 0x9e3779b97f4a7c15ull); }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  double gaussian() {
    // Box-Muller; 1 - u is in (0, 1], so the log is finite.
    const double u = 1.0 - uniform(), v = uniform();
    return std::sqrt(-2.0 * std::log(u)) * std::cos(2 * 3.14159265358979323846 * v);
  }
};

enum Stream : std::uint64_t { kUniform = 1, kSurface, kNoise, kSeedPoints };

void check_box(const Box3& b) {
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(b.lo[a]) || !std::isfinite(b.hi[a]) || !(b.lo[a] <= b.hi[a]))
      throw InputError("", 0, "sample bounds must be finite with lo <= hi on every axis");
}

Vec3 uniform_in(Rng& r, const Box3& b) {
  Vec3 p;
  for (int a = 0; a < 3; ++a) p[a] = b.lo[a] + (b.hi[a] - b.lo[a]) * r.uniform();
  return p;
}

void check_sigma(double sigma) {
  if (!std::isfinite(sigma) || sigma < 0) throw InputError("", 0, "sigma must be a finite number >= 0");
}

// Fills the distances of rows whose coordinates are set, from the mesh.
void mesh_distances(const MeshField& field, std::vector<float>& rows, int threads) {
  const std::size_t n = rows.size() / 4;
  parallel_for_ranges(threads, n, 1024, [&](int, std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i)
      rows[4 * i + 3] = static_cast<float>(field.signed_distance({rows[4 * i], rows[4 * i + 1], rows[4 * i + 2]}));
  });
}

void tape_distances(const Tape& tape, std::vector<float>& rows, int threads) {
  const std::size_t n = rows.size() / 4;
  std::vector<float> xs(n), ys(n), zs(n), vs(n);
  for (std::size_t i = 0; i < n; ++i) xs[i] = rows[4 * i], ys[i] = rows[4 * i + 1], zs[i] = rows[4 * i + 2];
  PointCloudOptions po;
  po.threads = threads;
  eval_points(tape, xs.data(), ys.data(), zs.data(), vs.data(), n, po);
  for (std::size_t i = 0; i < n; ++i) rows[4 * i + 3] = vs[i];
}

void set_point(std::vector<float>& rows, std::size_t i, const Vec3& p) {
  rows[4 * i] = static_cast<float>(p.x), rows[4 * i + 1] = static_cast<float>(p.y), rows[4 * i + 2] = static_cast<float>(p.z);
}

// Refuses a point count whose rows (16 bytes each) and scratch would not fit in memory.
void check_count(std::size_t count, std::uint64_t bytes_per_point) {
  require_memory(count, bytes_per_point, "sampling " + std::to_string(count) + " points", "sample fewer points");
}

// A point moved by the noise must stay a float32 point (rows are float32).
void set_noisy_point(std::vector<float>& rows, std::size_t i, const Vec3& p, double sigma) {
  set_point(rows, i, p);
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(rows[4 * i + static_cast<std::size_t>(k)])) {
      char msg[160];
      std::snprintf(msg, sizeof msg, "sigma %g moves points beyond the range of 32-bit floats; give a smaller --sigma", sigma);
      throw InputError("", 0, msg);
    }
}

std::vector<float> uniform_rows(const Box3& b, std::size_t count, std::uint64_t seed) {
  check_box(b);
  std::vector<float> rows(4 * count);
  for (std::size_t i = 0; i < count; ++i) {
    Rng r(seed, kUniform, i);
    set_point(rows, i, uniform_in(r, b));
  }
  return rows;
}

}  // namespace

std::vector<float> sample_uniform(const MeshField& field, const Box3& bounds, std::size_t count,
                                  const PointSampleOptions& o) {
  check_count(count, 16);
  std::vector<float> rows = uniform_rows(bounds, count, o.seed);
  mesh_distances(field, rows, o.threads);
  return rows;
}

std::vector<float> sample_near_surface(const MeshField& field, std::size_t count, double sigma,
                                       const PointSampleOptions& o) {
  check_sigma(sigma);
  check_count(count, 16);
  const TriMesh& m = field.welded();
  // Cumulative areas of the triangles: a uniform draw over the total picks one by area.
  std::vector<double> cum(m.triangles.size());
  double total = 0;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    total += 0.5 * length(cross(m.corner(t, 1) - m.corner(t, 0), m.corner(t, 2) - m.corner(t, 0)));
    cum[t] = total;
  }
  if (!(total > 0)) throw InputError(m.name, 0, "the mesh has no area to sample");
  std::vector<float> rows(4 * count);
  for (std::size_t i = 0; i < count; ++i) {
    Rng r(o.seed, kSurface, i);
    const double u = r.uniform() * total;
    const std::size_t t = std::min<std::size_t>(
        static_cast<std::size_t>(std::upper_bound(cum.begin(), cum.end(), u) - cum.begin()), cum.size() - 1);
    // Uniform in the triangle: (1 - sqrt r1) a + sqrt r1 (1 - r2) b + sqrt r1 r2 c.
    const double s = std::sqrt(r.uniform()), r2 = r.uniform();
    Vec3 p = m.corner(t, 0) * (1 - s) + m.corner(t, 1) * (s * (1 - r2)) + m.corner(t, 2) * (s * r2);
    Rng g(o.seed, kNoise, i);
    p += Vec3{g.gaussian(), g.gaussian(), g.gaussian()} * sigma;
    set_noisy_point(rows, i, p, sigma);
  }
  mesh_distances(field, rows, o.threads);
  return rows;
}

std::vector<float> sample_uniform(const Tape& tape, const Box3& bounds, std::size_t count,
                                  const PointSampleOptions& o) {
  check_count(count, 32);  // rows, and the evaluator's coordinate and value columns
  std::vector<float> rows = uniform_rows(bounds, count, o.seed);
  tape_distances(tape, rows, o.threads);
  return rows;
}

std::vector<float> sample_near_surface(const Tape& tape, const Box3& bounds, std::size_t count, double sigma,
                                       const PointSampleOptions& o) {
  check_sigma(sigma);
  check_count(count, 32 + 4 * 28);  // rows, and rounds of 4 seed points each (coordinates, gradients)
  check_box(bounds);
  const float tol = static_cast<float>(1e-6 * length(bounds.size()));
  PointCloudOptions po;
  po.threads = o.threads;
  PointCloudEvaluator eval(po);
  std::vector<Vec3f> surface;
  surface.reserve(count);
  // Seed points come in rounds, numbered globally, so the kept points depend on the seed alone.
  std::uint64_t next_seed = 0;
  const std::size_t batch = std::max<std::size_t>(4 * count, 4096);
  for (int round = 0; surface.size() < count; ++round) {
    if (round >= 8)
      throw InputError("", 0,
                       "found only " + std::to_string(surface.size()) + " of " + std::to_string(count) +
                           " surface points in the bounds (is the surface f = 0 inside them?)");
    std::vector<float> xs(batch), ys(batch), zs(batch);
    for (std::size_t i = 0; i < batch; ++i) {
      Rng r(o.seed, kSeedPoints, next_seed++);
      const Vec3 p = uniform_in(r, bounds);
      xs[i] = static_cast<float>(p.x), ys[i] = static_cast<float>(p.y), zs[i] = static_cast<float>(p.z);
    }
    std::vector<Grad> g(batch);
    for (int step = 0; step < 16; ++step) {
      eval.eval_grad(tape, xs.data(), ys.data(), zs.data(), g.data(), batch);
      for (std::size_t i = 0; i < batch; ++i) {
        const Grad& q = g[i];
        if (std::fabs(q.v) <= tol) continue;  // converged: stays put
        const float n2 = q.dx * q.dx + q.dy * q.dy + q.dz * q.dz;
        if (!(n2 > 0) || !std::isfinite(q.v)) continue;
        const float s = q.v / n2;
        xs[i] -= s * q.dx, ys[i] -= s * q.dy, zs[i] -= s * q.dz;
      }
    }
    eval.eval_grad(tape, xs.data(), ys.data(), zs.data(), g.data(), batch);
    for (std::size_t i = 0; i < batch && surface.size() < count; ++i) {
      const Vec3 p{xs[i], ys[i], zs[i]};
      if (std::fabs(g[i].v) <= tol && bounds.contains(p)) surface.push_back(Vec3f(p));
    }
  }
  std::vector<float> rows(4 * count);
  for (std::size_t i = 0; i < count; ++i) {
    Rng g(o.seed, kNoise, i);
    const Vec3 p = Vec3(surface[i]) + Vec3{g.gaussian(), g.gaussian(), g.gaussian()} * sigma;
    set_noisy_point(rows, i, p, sigma);
  }
  tape_distances(tape, rows, o.threads);
  return rows;
}

}  // namespace frep
