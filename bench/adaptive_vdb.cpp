// OpenVDB's adaptive meshing of a frep field, the baseline of bench/adaptive_vs_openvdb.sh (frep
// mesh --max-error against tools::volumeToMesh's adaptivity). A plain program, not a benchmark:
//   build/bench/adaptive_vdb INPUT RES ADAPTIVITY OUT.stl
// INPUT is anything frep mesh reads (load_field: .vm/.rhai/.frep, or a mesh as its exact distance).
// The grid is the one `frep mesh INPUT -r RES` starts from: the field's region (its known box, else
// the interval search's), cells of longest side / RES, one margin cell on every side, corners
// shifted by 1/64 of a cell (x1, x0.71, x0.43 per axis), f32 corner coordinates (contour::make_grid).
// frep samples that grid again on a second shifted grid when corners are exactly 0; this does not.
// Samples: with a Lipschitz bound L (meshes: 1, their exact distance), a narrow-band level set:
// values clamped to +-3 L cells (VDB's usual half width; crossings only use values within a cell
// of the surface), and blocks of 8^3 cells whose centre value proves |f| > 3 L cells everywhere
// in them filled with that unsampled. Fields that are not a distance (bear.vm: L unknown, |grad f|
// from 0.8 to 14 on its surface) are sampled at every corner and not clamped (a clamp in cells
// would cut values next to the surface and move VDB's crossings); the background is then the
// largest |f| sampled. NaN samples are outside (+background), as frep mesh takes them.
// The samples go into an openvdb::FloatGrid (level set class, voxel (i,j,k) at lo + (i,j,k) h: the
// output is in model coordinates), pruned to tiles, then volumeToMesh(isovalue 0, adaptivity).
// Quads are split along their first diagonal; triangles are oriented so that the signed volume is
// positive (outward normals, as frep check wants), the flip said on stderr.
// Prints one line: triangles, vertices, sample_s, vdb_s (volumeToMesh and the copy), total_s
// (load included), and whether triangles were flipped.
#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "contour/mesh_grid.hpp"
#include "frep/contour/bounds.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/eval/tape.hpp"
#include "frep/mesh/mesh.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/script/load.hpp"

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

constexpr int kBlock = 8;        // cells per pruning block side
constexpr double kBandCells = 3;  // narrow band half width, in cells

struct Samples {
  int n[3] = {0, 0, 0};  // corners per axis
  std::vector<float> v;  // x fastest
  std::size_t index(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * static_cast<std::size_t>(n[1]) + static_cast<std::size_t>(y)) *
               static_cast<std::size_t>(n[0]) + static_cast<std::size_t>(x);
  }
};

