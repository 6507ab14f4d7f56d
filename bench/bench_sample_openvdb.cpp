// frep sample's grids against OpenVDB on the same mesh, in one run, at the same voxel size and
// origin, all with all cores:
//   - truncated at 3 voxels (MeshGridOptions::truncate: exact within 3 voxels of the surface,
//     +-3 voxels beyond, every sample of the dense box written) against OpenVDB's
//     meshToLevelSet with a half-width of 3 voxels (LEVEL_SET_HALF_WIDTH, its default; a sparse
//     narrow band). Both are timed the best of FREP_BENCH_REPEAT runs (default 3), interleaved.
//   - the exact dense grid (the closest point transform, double precision rounded to float32)
//     against OpenVDB's meshToSignedDistanceField filling the same box: exterior and interior
//     bands just wide enough to cover every sample of the grid (taken from frep's grid), and for
//     reference its narrow band of 3 voxels. OpenVDB's dense fill takes tens of seconds at
//     256^3: FREP_BENCH_NO_VDB_DENSE=1 skips it.
// Then the mesh's converted expression against MeshDistance on the same scattered points
// (uniform in the grid's box, and near the surface); FREP_BENCH_EXPR_GRID=1 also samples the
// expression's dense grid (slow), FREP_BENCH_NO_EXPR=1 skips the expression.
//   build/bench/bench_sample_openvdb MESH [N=256] [EXPR]
// EXPR: an expression file to use instead of converting MESH in the run. Prints one line per
// measurement and the ratios.
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "frep/convert/convert.hpp"
#include "frep/eval/point_cloud.hpp"
#include "frep/script/load.hpp"
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
  const double voxel = (grid.bounds.hi.x - grid.bounds.lo.x) / (n - 1);
  const int repeat = std::getenv("FREP_BENCH_REPEAT") ? std::max(1, std::atoi(std::getenv("FREP_BENCH_REPEAT"))) : 3;

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

  std::printf("mesh %s: %zu triangles, grid %d^3 (%zu samples), voxel %.6g\n", path.c_str(),
              field.welded().triangles.size(), n, grid.size(), voxel);
  std::printf("frep_prepare_s %.3f   (weld, check, distance oracle)\n", t_prepare);

  // Truncated at 3 voxels against OpenVDB's level set of half-width 3, best of `repeat`, interleaved.
  const float band = static_cast<float>(openvdb::LEVEL_SET_HALF_WIDTH);
  frep::MeshGridOptions to;
  to.truncate = band * voxel;
  frep::MeshGridStats tstats;
  std::vector<float> trunc;
  double t_trunc = INFINITY, t_vdb = INFINITY;
  openvdb::Index64 active = 0;
  for (int r = 0; r < repeat; ++r) {
    t = now();
    trunc = frep::sample_grid(field, grid, to, &tstats);
    t_trunc = std::min(t_trunc, now() - t);
    t = now();
    const auto ls = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*xform, points, tris, band);
    t_vdb = std::min(t_vdb, now() - t);
    active = ls->activeVoxelCount();
  }
  std::printf("frep_truncated3_s %.3f   (best of %d; %s, %zu samples exact, %.2f distances per sample, %zu side "
              "queries)\n",
              t_trunc, repeat, tstats.method == frep::MeshGridMethod::Cpt ? "closest point transform" : "oracle queries",
              tstats.band_samples, static_cast<double>(tstats.evaluations) / static_cast<double>(grid.size()),
              tstats.side_queries);
  std::printf("openvdb_levelset3_s %.3f   (best of %d; meshToLevelSet, half-width %g voxels, %llu active voxels)\n",
              t_vdb, repeat, band, static_cast<unsigned long long>(active));
  std::printf("ratio frep_truncated3 / openvdb_levelset3: %.2f\n", t_trunc / t_vdb);
  std::printf("ratio (frep_prepare + frep_truncated3) / openvdb_levelset3: %.2f\n", (t_prepare + t_trunc) / t_vdb);

  // The exact dense grid.
  t = now();
  frep::MeshGridStats stats;
  const std::vector<float> ours = frep::sample_grid(field, grid, {}, &stats);
  const double t_grid = now() - t;
  std::printf("frep_grid_s %.3f   (%s, %.2f distances per sample, %zu fallback samples)\n", t_grid,
              stats.method == frep::MeshGridMethod::Cpt ? "closest point transform" : "oracle queries",
              static_cast<double>(stats.evaluations) / static_cast<double>(grid.size()), stats.fallback_samples);
  // The truncated grid is the dense one clamped, bit for bit (as the tests check on smaller grids).
  std::size_t differ = 0;
  for (std::size_t i = 0; i < ours.size(); ++i)
    differ += std::bit_cast<std::uint32_t>(static_cast<float>(std::clamp(static_cast<double>(ours[i]), -to.truncate,
                                                                         to.truncate))) !=
              std::bit_cast<std::uint32_t>(trunc[i]);
  std::printf("truncated grid vs clamped dense grid: %zu samples differ\n", differ);

  auto run_vdb = [&](float ex, float in) {
    const double s = now();
    auto g = openvdb::tools::meshToSignedDistanceField<openvdb::FloatGrid>(*xform, points, tris, quads, ex, in);
    const double e = now() - s;
    return std::make_pair(e, g->activeVoxelCount());
  };
  const auto [t_vdb3, active3] = run_vdb(band, band);
  std::printf("openvdb_band3_s %.3f   (meshToSignedDistanceField, 3 voxels each side, %llu active voxels)\n", t_vdb3,
              static_cast<unsigned long long>(active3));
  std::printf("ratio frep_grid / openvdb_band3: %.2f\n", t_grid / t_vdb3);
  std::printf("ratio (frep_prepare + frep_grid) / openvdb_band3: %.2f\n", (t_prepare + t_grid) / t_vdb3);
  if (!std::getenv("FREP_BENCH_NO_VDB_DENSE")) {
    // Bands (in voxels) that reach every sample of the box: its largest distance outside and
    // inside, plus a voxel.
    double out_max = 0, in_max = 0;
    for (float v : ours) out_max = std::max(out_max, double(v)), in_max = std::max(in_max, -double(v));
    const float ex = static_cast<float>(std::ceil(out_max / voxel) + 1), in = static_cast<float>(std::ceil(in_max / voxel) + 1);
    const auto [t_dense, active_dense] = run_vdb(ex, in);
    std::printf("openvdb_dense_s %.3f   (meshToSignedDistanceField, bands %g voxels outside and %g inside, %llu "
                "active voxels)\n",
                t_dense, ex, in, static_cast<unsigned long long>(active_dense));
    std::printf("ratio openvdb_dense / frep_grid: %.2f\n", t_dense / t_grid);
  }

  if (!std::getenv("FREP_BENCH_NO_EXPR")) {
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
    std::printf("ratio expr_grid / openvdb_band3: %.2f\n", t_expr / t_vdb3);
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
