// Grid layout, and dense grids of signed distances from meshes (closest point transform or
// oracle queries) and from expressions (the subdivision driver, SIMD batches at the leaves).
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
#include "frep/eval/subdivision.hpp"
#include "frep/mesh/mesh_field.hpp"
#include "frep/util/memory_budget.hpp"
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

void check_truncation(double d) {
  if (!(d >= 0) || !std::isfinite(d))
    throw InputError("", 0, "the truncation distance must be a finite number > 0 (0: no truncation), got " + std::to_string(d));
}

std::string grid_job(const GridSpec& g) {
  return "a grid of " + std::to_string(g.counts[0]) + " x " + std::to_string(g.counts[1]) + " x " +
         std::to_string(g.counts[2]) + " samples";
}

template <class T>
std::vector<T> sample_mesh(const MeshField& field, const GridSpec& grid, const MeshGridOptions& o, MeshGridStats* st) {
  grid.check();
  check_truncation(o.truncate);
  const auto t0 = std::chrono::steady_clock::now();
  // The transform's reach walk needs the whole mesh in the grid; a truncated transform with a
  // narrow band does without it (see cpt.hpp).
  const bool inside = (grid.bounds.contains(field.box().lo) && grid.bounds.contains(field.box().hi)) ||
                      sample_detail::truncation_scans_band(grid, o.truncate);
  const bool cpt_ok = field.solid() && field.sign() == SignMethod::Pseudonormal && inside;
  MeshGridStats stats;
  stats.method = o.method == MeshGridMethod::Auto ? (cpt_ok ? MeshGridMethod::Cpt : MeshGridMethod::Queries) : o.method;
  if (stats.method == MeshGridMethod::Cpt && !cpt_ok)
    throw InputError("", 0,
                     field.solid() && field.sign() == SignMethod::Pseudonormal
                         ? "the closest point transform needs grid bounds that contain the mesh (or a truncation of "
                           "at most " + std::to_string(static_cast<int>(sample_detail::kScanBandVoxels)) + " voxels)"
                         : "the closest point transform needs a valid solid with pseudonormal signs (" +
                               field.summary() + ")");
  // The output, and the transform's nearest squared distance (double) and owner per sample: of
  // every sample, or for a truncated grid, of the rows (i, j) within the band of the mesh's box.
  std::uint64_t scratch = stats.method == MeshGridMethod::Cpt ? grid.size() : 0;
  if (scratch && o.truncate > 0) {
    const Box3 near = field.box().inflated(2 * sample_detail::truncation_band(grid, o.truncate));
    std::uint64_t along[2] = {0, 0};
    for (int a = 0; a < 2; ++a)
      for (int i = 0; i < grid.counts[a]; ++i) along[a] += grid.coord(a, i) >= near.lo[a] && grid.coord(a, i) <= near.hi[a];
    scratch = along[0] * along[1] * static_cast<std::uint64_t>(grid.counts[2]);
  }
  require_memory(grid.size(), sizeof(T) + (12 * scratch + grid.size() - 1) / grid.size(), grid_job(grid),
                 "sample a smaller grid");
  std::vector<T> out(grid.size());
  ThreadPool pool(o.threads);
  if (stats.method == MeshGridMethod::Cpt) {
    sample_detail::closest_point_transform(field, grid, pool, out.data(), o, stats);
  } else {
    std::vector<double> ys(static_cast<std::size_t>(grid.counts[1])), zs(static_cast<std::size_t>(grid.counts[2]));
    for (int j = 0; j < grid.counts[1]; ++j) ys[static_cast<std::size_t>(j)] = grid.coord(1, j);
    for (int k = 0; k < grid.counts[2]; ++k) zs[static_cast<std::size_t>(k)] = grid.coord(2, k);
    std::atomic<int> done{0};
    // Truncated: every sample is queried and clamped (the oracle is exact, so the clamp is too).
    const double d = o.truncate > 0 ? o.truncate : INFINITY;
    pool.parallel_for(grid.counts[0], [&](int, int i) {
      const double x = grid.coord(0, i);
      for (int j = 0; j < grid.counts[1]; ++j)
        for (int k = 0; k < grid.counts[2]; ++k)
          out[grid.index(i, j, k)] = static_cast<T>(std::clamp(
              field.signed_distance({x, ys[static_cast<std::size_t>(j)], zs[static_cast<std::size_t>(k)]}), -d, d));
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
  check_truncation(options.truncate);
  if (!(options.lipschitz >= 0) || !std::isfinite(options.lipschitz))
    throw std::invalid_argument("the Lipschitz bound must be finite and >= 0");
  FREP_ASSERT(!tape.code().empty(), "grid sampling needs a tape with register code");
  const std::vector<int>& tiles = options.tiles;
  if (tiles.empty() || tiles.back() < 1 || !std::is_sorted(tiles.rbegin(), tiles.rend()))
    throw std::invalid_argument("grid tiles must be positive and not increase");
  std::array<std::vector<float>, 3> coords;
  for (int a = 0; a < 3; ++a) {
    coords[a].resize(static_cast<std::size_t>(grid.counts[a]));
    for (int i = 0; i < grid.counts[a]; ++i) coords[a][static_cast<std::size_t>(i)] = static_cast<float>(grid.coord(a, i));
  }
  require_memory(grid.size(), sizeof(float), grid_job(grid), "sample a smaller grid");
  std::vector<float> out(grid.size());
  SampleGrid sg;
  sg.coords = std::move(coords);
  sg.check("grid");
  // The subdivision driver without a breadth-first frontier: a dense sampler settles no box, so a
  // frontier would keep a simplified tape for every box of its levels (for a converted mesh of
  // millions of instructions, more than 14 GB at 64^3); this way each worker keeps one group of
  // tapes per level. A truncated one settles the boxes beyond +-D, also from their centre's value
  // with a Lipschitz bound (useless otherwise: the centres would be evaluated for nothing).
  const double trunc = options.truncate;
  Subdivider driver({tiles, options.threads, 0, trunc > 0 ? options.lipschitz : 0});
  struct Scratch {
    BatchEvaluator batch;
    std::vector<float> xs, ys, zs, vs;
  };
  std::vector<Scratch> scratch(static_cast<std::size_t>(driver.workers()));
  struct Visitor {
    const SampleGrid& sg;
    const GridSpec& grid;
    std::vector<Scratch>& scratch;
    std::vector<float>& out;
    double trunc;
    // Truncated: a box whose values all lie beyond +-D is +-D wherever the clamp is taken (a value
    // of exactly D is float(D) itself).
    bool settled(int, const IndexBox& b, Interval v) {
      if (!(trunc > 0)) return false;
      float fill;
      if (static_cast<double>(v.lo) >= trunc) fill = static_cast<float>(trunc);
      else if (static_cast<double>(v.hi) <= -trunc) fill = static_cast<float>(-trunc);
      else return false;
      const std::size_t nz = static_cast<std::size_t>(b.extent(2));
      for (int i = b.lo[0]; i < b.hi[0]; ++i)
        for (int j = b.lo[1]; j < b.hi[1]; ++j) std::fill_n(out.data() + grid.index(i, j, b.lo[2]), nz, fill);
      return true;
    }
    // A leaf: its samples in C order, evaluated in one batch and copied row by row.
    void leaf(int wi, const Tape& t, const IndexBox& b) {
      Scratch& w = scratch[static_cast<std::size_t>(wi)];
      const std::size_t nz = static_cast<std::size_t>(b.extent(2));
      const std::size_t count = static_cast<std::size_t>(b.count());
      w.xs.resize(count), w.ys.resize(count), w.zs.resize(count), w.vs.resize(count);
      std::size_t n = 0;
      for (int i = b.lo[0]; i < b.hi[0]; ++i)
        for (int j = b.lo[1]; j < b.hi[1]; ++j)
          for (int k = b.lo[2]; k < b.hi[2]; ++k, ++n) {
            w.xs[n] = sg.coords[0][static_cast<std::size_t>(i)];
            w.ys[n] = sg.coords[1][static_cast<std::size_t>(j)];
            w.zs[n] = sg.coords[2][static_cast<std::size_t>(k)];
          }
      w.batch.eval(t, w.xs.data(), w.ys.data(), w.zs.data(), w.vs.data(), count);
      if (trunc > 0)
        for (float& v : w.vs) v = static_cast<float>(std::clamp(static_cast<double>(v), -trunc, trunc));
      n = 0;
      for (int i = b.lo[0]; i < b.hi[0]; ++i)
        for (int j = b.lo[1]; j < b.hi[1]; ++j, n += nz) std::copy_n(w.vs.data() + n, nz, out.data() + grid.index(i, j, b.lo[2]));
    }
  } visitor{sg, grid, scratch, out, trunc};
  driver.run(tape, sg, visitor);
  return out;
}

}  // namespace frep
