// Meshing a converted mesh: frep's dual contouring against "sample the expression on the same grid,
// then OpenVDB's volumeToMesh", in one run. The expression is ../shared/data/meshes/armadillo_libigl.obj
// converted by convert_mesh (not timed); the grid is dual contouring's: 256 cells across the longest
// side of the mesh's bounding box grown by 1% (MeshOptions::known_bounds), plus one margin cell.
//   BM_ArmadilloDC        frep's mesher (warm Mesher), dual contouring, as frep mesh runs it: with the
//                         Lipschitz bound the conversion reports (1: an exact distance) and the
//                         mesher's default tiles. FREP_DC_LIPSCHITZ=0 turns the bound off.
//   BM_ArmadilloVdbDense  every grid corner evaluated (the subdivision driver simplifies the tape
//                         per 8-sample box, the batch evaluator samples all of them), copied into
//                         an openvdb::FloatGrid (copyFromDense), then tools::volumeToMesh.
//   BM_ArmadilloVdbPruned the same, but boxes of cells that interval arithmetic proves empty or
//                         full are not sampled: their corners get +-(one cell) unless a sampled box
//                         shares them, so every edge with a sign change still has exact values at
//                         both ends (the same mesh as dense), and VDB gets constant tiles there.
// Counters: sample_s (sampling), vdb_s (copy into the VDB grid and volumeToMesh), triangles
// (volumeToMesh's quads count as two). Threads: frep uses all cores, OpenVDB its TBB default (all).
// Run: build/bench/bench_mesh_vdb (needs ../shared/data/meshes and OpenVDB: libopenvdb-dev).
#include <benchmark/benchmark.h>

#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <memory>
#include <vector>

#include "frep/contour/mesher.hpp"
#include "frep/convert/convert.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/eval/subdivision.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/validate.hpp"

namespace {

// Cells across; FREP_MESH_RESOLUTION overrides it (256 ran out of the 10-12 GB allowed here: docs/meshing.md).
const int kResolution = [] {
  const char* r = std::getenv("FREP_MESH_RESOLUTION");
  return r ? std::atoi(r) : 256;
}();
// Subdivision tiles of the sampling pipelines. The default ({128, 32, 8}) stores a simplified tape
// for every open box of the two breadth-first levels at once: over 12 GB for this expression. With a
// top level of 256, those two levels hold at most 8 + 64 boxes. FREP_TILES=32,8 overrides it (for
// dual contouring too, whose default is the mesher's).
const std::vector<int> kTiles = [] {
  std::vector<int> t;
  if (const char* e = std::getenv("FREP_TILES"))
    for (const char* p = e; *p;) {
      t.push_back(std::atoi(p));
      while (*p && *p != ',') ++p;
      if (*p == ',') ++p;
    }
  if (t.empty()) t = {256, 128, 32, 8};
  return t;
}();

struct Armadillo {
  frep::Model model;
  std::unique_ptr<frep::Tape> tape;
  frep::Box3 box;         // the mesh's bounding box, grown by 1% of its longest side
  bool ok = false;
};

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

const Armadillo& armadillo() {
  static const Armadillo a = [] {
    Armadillo r;
    const std::string path = FREP_SOURCE_DIR "/../shared/data/meshes/armadillo_libigl.obj";
    if (!std::filesystem::exists(path)) return r;
    const double t0 = now();
    const frep::TriMesh mesh = frep::read_mesh(path);
    frep::ConvertResult c = frep::convert_mesh(mesh);
    r.box = frep::validate_mesh(mesh).box;
    const frep::Vec3 e = r.box.hi - r.box.lo;
    const double g = 0.01 * std::max({e.x, e.y, e.z});
    r.box.lo = r.box.lo - frep::Vec3{g, g, g};
    r.box.hi = r.box.hi + frep::Vec3{g, g, g};
    std::fprintf(stderr, "armadillo: %zu triangles converted to %zu nodes in %.2f s (not timed below)\n",
                 c.stats.triangles, c.stats.nodes, now() - t0);
    r.model = std::move(c.model);
    r.tape = std::make_unique<frep::Tape>(frep::Tape::compile(*r.model.graph, r.model.root));
    r.ok = true;
    return r;
  }();
  return a;
}

// Bounds known (the grown box): the interval search on a converted mesh of this size needs more
// memory than the machine has (see docs/meshing.md).
frep::MeshOptions dc_options() {
  frep::MeshOptions o;
  o.resolution = kResolution;
  o.known_bounds = armadillo().box;
  if (std::getenv("FREP_TILES")) o.tiles = kTiles;
  const char* l = std::getenv("FREP_DC_LIPSCHITZ");
  o.lipschitz = l ? std::atof(l) : armadillo().model.info.lipschitz;
  return o;
}

void BM_ArmadilloDC(benchmark::State& state) {
  const Armadillo& a = armadillo();
  if (!a.ok) return state.SkipWithError("../shared/data/meshes/armadillo_libigl.obj not found");
  frep::Mesher mesher(dc_options());
  frep::TriMesh mesh = mesher.mesh(*a.tape);
  static bool checked = false;
  if (!checked) {
    checked = true;
    const frep::ValidationReport r = frep::validate_mesh(mesh);
    std::fprintf(stderr, "check: armadillo dc %d: %s; grid %d x %d x %d, cell %.5g\n", kResolution,
                 r.summary().c_str(), mesher.stats().cells[0], mesher.stats().cells[1], mesher.stats().cells[2],
                 mesher.stats().cell_size);
  }
  for (auto _ : state) {
    mesh = mesher.mesh(*a.tape);
    benchmark::DoNotOptimize(mesh.vertices.data());
  }
  state.counters["triangles"] = static_cast<double>(mesh.triangles.size());
  state.counters["cells_s"] = mesher.stats().seconds_cells;
  state.counters["assembly_s"] = mesher.stats().seconds_assembly;
}

// Samples the expression at every corner of the DC grid into a dense x-fastest array.
class Sampler {
 public:
  explicit Sampler(const frep::MeshStats& st) : evals_(static_cast<std::size_t>(subdivider_.workers())) {
    h_ = st.cell_size;
    for (int a = 0; a < 3; ++a) {
      n_[a] = st.cells[static_cast<std::size_t>(a)] + 1;
      auto& c = grid_.coords[static_cast<std::size_t>(a)];
      c.resize(static_cast<std::size_t>(n_[a]));
      for (int i = 0; i < n_[a]; ++i) c[static_cast<std::size_t>(i)] = static_cast<float>(st.bounds.lo[a] + i * h_);
    }
    values_.resize(static_cast<std::size_t>(n_[0]) * n_[1] * n_[2]);
    for (auto& e : evals_) e = std::make_unique<frep::BatchEvaluator>();
    scratch_.resize(evals_.size());
  }
  const std::vector<float>& values() const { return values_; }
  int n(int a) const { return n_[a]; }
  double h() const { return h_; }
  const frep::SampleGrid& grid() const { return grid_; }

