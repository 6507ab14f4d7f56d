// frep sample's dense grid against OpenVDB's meshToSignedDistanceField on the same mesh, in one
// run, at the same voxel size, all with all cores. frep computes every sample exactly: from the
// mesh by the closest point transform (double precision, rounded to float32), and from the
// mesh's converted expression by the pruned evaluator (float32). OpenVDB computes a narrow band
// of 3 voxels each side (openvdb::LEVEL_SET_HALF_WIDTH, its default) and, for grids up to 128^3,
// a band wide enough to cover the whole grid. Then the expression against MeshDistance on the
// same scattered points (uniform in the grid's box, and near the surface).
//   build/bench/bench_sample_openvdb MESH [N=256] [EXPR]
// EXPR: an expression file to use instead of converting MESH in the run. Prints one line per
// measurement and the ratios.
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "frep/convert/convert.hpp"
#include "frep/eval/point_cloud.hpp"
#include "frep/io/load.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/sample/grid.hpp"
#include "frep/mesh/mesh_field.hpp"
#include "frep/sample/points.hpp"

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
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // lines appear as measured, even if the run is stopped
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
  const auto [t_vdb, active] = run_vdb(static_cast<float>(openvdb::LEVEL_SET_HALF_WIDTH));
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

  {
    t = now();
    frep::Model m;
    std::size_t nodes = 0;
    if (argc > 3) {
      m = frep::load_expression(argv[3]);
    } else {
      frep::ConvertResult c = frep::convert_mesh(mesh);
      nodes = c.stats.nodes;
      m = std::move(c.model);
    }
    const frep::Tape tape = frep::Tape::compile(*m.graph, m.root);
    const double t_load = now() - t;
    const double diag = frep::length(field.box().size());
    if (argc > 3) std::printf("expr_load_s %.3f   (%s, %zu instructions)\n", t_load, argv[3], tape.size());
    else std::printf("expr_convert_s %.3f   (%zu nodes, %zu instructions)\n", t_load, nodes, tape.size());
    // The expression grid of a converted mesh is slow (439 s at 64^3 on armadillo): only when asked.
    if (std::getenv("FREP_BENCH_EXPR_GRID")) {
    t = now();
    const std::vector<float> ev = frep::sample_grid(tape, grid);
    const double t_expr = now() - t;
    double worst = 0;
    for (std::size_t i = 0; i < ev.size(); ++i) worst = std::max(worst, std::fabs(double(ev[i]) - ours[i]));
    std::printf("expr_grid_s %.3f   (pruned evaluator; max |expr - mesh grid| %.3g = %.3g of the diagonal)\n", t_expr,
                worst, worst / diag);
    std::printf("ratio expr_grid / openvdb_band3: %.2f\n", t_expr / t_vdb);
    std::printf("ratio expr_grid / frep_grid: %.2f\n", t_expr / t_grid);
    }

    // The same scattered points for both: 100k uniform in the grid's box, 100k near the surface
    // (Gaussian, deviation 1% of the diagonal); float32 coordinates, widened for the oracle.
    const std::size_t np = 100000;
    frep::PointSampleOptions po;
    po.seed = 1;
    const std::vector<float> uni = frep::sample_uniform(field, grid.bounds, np, po);
    const std::vector<float> near = frep::sample_near_surface(field, np, 0.01 * diag, po);
    for (const auto& [name, rows] : {std::pair<const char*, const std::vector<float>*>{"uniform", &uni},
                                     std::pair<const char*, const std::vector<float>*>{"near_surface", &near}}) {
      std::vector<float> xs(np), ys(np), zs(np), out(np);
      std::vector<double> xd(np), yd(np), zd(np), od(np);
      for (std::size_t i = 0; i < np; ++i) {
        xs[i] = (*rows)[4 * i], ys[i] = (*rows)[4 * i + 1], zs[i] = (*rows)[4 * i + 2];
        xd[i] = xs[i], yd[i] = ys[i], zd[i] = zs[i];
      }
      t = now();
      frep::eval_points(tape, xs.data(), ys.data(), zs.data(), out.data(), np);
      const double t_pts_expr = now() - t;
      t = now();
      field.distance().signed_distance(xd.data(), yd.data(), zd.data(), od.data(), np, frep::SignMethod::Pseudonormal);
      const double t_pts_mesh = now() - t;
      double w = 0;
      for (std::size_t i = 0; i < np; ++i) w = std::max(w, std::fabs(double(out[i]) - od[i]));
      std::printf("%s points: expr_s %.3f (%.3g points/s)   mesh_distance_s %.3f (%.3g points/s)   ratio expr / "
                  "mesh_distance %.2f   max |expr - mesh| %.3g of the diagonal\n",
                  name, t_pts_expr, np / t_pts_expr, t_pts_mesh, np / t_pts_mesh, t_pts_expr / t_pts_mesh, w / diag);
    }
  }
  return 0;
}