// Every corner of the grid (or of the blocks the Lipschitz bound cannot settle), clamped to +-band.
Samples sample(const frep::Tape& tape, const frep::contour::MeshGrid& g, double lipschitz, float band, std::size_t& evaluated) {
  Samples s;
  for (int a = 0; a < 3; ++a) s.n[a] = g.n[static_cast<std::size_t>(a)] + 1;
  s.v.assign(static_cast<std::size_t>(s.n[0]) * s.n[1] * s.n[2], band);
  int nb[3];
  for (int a = 0; a < 3; ++a) nb[a] = (g.n[static_cast<std::size_t>(a)] + kBlock - 1) / kBlock;
  const int blocks = nb[0] * nb[1] * nb[2];
  std::atomic<int> next{0};
  std::atomic<std::size_t> count{0};
  const auto& c = g.grid.coords;
  auto work = [&] {
    frep::BatchEvaluator ev;
    std::vector<float> xs, ys, zs, out;
    std::size_t mine = 0;
    for (int b; (b = next.fetch_add(1)) < blocks;) {
      const int bx = b % nb[0], by = (b / nb[0]) % nb[1], bz = b / (nb[0] * nb[1]);
      int lo[3] = {bx * kBlock, by * kBlock, bz * kBlock}, hi[3];  // corners lo..hi inclusive
      for (int a = 0; a < 3; ++a) hi[a] = std::min(lo[a] + kBlock, s.n[a] - 1);
      if (lipschitz > 0) {
        float p[3];
        double r2 = 0;
        for (int a = 0; a < 3; ++a) {
          const double l = c[static_cast<std::size_t>(a)][static_cast<std::size_t>(lo[a])];
          const double h = c[static_cast<std::size_t>(a)][static_cast<std::size_t>(hi[a])];
          p[a] = static_cast<float>(0.5 * (l + h));
          r2 += 0.25 * (h - l) * (h - l);
        }
        float f = 0;
        ev.eval(tape, &p[0], &p[1], &p[2], &f, 1);
        ++mine;
        if (std::abs(f) > lipschitz * std::sqrt(r2) * 1.001 + band) {
          const float v = f > 0 ? band : -band;
          for (int z = lo[2]; z <= hi[2]; ++z)
            for (int y = lo[1]; y <= hi[1]; ++y)
              for (int x = lo[0]; x <= hi[0]; ++x)  // shared faces: the same value from either block
                std::atomic_ref<float>(s.v[s.index(x, y, z)]).store(v, std::memory_order_relaxed);
          continue;
        }
      }
      xs.clear(), ys.clear(), zs.clear();
      for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y)
          for (int x = lo[0]; x <= hi[0]; ++x) {
            xs.push_back(c[0][static_cast<std::size_t>(x)]);
            ys.push_back(c[1][static_cast<std::size_t>(y)]);
            zs.push_back(c[2][static_cast<std::size_t>(z)]);
          }
      out.resize(xs.size());
      ev.eval(tape, xs.data(), ys.data(), zs.data(), out.data(), xs.size());
      mine += xs.size();
      std::size_t k = 0;
      for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y)
          for (int x = lo[0]; x <= hi[0]; ++x) {
            float v = out[k++];
            // Neighbouring blocks write shared corners with the same value (or one settled as
            // +-band where the clamp gives the same): relaxed atomic stores keep that defined.
            std::atomic_ref<float>(s.v[s.index(x, y, z)])
                .store(std::isnan(v) ? v : std::clamp(v, -band, band), std::memory_order_relaxed);
          }
    }
    count += mine;
  };
  const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  evaluated = count;
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: adaptive_vdb INPUT RES ADAPTIVITY OUT.stl\n");
    return 2;
  }
  try {
    const double t0 = now();
    const std::string input = argv[1], output = argv[4];
    const int res = std::atoi(argv[2]);
    const double adaptivity = std::atof(argv[3]);
    const frep::Model m = frep::load_field(input);
    const frep::Tape tape = frep::Tape::compile(*m.graph, m.root);

    // frep mesh's grid: its region (field_region = the known box or the interval search with the
    // field's Lipschitz bound, as find_region), cell edge, margin and first shift.
    const double t1 = now();
    const frep::Box3 region = frep::field_region(tape, m.info);
    double longest = 0;
    for (int a = 0; a < 3; ++a) longest = std::max(longest, region.hi[a] - region.lo[a]);
    const double h = longest / res;
    const frep::contour::MeshGrid g = frep::contour::make_grid(region, h, 1, 1.0 / 64);
    const double lipschitz = m.info.lipschitz;
    float band = lipschitz > 0 ? static_cast<float>(kBandCells * lipschitz * h) : std::numeric_limits<float>::infinity();
    std::size_t evaluated = 0;
    Samples s = sample(tape, g, lipschitz, band, evaluated);
    if (!std::isfinite(band)) {
      band = 0;
      for (float v : s.v)
        if (std::isfinite(v)) band = std::max(band, std::abs(v));
    }
    for (float& v : s.v)
      if (std::isnan(v)) v = band;
    const double t2 = now();

    openvdb::initialize();
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(band);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(h));
    // Corner i along an axis is at coords[0] + i h (the coordinates are those values rounded to f32).
    grid->transform().postTranslate(openvdb::Vec3d(g.grid.coords[0][0], g.grid.coords[1][0], g.grid.coords[2][0]));
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    const openvdb::CoordBBox box(openvdb::Coord(0, 0, 0), openvdb::Coord(s.n[0] - 1, s.n[1] - 1, s.n[2] - 1));
    openvdb::tools::Dense<float, openvdb::tools::LayoutXYZ> dense(box, const_cast<float*>(s.v.data()));
    openvdb::tools::copyFromDense(dense, *grid, 0.0f);
    openvdb::tools::pruneLevelSet(grid->tree());  // +-band regions: inactive tiles, as a level set has them
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> tris;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(*grid, points, tris, quads, 0.0, adaptivity);
    const double t3 = now();

    frep::TriMesh mesh;
    mesh.vertices.reserve(points.size());
    for (const auto& p : points) mesh.vertices.push_back({p.x(), p.y(), p.z()});
    mesh.triangles.reserve(tris.size() + 2 * quads.size());
    for (const auto& t : tris) mesh.triangles.push_back({t[0], t[1], t[2]});
    for (const auto& q : quads) {
      mesh.triangles.push_back({q[0], q[1], q[2]});
      mesh.triangles.push_back({q[0], q[2], q[3]});
    }
    // Signed volume (divergence theorem): negative means VDB's winding is inward for this field.
    double vol = 0;
    for (const auto& t : mesh.triangles) {
      const frep::Vec3 a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
      vol += frep::dot(a, frep::cross(b, c)) / 6;
    }
    const bool flipped = vol < 0;
    if (flipped)
      for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
    frep::write_mesh(output, mesh);
    const double t4 = now();
    std::printf("triangles %zu vertices %zu quads %zu tris %zu sample_s %.3f vdb_s %.3f total_s %.3f flipped %d "
                "grid %d %d %d cell %.6g evaluated %zu\n",
                mesh.triangles.size(), mesh.vertices.size(), quads.size(), tris.size(), t2 - t1, t3 - t2, t4 - t0,
                flipped ? 1 : 0, g.n[0], g.n[1], g.n[2], h, evaluated);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "adaptive_vdb: %s\n", e.what());
    return 1;
  }
  return 0;
}
