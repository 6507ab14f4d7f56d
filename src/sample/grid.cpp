// Grid layout, and dense grids of signed distances from meshes (closest point transform or
// oracle queries) and from expressions (interval pruning depth first, SIMD batches at the leaves).
#include "frep/sample/grid.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/sample/mesh_field.hpp"
#include "frep/util/thread_pool.hpp"
#include "sample/cpt.hpp"

namespace frep {

double GridSpec::coord(int axis, int i) const {
  const int n = counts[axis];
  const double lo = bounds.lo[axis], hi = bounds.hi[axis];
  if (i == 0) return lo;
  if (i == n - 1) return hi;
  return (static_cast<double>(n - 1 - i) * lo + static_cast<double>(i) * hi) / static_cast<double>(n - 1);
}

void GridSpec::check() const {
  for (int a = 0; a < 3; ++a) {
    if (counts[a] < 2 || counts[a] > 4096)
      throw InputError("", 0, "grid size must be between 2 and 4096 samples per axis, got " + std::to_string(counts[a]));
    if (!std::isfinite(bounds.lo[a]) || !std::isfinite(bounds.hi[a]) || !(bounds.lo[a] < bounds.hi[a]))
      throw InputError("", 0, "grid bounds must be finite with lo < hi on every axis");
  }
}

GridSpec cube_grid(const Box3& bounds, int n) { return GridSpec{bounds, {n, n, n}}; }

Box3 default_mesh_bounds(const Box3& b, double margin) {
  const Vec3 c = b.center(), s = b.size();
  const double half = 0.5 * std::max({s.x, s.y, s.z}) + margin * length(s);
  return {c - Vec3{half, half, half}, c + Vec3{half, half, half}};
}

namespace {

template <class T>
std::vector<T> sample_mesh(const MeshField& field, const GridSpec& grid, const MeshGridOptions& o, MeshGridStats* st) {
  grid.check();
  const auto t0 = std::chrono::steady_clock::now();
  const bool inside = grid.bounds.contains(field.box().lo) && grid.bounds.contains(field.box().hi);
  const bool cpt_ok = field.solid() && field.sign() == SignMethod::Pseudonormal && inside;
  MeshGridStats stats;
  stats.method = o.method == MeshGridMethod::Auto ? (cpt_ok ? MeshGridMethod::Cpt : MeshGridMethod::Queries) : o.method;
  if (stats.method == MeshGridMethod::Cpt && !cpt_ok)
    throw InputError("", 0,
                     field.solid() && field.sign() == SignMethod::Pseudonormal
                         ? "the closest point transform needs grid bounds that contain the mesh"
                         : "the closest point transform needs a valid solid with pseudonormal signs (" +
                               field.summary() + ")");
  std::vector<T> out(grid.size());
  ThreadPool pool(o.threads);
  if (stats.method == MeshGridMethod::Cpt) {
    sample_detail::closest_point_transform(field, grid, pool, out.data(), o, stats);
  } else {
    std::vector<double> ys(static_cast<std::size_t>(grid.counts[1])), zs(static_cast<std::size_t>(grid.counts[2]));
    for (int j = 0; j < grid.counts[1]; ++j) ys[static_cast<std::size_t>(j)] = grid.coord(1, j);
    for (int k = 0; k < grid.counts[2]; ++k) zs[static_cast<std::size_t>(k)] = grid.coord(2, k);
    std::atomic<int> done{0};
    pool.parallel_for(grid.counts[0], [&](int, int i) {
      const double x = grid.coord(0, i);
      for (int j = 0; j < grid.counts[1]; ++j)
        for (int k = 0; k < grid.counts[2]; ++k)
          out[grid.index(i, j, k)] =
              static_cast<T>(field.signed_distance({x, ys[static_cast<std::size_t>(j)], zs[static_cast<std::size_t>(k)]}));
      if (o.progress) o.progress("queries", static_cast<double>(++done) / grid.counts[0]);
    });
  }
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (st) *st = stats;
  return out;
}

}  // namespace

std::vector<float> sample_grid(const MeshField& field, const GridSpec& grid, const MeshGridOptions& options,
                               MeshGridStats* stats) {
  return sample_mesh<float>(field, grid, options, stats);
}

std::vector<double> sample_grid_f64(const MeshField& field, const GridSpec& grid, const MeshGridOptions& options,
                                    MeshGridStats* stats) {
  return sample_mesh<double>(field, grid, options, stats);
}

std::vector<float> sample_grid(const Tape& tape, const GridSpec& grid, const ExprGridOptions& options) {
  grid.check();
  FREP_ASSERT(!tape.code().empty(), "grid sampling needs a tape with register code");
  const std::vector<int>& tiles = options.tiles;
  if (tiles.empty() || tiles.back() < 1 || !std::is_sorted(tiles.rbegin(), tiles.rend()))
    throw std::invalid_argument("grid tiles must be positive and not increase");
  std::array<std::vector<float>, 3> coords;
  for (int a = 0; a < 3; ++a) {
    coords[a].resize(static_cast<std::size_t>(grid.counts[a]));
    for (int i = 0; i < grid.counts[a]; ++i) coords[a][static_cast<std::size_t>(i)] = static_cast<float>(grid.coord(a, i));
  }
  std::vector<float> out(grid.size());
  // Depth first per top-level box, each worker keeping one simplified tape per level. Not the
  // shared subdivision driver: it keeps the simplified tapes of its whole breadth-first frontier,
  // and a sampler settles no box, so for a converted mesh (millions of instructions) that frontier
  // alone took more than 14 GB at 64^3.
  struct Worker {
    IntervalEvaluator interval;
    BatchEvaluator batch;
    std::vector<Tape> tapes;
    std::vector<float> xs, ys, zs, vs;
  };
  ThreadPool pool(options.threads);
  std::vector<std::unique_ptr<Worker>> workers;
  for (int w = 0; w < pool.size(); ++w) {
    workers.push_back(std::make_unique<Worker>());
    workers.back()->tapes.resize(tiles.size());
  }
  using Box = std::array<std::array<int, 2>, 3>;  // [lo, hi) per axis
  auto children = [&](const Box& b, int edge, auto&& fn) {
    for (int i = b[0][0]; i < b[0][1]; i += edge)
      for (int j = b[1][0]; j < b[1][1]; j += edge)
        for (int k = b[2][0]; k < b[2][1]; k += edge)
          fn(Box{{{i, std::min(i + edge, b[0][1])}, {j, std::min(j + edge, b[1][1])}, {k, std::min(k + edge, b[2][1])}}});
  };
  auto visit = [&](auto&& self, Worker& w, const Box& b, std::size_t level, const Tape& parent) -> void {
    Tape& t = w.tapes[level];
    auto range = [&](int a) {
      return Interval{coords[a][static_cast<std::size_t>(b[a][0])], coords[a][static_cast<std::size_t>(b[a][1] - 1)]};
    };
    w.interval.simplify(parent, range(0), range(1), range(2), t);
    if (level + 1 < tiles.size()) {
      children(b, tiles[level + 1], [&](const Box& c) { self(self, w, c, level + 1, t); });
      return;
    }
    // Leaf: its samples in C order, evaluated in one batch and copied row by row.
    const std::size_t nz = static_cast<std::size_t>(b[2][1] - b[2][0]);
    const std::size_t count = static_cast<std::size_t>(b[0][1] - b[0][0]) * static_cast<std::size_t>(b[1][1] - b[1][0]) * nz;
    w.xs.resize(count), w.ys.resize(count), w.zs.resize(count), w.vs.resize(count);
    std::size_t n = 0;
    for (int i = b[0][0]; i < b[0][1]; ++i)
      for (int j = b[1][0]; j < b[1][1]; ++j)
        for (int k = b[2][0]; k < b[2][1]; ++k, ++n) {
          w.xs[n] = coords[0][static_cast<std::size_t>(i)];
          w.ys[n] = coords[1][static_cast<std::size_t>(j)];
          w.zs[n] = coords[2][static_cast<std::size_t>(k)];
        }
    w.batch.eval(t, w.xs.data(), w.ys.data(), w.zs.data(), w.vs.data(), count);
    n = 0;
    for (int i = b[0][0]; i < b[0][1]; ++i)
      for (int j = b[1][0]; j < b[1][1]; ++j, n += nz) std::copy_n(w.vs.data() + n, nz, out.data() + grid.index(i, j, b[2][0]));
  };
  std::vector<Box> top;
  children(Box{{{0, grid.counts[0]}, {0, grid.counts[1]}, {0, grid.counts[2]}}}, tiles[0],
           [&](const Box& c) { top.push_back(c); });
  pool.parallel_for(static_cast<int>(top.size()), [&](int wi, int i) {
    visit(visit, *workers[static_cast<std::size_t>(wi)], top[static_cast<std::size_t>(i)], 0, tape);
  });
  return out;
}

}  // namespace frep
