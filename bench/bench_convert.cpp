// The converter: conversion time per shared mesh and sign method (nodes per triangle reported as
// counters), and evaluating the converted expression against the distance oracle on the same
// points (points per second, near the surface and uniform in the box), measured in one run.
//   build/bench/bench_convert [--benchmark_filter=...]      (needs ../shared/data/meshes)
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <random>

#include "frep/convert/convert.hpp"
#include "frep/eval/point_cloud.hpp"
#include "frep/mesh/mesh_distance.hpp"
#include "frep/mesh/mesh_io.hpp"

namespace {

std::string mesh_path(const std::string& name) { return std::string(FREP_SOURCE_DIR "/../shared/data/meshes/") + name; }

const frep::TriMesh* mesh(const std::string& name) {
  static std::map<std::string, frep::TriMesh> cache;
  if (auto it = cache.find(name); it != cache.end()) return &it->second;
  if (!std::filesystem::exists(mesh_path(name))) return nullptr;
  return &cache.emplace(name, frep::read_mesh(mesh_path(name))).first->second;
}

void BM_Convert(benchmark::State& state, const char* name, frep::SignMode sign) {
  const frep::TriMesh* m = mesh(name);
  if (!m) return state.SkipWithError("shared mesh not found");
  if (sign == frep::SignMode::Tetrahedra && std::system("command -v tetgen > /dev/null 2>&1") != 0)
    return state.SkipWithError("tetgen not installed");
  frep::ConvertOptions o;
  o.sign = sign;
  frep::ConvertStats stats;
  for (auto _ : state) {
    frep::ConvertResult r = frep::convert_mesh(*m, o);
    stats = r.stats;
    benchmark::DoNotOptimize(r.model.root);
  }
  state.counters["triangles"] = static_cast<double>(stats.triangles);
  state.counters["nodes_per_triangle"] = static_cast<double>(stats.nodes) / static_cast<double>(stats.triangles);
  state.counters["tetrahedra"] = static_cast<double>(stats.tetrahedra);
}

#define FREP_CONVERT_BENCH(name, file)                                                                       \
  BENCHMARK_CAPTURE(BM_Convert, name##_pseudonormal, file, frep::SignMode::Pseudonormal)                      \
      ->Unit(benchmark::kMillisecond)                                                                        \
      ->UseRealTime();                                                                                       \
  BENCHMARK_CAPTURE(BM_Convert, name##_tets, file, frep::SignMode::Tetrahedra)->Unit(benchmark::kMillisecond)->UseRealTime()
FREP_CONVERT_BENCH(armadillo, "armadillo_libigl.obj");
FREP_CONVERT_BENCH(fandisk, "fandisk.obj");
FREP_CONVERT_BENCH(plate_holes, "plate_holes.stl");
FREP_CONVERT_BENCH(tray_bottom, "tray_bottom_ascii.stl");

// Points near the surface (a random surface point moved by up to 1% of the diagonal) or uniform
// in the bounding box grown by 10%.
struct Points {
  std::vector<float> x, y, z;
  std::vector<double> xd, yd, zd;
};
Points make_points(const frep::TriMesh& m, bool near, std::size_t n) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  const frep::Box3 b = frep::bounding_box(m);
  const frep::Vec3 s = b.size();
  const double diag = length(s);
  Points p;
  for (std::size_t i = 0; i < n; ++i) {
    frep::Vec3 q;
    if (near) {
      const std::size_t t = static_cast<std::size_t>(u(rng) * static_cast<double>(m.num_triangles())) % m.num_triangles();
      double a = u(rng), c = u(rng);
      if (a + c > 1) a = 1 - a, c = 1 - c;
      q = m.corner(t, 0) + (m.corner(t, 1) - m.corner(t, 0)) * a + (m.corner(t, 2) - m.corner(t, 0)) * c;
      q += frep::Vec3{u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5} * (0.02 * diag);
    } else {
      q = {b.lo.x - 0.05 * s.x + 1.1 * s.x * u(rng), b.lo.y - 0.05 * s.y + 1.1 * s.y * u(rng),
           b.lo.z - 0.05 * s.z + 1.1 * s.z * u(rng)};
    }
    p.x.push_back(static_cast<float>(q.x)), p.y.push_back(static_cast<float>(q.y)), p.z.push_back(static_cast<float>(q.z));
    p.xd.push_back(p.x.back()), p.yd.push_back(p.y.back()), p.zd.push_back(p.z.back());
  }
  return p;
}

const frep::Tape* armadillo_tape() {
  static std::unique_ptr<frep::Tape> tape;
  if (!tape) {
    const frep::TriMesh* m = mesh("armadillo_libigl.obj");
    if (!m) return nullptr;
    const frep::ConvertResult r = frep::convert_mesh(*m);
    tape = std::make_unique<frep::Tape>(frep::Tape::compile(*r.model.graph, r.model.root));
  }
  return tape.get();
}

// The converted expression at points, one thread (the point cloud evaluator: pruned per group).
void BM_ExpressionPoints(benchmark::State& state, bool near) {
  const frep::Tape* t = armadillo_tape();
  if (!t) return state.SkipWithError("shared mesh not found");
  const Points p = make_points(*mesh("armadillo_libigl.obj"), near, static_cast<std::size_t>(state.range(0)));
  std::vector<float> out(p.x.size());
  frep::PointCloudEvaluator ev({1});
  for (auto _ : state) ev.eval(*t, p.x.data(), p.y.data(), p.z.data(), out.data(), out.size());
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * out.size()));
}
BENCHMARK_CAPTURE(BM_ExpressionPoints, near, true)->Arg(1 << 14)->Arg(1 << 18)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_ExpressionPoints, uniform, false)->Arg(1 << 14)->Arg(1 << 18)->Unit(benchmark::kMillisecond)->UseRealTime();

// The oracle at the same points, one thread, pseudonormal sign (its faster method).
void BM_OraclePoints(benchmark::State& state, bool near) {
  const frep::TriMesh* m = mesh("armadillo_libigl.obj");
  if (!m) return state.SkipWithError("shared mesh not found");
  const Points p = make_points(*m, near, static_cast<std::size_t>(state.range(0)));
  const frep::MeshDistance md(*m);
  std::vector<double> out(p.x.size());
  for (auto _ : state)
    md.signed_distance(p.xd.data(), p.yd.data(), p.zd.data(), out.data(), out.size(), frep::SignMethod::Pseudonormal, 1);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * out.size()));
}
BENCHMARK_CAPTURE(BM_OraclePoints, near, true)->Arg(1 << 14)->Arg(1 << 18)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_OraclePoints, uniform, false)->Arg(1 << 14)->Arg(1 << 18)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