  // Every sample. The grid is one of samples: each box covers its samples exactly once.
  void dense(const frep::Tape& tape) {
    grid_.cells = false;
    struct V {
      Sampler& s;
      bool settled(int, const frep::IndexBox&, frep::Interval) { return false; }
      void leaf(int w, const frep::Tape& t, const frep::IndexBox& b) { s.sample(w, t, b, b.hi); }
    } v{*this};
    subdivider_.run(tape, grid_, v);
  }

  // Boxes of cells settled by intervals are not sampled; their corners are filled afterwards
  // where no sampled box wrote them.
  void pruned(const frep::Tape& tape) {
    grid_.cells = true;
    std::fill(values_.begin(), values_.end(), std::numeric_limits<float>::quiet_NaN());
    settled_.assign(evals_.size(), {});
    struct V {
      Sampler& s;
      bool settled(int w, const frep::IndexBox& b, frep::Interval i) {
        if (!(i.lo > 0 || i.hi < 0)) return false;
        s.settled_[static_cast<std::size_t>(w)].push_back({b, i.lo > 0 ? 1.0f : -1.0f});
        return true;
      }
      void leaf(int w, const frep::Tape& t, const frep::IndexBox& b) {
        s.sample(w, t, b, {b.hi[0] + 1, b.hi[1] + 1, b.hi[2] + 1});  // cells lo..hi: corners lo..hi inclusive
      }
    } v{*this};
    subdivider_.run(tape, grid_, v);
    const float band = static_cast<float>(h_);
    for (auto& list : settled_)
      for (const auto& [b, sign] : list)
        for (int z = b.lo[2]; z <= b.hi[2]; ++z)
          for (int y = b.lo[1]; y <= b.hi[1]; ++y) {
            float* row = &values_[index(0, y, z)];
            for (int x = b.lo[0]; x <= b.hi[0]; ++x)
              if (std::isnan(row[x])) row[x] = sign * band;
          }
  }

