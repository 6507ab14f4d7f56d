// Points per second of the signed-distance oracle on armadillo (86k triangles), against CGAL's
// AABB_tree closest-point query on the same points, single-threaded. Uniform points in the
// mesh's bounding box, and points near the surface (1% of the diagonal, Gaussian).
//   build/bench/bench_mesh_distance --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <random>

#include "frep/mesh/mesh_distance.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/topology.hpp"
#include "frep/mesh/weld.hpp"

namespace {

using K = CGAL::Simple_cartesian<double>;
using CgalTriangles = std::vector<K::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<K, CgalTriangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

constexpr std::size_t kPoints = 100000;

struct Fixture {
  frep::TriMesh mesh;
  std::unique_ptr<frep::MeshDistance> ours;
  CgalTriangles cgal_tris;
  std::unique_ptr<Tree> tree;
  std::vector<frep::Vec3> uniform, near;
  bool ok = false;
};

Fixture& fixture() {
  static Fixture f = [] {
    Fixture f;
    const std::string path = FREP_SOURCE_DIR "/../shared/data/meshes/armadillo_libigl.obj";
    if (!std::filesystem::exists(path)) return f;
    f.mesh = frep::read_mesh(path);
    f.ours = std::make_unique<frep::MeshDistance>(f.mesh);
    for (std::size_t t = 0; t < f.mesh.num_triangles(); ++t) {
      auto P = [&](int k) {
        const frep::Vec3 v = f.mesh.corner(t, k);
        return K::Point_3(v.x, v.y, v.z);
      };
      f.cgal_tris.emplace_back(P(0), P(1), P(2));
    }
    f.tree = std::make_unique<Tree>(f.cgal_tris.cbegin(), f.cgal_tris.cend());
    f.tree->build();
    f.tree->accelerate_distance_queries();
    const frep::Box3 box = frep::bounding_box(f.mesh);
    const double diag = frep::length(box.size());
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> u(0, 1);
    std::normal_distribution<double> g(0, 0.01 * diag);
    std::uniform_int_distribution<std::size_t> tri(0, f.mesh.num_triangles() - 1);
    for (std::size_t i = 0; i < kPoints; ++i) {
      f.uniform.push_back({box.lo.x + u(rng) * box.size().x, box.lo.y + u(rng) * box.size().y,
                           box.lo.z + u(rng) * box.size().z});
      const std::size_t t = tri(rng);
      double a = u(rng), b = u(rng);
      if (a + b > 1) a = 1 - a, b = 1 - b;
      const frep::Vec3 p0 = f.mesh.corner(t, 0), p1 = f.mesh.corner(t, 1), p2 = f.mesh.corner(t, 2);
      f.near.push_back(p0 + (p1 - p0) * a + (p2 - p0) * b + frep::Vec3{g(rng), g(rng), g(rng)});
    }
    // Both answer the same question: check the distances agree before timing anything.
    for (const auto* pts : {&f.uniform, &f.near})
      for (std::size_t i = 0; i < pts->size(); i += 97) {
        const frep::Vec3 p = (*pts)[i];
        const K::Point_3 q = f.tree->closest_point(K::Point_3(p.x, p.y, p.z));
        const double dc = std::sqrt(CGAL::squared_distance(q, K::Point_3(p.x, p.y, p.z)));
        const double d = f.ours->unsigned_distance(p);
        if (std::fabs(dc - d) > 1e-12 * diag) {
          std::fprintf(stderr, "distance mismatch at point %zu: frep %.17g, CGAL %.17g\n", i, d, dc);
          std::abort();
        }
      }
    f.ok = true;
    return f;
  }();
  return f;
}

const std::vector<frep::Vec3>& points(Fixture& f, int which) { return which == 0 ? f.uniform : f.near; }

void BM_Frep_Unsigned(benchmark::State& state) {
  Fixture& f = fixture();
  if (!f.ok) return state.SkipWithError("../shared/data/meshes/armadillo_libigl.obj is absent");
  const auto& pts = points(f, static_cast<int>(state.range(0)));
  double sink = 0;
  for (auto _ : state)
    for (const frep::Vec3& p : pts) sink += f.ours->closest_point(p).distance;
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(state.iterations() * pts.size());
  state.SetLabel(state.range(0) == 0 ? "uniform" : "near surface");
}

void BM_Frep_Signed(benchmark::State& state) {
  Fixture& f = fixture();
  if (!f.ok) return state.SkipWithError("../shared/data/meshes/armadillo_libigl.obj is absent");
  const auto& pts = points(f, static_cast<int>(state.range(0)));
  const auto method = state.range(1) == 0 ? frep::SignMethod::WindingNumber : frep::SignMethod::Pseudonormal;
  double sink = 0;
  for (auto _ : state)
    for (const frep::Vec3& p : pts) sink += f.ours->signed_distance(p, method);
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(state.iterations() * pts.size());
  state.SetLabel(std::string(state.range(0) == 0 ? "uniform" : "near surface") +
                 (state.range(1) == 0 ? ", winding number" : ", pseudonormal"));
}

void BM_Cgal_ClosestPoint(benchmark::State& state) {
  Fixture& f = fixture();
  if (!f.ok) return state.SkipWithError("../shared/data/meshes/armadillo_libigl.obj is absent");
  const auto& pts = points(f, static_cast<int>(state.range(0)));
  double sink = 0;
  for (auto _ : state)
    for (const frep::Vec3& p : pts) {
      const K::Point_3 q(p.x, p.y, p.z);
      sink += std::sqrt(CGAL::squared_distance(f.tree->closest_point(q), q));
    }
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(state.iterations() * pts.size());
  state.SetLabel(state.range(0) == 0 ? "uniform" : "near surface");
}

void BM_Frep_Build(benchmark::State& state) {
  Fixture& f = fixture();
  if (!f.ok) return state.SkipWithError("../shared/data/meshes/armadillo_libigl.obj is absent");
  for (auto _ : state) benchmark::DoNotOptimize(frep::MeshDistance(f.mesh).num_triangles());
}

// The part of the build that is the shared mesh topology (edges, fans, shells, normals, shapes).
void BM_Frep_Topology(benchmark::State& state) {
  Fixture& f = fixture();
  if (!f.ok) return state.SkipWithError("../shared/data/meshes/armadillo_libigl.obj is absent");
  const frep::TriMesh welded = frep::weld(f.mesh).mesh;
  for (auto _ : state) benchmark::DoNotOptimize(frep::MeshTopology(welded).num_edges());
}

void BM_Cgal_Build(benchmark::State& state) {
  Fixture& f = fixture();
  if (!f.ok) return state.SkipWithError("../shared/data/meshes/armadillo_libigl.obj is absent");
  for (auto _ : state) {
    Tree t(f.cgal_tris.cbegin(), f.cgal_tris.cend());
    t.build();
    t.accelerate_distance_queries();
  }
}

}  // namespace

BENCHMARK(BM_Frep_Unsigned)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Cgal_ClosestPoint)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Frep_Signed)->Args({0, 0})->Args({1, 0})->Args({0, 1})->Args({1, 1})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Frep_Build)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Frep_Topology)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Cgal_Build)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
