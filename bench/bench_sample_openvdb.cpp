// frep sample's dense grid against OpenVDB's meshToSignedDistanceField on the same mesh, in one
// run, at the same voxel size, both with all cores. frep computes every sample exactly (double
// precision, rounded to float32); OpenVDB computes a narrow band (3 voxels each side, its
// default) and, for reference, a band wide enough to cover the whole grid. Optionally also the
// expression path (a .frep/.vm of the same mesh: grid time, and points per second of the
// expression against MeshDistance on the same uniform points).
//   build/bench/bench_sample_openvdb MESH [N=256] [EXPR]
// Prints one line per measurement, "name seconds", and the ratios.
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "frep/eval/point_cloud.hpp"
#include "frep/io/load.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/sample/grid.hpp"
#include "frep/sample/mesh_field.hpp"

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s MESH [N=256] [EXPR]\n", argv[0]);
    return 2;
  }
  const std::string path = argv[1];
  const int n = argc > 2 ? std::atoi(argv[2]) : 256;
  openvdb::initialize();
  const frep::TriMesh mesh = frep::read_mesh(path);

  double t = now();
  const frep::MeshField field(mesh);
  const double t_prepare = now() - t;
  const frep::GridSpec grid = frep::cube_grid(frep::default_mesh_bounds(field.box()), n);
  t = now();
  frep::MeshGridStats stats;
  const std::vector<float> ours = frep::sample_grid(field, grid, {}, &stats);
  const double t_grid = now() - t;
  const double voxel = (grid.bounds.hi.x - grid.bounds.lo.x) / (n - 1);

  // OpenVDB: index space with the same voxel size and origin (sample i at lo + i * voxel).
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> tris;
  std::vector<openvdb::Vec4I> quads;
  for (const frep::Vec3& v : field.welded().vertices)
    points.emplace_back(static_cast<float>((v.x - grid.bounds.lo.x) / voxel),
                        static_cast<float>((v.y - grid.bounds.lo.y) / voxel),
                        static_cast<float>((v.z - grid.bounds.lo.z) / voxel));
  for (const frep::Triangle& tr : field.welded().triangles) tris.emplace_back(tr[0], tr[1], tr[2]);
  const auto xform = openvdb::math::Transform::createLinearTransform(1.0);
  auto run_vdb = [&](float band) {
    const double s = now();
    auto g = openvdb::tools::meshToSignedDistanceField<openvdb::FloatGrid>(*xform, points, tris, quads, band, band);
    const double e = now() - s;
    return std::make_pair(e, g->activeVoxelCount());
  };
  const auto [t_vdb, active] = run_vdb(3.0f);
  // The band that covers the whole grid is slow (tens of seconds at 128^3): only for small grids.
  const auto [t_vdb_wide, active_wide] = n <= 128 ? run_vdb(static_cast<float>(n)) : std::make_pair(0.0, openvdb::Index64(0));

  std::printf("mesh %s: %zu triangles, grid %d^3 (%zu samples), voxel %.6g\n", path.c_str(),
              field.welded().triangles.size(), n, grid.size(), voxel);
  std::printf("frep_prepare_s %.3f   (weld, check, distance oracle)\n", t_prepare);
  std::printf("frep_grid_s %.3f   (%s, %.2f distances per sample, %zu fallback samples)\n", t_grid,
              stats.method == frep::MeshGridMethod::Cpt ? "closest point transform" : "oracle queries",
              static_cast<double>(stats.evaluations) / static_cast<double>(grid.size()), stats.fallback_samples);
  std::printf("openvdb_band3_s %.3f   (%llu active voxels)\n", t_vdb, static_cast<unsigned long long>(active));
  if (t_vdb_wide > 0)
    std::printf("openvdb_dense_s %.3f   (band %d voxels, %llu active voxels)\n", t_vdb_wide, n,
                static_cast<unsigned long long>(active_wide));
  std::printf("ratio frep_grid / openvdb_band3: %.2f\n", t_grid / t_vdb);
  std::printf("ratio (frep_prepare + frep_grid) / openvdb_band3: %.2f\n", (t_prepare + t_grid) / t_vdb);
  if (t_vdb_wide > 0) std::printf("ratio frep_grid / openvdb_dense: %.2f\n", t_grid / t_vdb_wide);

  if (argc > 3) {
    const frep::Model m = frep::load_expression(argv[3]);
    const frep::Tape tape = frep::Tape::compile(*m.graph, m.root);
    t = now();
    const std::vector<float> ev = frep::sample_grid(tape, grid);
    const double t_expr = now() - t;
    double worst = 0;
    for (std::size_t i = 0; i < ev.size(); ++i) worst = std::max(worst, std::fabs(double(ev[i]) - ours[i]));
    std::printf("expr_grid_s %.3f   (%s, %zu instructions; max |expr - mesh| %.3g = %.3g of the diagonal)\n", t_expr,
                argv[3], tape.size(), worst, worst / frep::length(field.box().size()));
    // Points per second on the same uniform points: the expression (pruned point cloud) against the oracle.
    const std::size_t np = 1000000;
    std::vector<float> xs(np), ys(np), zs(np), out(np);
    // Same points for both: drawn once.
    std::vector<double> xd(np), yd(np), zd(np), od(np);
    std::uint64_t s = 12345;
    for (std::size_t i = 0; i < np; ++i) {
      auto u = [&] {
        s = s * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<double>(s >> 11) * 0x1.0p-53;
      };
      xs[i] = static_cast<float>(grid.bounds.lo.x + (grid.bounds.hi.x - grid.bounds.lo.x) * u());
      ys[i] = static_cast<float>(grid.bounds.lo.y + (grid.bounds.hi.y - grid.bounds.lo.y) * u());
      zs[i] = static_cast<float>(grid.bounds.lo.z + (grid.bounds.hi.z - grid.bounds.lo.z) * u());
      xd[i] = xs[i], yd[i] = ys[i], zd[i] = zs[i];
    }
    t = now();
    frep::eval_points(tape, xs.data(), ys.data(), zs.data(), out.data(), np);
    const double t_pts_expr = now() - t;
    t = now();
    field.distance().signed_distance(xd.data(), yd.data(), zd.data(), od.data(), np, frep::SignMethod::Pseudonormal);
    const double t_pts_mesh = now() - t;
    std::printf("expr_points_per_s %.3g   mesh_distance_points_per_s %.3g   (1M uniform points, all cores)\n",
                np / t_pts_expr, np / t_pts_mesh);
    std::printf("ratio expr_grid / frep_grid: %.2f\n", t_expr / t_grid);
  }
  return 0;
}