 private:
  std::size_t index(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * static_cast<std::size_t>(n_[1]) + static_cast<std::size_t>(y)) *
               static_cast<std::size_t>(n_[0]) + static_cast<std::size_t>(x);
  }
  // Samples lo..end-1 of box b. Neighbouring boxes may write the same corner (the same value, bit
  // for bit): relaxed atomic stores keep that well defined.
  void sample(int w, const frep::Tape& t, const frep::IndexBox& b, std::array<int, 3> end) {
    Scratch& s = scratch_[static_cast<std::size_t>(w)];
    s.x.clear(), s.y.clear(), s.z.clear();
    for (int z = b.lo[2]; z < end[2]; ++z)
      for (int y = b.lo[1]; y < end[1]; ++y)
        for (int x = b.lo[0]; x < end[0]; ++x) {
          s.x.push_back(grid_.coords[0][static_cast<std::size_t>(x)]);
          s.y.push_back(grid_.coords[1][static_cast<std::size_t>(y)]);
          s.z.push_back(grid_.coords[2][static_cast<std::size_t>(z)]);
        }
    s.out.resize(s.x.size());
    evals_[static_cast<std::size_t>(w)]->eval(t, s.x.data(), s.y.data(), s.z.data(), s.out.data(), s.x.size());
    std::size_t k = 0;
    for (int z = b.lo[2]; z < end[2]; ++z)
      for (int y = b.lo[1]; y < end[1]; ++y)
        for (int x = b.lo[0]; x < end[0]; ++x)
          std::atomic_ref<float>(values_[index(x, y, z)]).store(s.out[k++], std::memory_order_relaxed);
  }

  struct Scratch {
    std::vector<float> x, y, z, out;
  };
  struct Settled {
    frep::IndexBox box;
    float sign;
  };
  frep::Subdivider subdivider_{frep::SubdivisionOptions{kTiles, 0, 2}};
  frep::SampleGrid grid_;
  int n_[3] = {0, 0, 0};
  double h_ = 0;
  std::vector<float> values_;
  std::vector<std::unique_ptr<frep::BatchEvaluator>> evals_;
  std::vector<Scratch> scratch_;
  std::vector<std::vector<Settled>> settled_;
};

// Copies the samples into a VDB grid (voxel (i,j,k) at lo + (i,j,k) h) and extracts the 0 surface.
std::size_t vdb_mesh(const Sampler& s, const frep::MeshStats& st) {
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(static_cast<float>(s.h()));
  grid->setTransform(openvdb::math::Transform::createLinearTransform(s.h()));
  grid->transform().postTranslate(openvdb::Vec3d(st.bounds.lo.x, st.bounds.lo.y, st.bounds.lo.z));
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  const openvdb::CoordBBox box(openvdb::Coord(0, 0, 0), openvdb::Coord(s.n(0) - 1, s.n(1) - 1, s.n(2) - 1));
  // copyFromDense only reads the array.
  openvdb::tools::Dense<float, openvdb::tools::LayoutXYZ> dense(box, const_cast<float*>(s.values().data()));
  openvdb::tools::copyFromDense(dense, *grid, 0.0f);
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(*grid, points, triangles, quads, 0.0);
  return triangles.size() + 2 * quads.size();
}

void run_vdb(benchmark::State& state, bool pruned) {
  const Armadillo& a = armadillo();
  if (!a.ok) return state.SkipWithError("../shared/data/meshes/armadillo_libigl.obj not found");
  openvdb::initialize();
  static const frep::MeshStats st = [&] {
    frep::Mesher m(dc_options());
    m.mesh(*a.tape);
    return m.stats();
  }();
  Sampler sampler(st);
  double sample_s = 0, vdb_s = 0;
  std::size_t triangles = 0;
  for (auto _ : state) {
    const double t0 = now();
    if (pruned) sampler.pruned(*a.tape);
    else sampler.dense(*a.tape);
    const double t1 = now();
    triangles = vdb_mesh(sampler, st);
    const double t2 = now();
    sample_s = t1 - t0;
    vdb_s = t2 - t1;
  }
  state.counters["triangles"] = static_cast<double>(triangles);
  state.counters["sample_s"] = sample_s;
  state.counters["vdb_s"] = vdb_s;
}

void BM_ArmadilloVdbDense(benchmark::State& s) { run_vdb(s, false); }
void BM_ArmadilloVdbPruned(benchmark::State& s) { run_vdb(s, true); }

BENCHMARK(BM_ArmadilloDC)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ArmadilloVdbDense)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ArmadilloVdbPruned)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
