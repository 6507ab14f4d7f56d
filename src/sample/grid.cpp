// Grid layout, and dense grids of signed distances from meshes (closest point transform or
// oracle queries) and from expressions (the subdivision driver with a sampling visitor).
#include "frep/sample/grid.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <string>

#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/eval/subdivision.hpp"
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
  SampleGrid sg;
  for (int a = 0; a < 3; ++a) {
    sg.coords[a].resize(static_cast<std::size_t>(grid.counts[a]));
    for (int i = 0; i < grid.counts[a]; ++i) sg.coords[a][static_cast<std::size_t>(i)] = static_cast<float>(grid.coord(a, i));
  }
  SubdivisionOptions so;
  so.tiles = options.tiles;
  so.threads = options.threads;
  Subdivider sub(so);
  std::vector<float> out(grid.size());
  struct Scratch {
    BatchEvaluator batch;
    std::vector<float> xs, ys, zs, vs;
  };
  std::vector<std::unique_ptr<Scratch>> scratch;
  for (int w = 0; w < sub.workers(); ++w) scratch.push_back(std::make_unique<Scratch>());
  // Never settles a box: every sample needs its value. Leaves evaluate their samples with the
  // tape simplified for them, in z-major rows so the values land in place row by row.
  struct Visitor {
    const SampleGrid& sg;
    const GridSpec& grid;
    std::vector<std::unique_ptr<Scratch>>& scratch;
    float* out;
    bool settled(int, const IndexBox&, Interval) { return false; }
    void leaf(int wi, const Tape& t, const IndexBox& b) {
      Scratch& s = *scratch[static_cast<std::size_t>(wi)];
      const std::size_t count = static_cast<std::size_t>(b.count());
      s.xs.resize(count), s.ys.resize(count), s.zs.resize(count), s.vs.resize(count);
      std::size_t n = 0;
      for (int i = b.lo[0]; i < b.hi[0]; ++i)
        for (int j = b.lo[1]; j < b.hi[1]; ++j)
          for (int k = b.lo[2]; k < b.hi[2]; ++k, ++n) {
            s.xs[n] = sg.coords[0][static_cast<std::size_t>(i)];
            s.ys[n] = sg.coords[1][static_cast<std::size_t>(j)];
            s.zs[n] = sg.coords[2][static_cast<std::size_t>(k)];
          }
      s.batch.eval(t, s.xs.data(), s.ys.data(), s.zs.data(), s.vs.data(), count);
      n = 0;
      const std::size_t w = static_cast<std::size_t>(b.extent(2));
      for (int i = b.lo[0]; i < b.hi[0]; ++i)
        for (int j = b.lo[1]; j < b.hi[1]; ++j, n += w)
          std::copy_n(s.vs.data() + n, w, out + grid.index(i, j, b.lo[2]));
    }
  } visitor{sg, grid, scratch, out.data()};
  sub.run(tape, sg, visitor);
  return out;
}

}  // namespace frep
