// The CGAL baseline of bench/sdf_points.py: signed distances of a closed mesh at given points,
// with CGAL's AABB tree (closest point, double precision) for the magnitude and
// Side_of_triangle_mesh (ray shooting) for the sign, split over threads. Writes the distances
// as a float32 .npy and prints one line of JSON with the time and the rate.
//   build/bench/bench_sdf_points_cgal MESH POINTS.npy OUT.npy [THREADS]
// POINTS.npy is an (N, 3) float32 array; the time excludes reading and tree building, reported
// separately.
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <stdexcept>
#include <thread>
#include <vector>

#include "frep/io/npy.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/weld.hpp"

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<K::Point_3>;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s MESH POINTS.npy OUT.npy [THREADS]\n", argv[0]);
    return 2;
  }
  try {
    const int threads = argc > 4 ? std::max(1, std::atoi(argv[4])) : 1;
    const auto t0 = std::chrono::steady_clock::now();
    const frep::TriMesh tri = frep::weld(frep::read_mesh(argv[1])).mesh;
    Mesh mesh;
    std::vector<Mesh::Vertex_index> vs;
    for (const frep::Vec3& v : tri.vertices) vs.push_back(mesh.add_vertex(K::Point_3(v.x, v.y, v.z)));
    for (std::size_t t = 0; t < tri.num_triangles(); ++t)
      mesh.add_face(vs[tri.triangles[t][0]], vs[tri.triangles[t][1]], vs[tri.triangles[t][2]]);
    Tree tree(faces(mesh).first, faces(mesh).second, mesh);
    tree.accelerate_distance_queries();
    const CGAL::Side_of_triangle_mesh<Mesh, K> inside(tree);
    const frep::NpyArray pts = frep::read_npy(argv[2]);
    if (pts.shape.size() != 2 || pts.shape[1] != 3) throw std::runtime_error("points must be an (N, 3) float32 array");
    const std::size_t n = pts.shape[0];
    const double setup = seconds_since(t0);

    std::vector<float> out(n);
    const auto t1 = std::chrono::steady_clock::now();
    std::vector<std::thread> pool;
    for (int w = 0; w < threads; ++w)
      pool.emplace_back([&, w] {
        for (std::size_t i = n * w / threads; i < n * (w + 1) / threads; ++i) {
          const K::Point_3 p(pts.data[3 * i], pts.data[3 * i + 1], pts.data[3 * i + 2]);
          const double d = std::sqrt(CGAL::to_double(tree.squared_distance(p)));
          out[i] = static_cast<float>(inside(p) == CGAL::ON_BOUNDED_SIDE ? -d : d);
        }
      });
    for (auto& t : pool) t.join();
    const double query = seconds_since(t1);
    frep::write_npy(argv[3], out.data(), {n});
    std::printf("{\"points\": %zu, \"threads\": %d, \"setup_s\": %.4f, \"query_s\": %.4f, \"points_per_s\": %.0f}\n", n,
                threads, setup, query, n / query);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_sdf_points_cgal: %s\n", e.what());
    return 1;
  }
}
