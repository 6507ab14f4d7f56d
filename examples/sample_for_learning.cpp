// Example: training data for a neural signed distance function, from a triangle mesh. Writes two
// NumPy files:
//   points.npy  (N, 4) float32 rows (x, y, z, d): points near the surface and their exact
//               signed distance (negative inside)
//   grid.npy    (n, n, n) float32: exact signed distances on a cube grid around the mesh;
//               grid[i][j][k] is the distance at (x_i, y_j, z_k), see frep/sample/grid.hpp
//
//   sample_for_learning [INPUT mesh] [OUTPUT_DIR] [N] [n]
//   (defaults: examples/bracket.obj, ., 100000, 64)
//
// In Python: np.load("points.npy"), np.load("grid.npy").
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include <frep/frep.hpp>

int main(int argc, char** argv) {
  try {
    const std::string input = argc > 1 ? argv[1] : "examples/bracket.obj";
    const std::string dir = argc > 2 ? argv[2] : ".";
    const std::size_t count = argc > 3 ? std::strtoull(argv[3], nullptr, 10) : 100000;
    const int n = argc > 4 ? std::atoi(argv[4]) : 64;

    // The mesh's exact distance: welds, validates and builds a BVH over its triangles.
    const frep::MeshField field(frep::read_mesh(input));
    std::printf("%s: %s\n", input.c_str(), field.summary().c_str());

    // Near-surface samples: surface points moved by Gaussian noise, sigma 1% of the box's
    // diagonal. The same seed gives the same points on any number of threads.
    const double sigma = 0.01 * length(field.box().size());
    frep::PointSampleOptions point_options;
    point_options.seed = 1;
    const std::vector<float> points = frep::sample_near_surface(field, count, sigma, point_options);
    frep::write_npy(dir + "/points.npy", points.data(), {count, 4});

    // A dense grid on the cube around the mesh (5% margin), so the voxels are cubes.
    const frep::GridSpec grid = frep::cube_grid(frep::default_mesh_bounds(field.box()), n);
    const std::vector<float> distances = frep::sample_grid(field, grid);
    const auto side = static_cast<std::size_t>(n);
    frep::write_npy(dir + "/grid.npy", distances.data(), {side, side, side});

    // Read both back and check them: the shapes, finite values, and both signs present.
    const frep::NpyArray p = frep::read_npy(dir + "/points.npy");
    const frep::NpyArray d = frep::read_npy(dir + "/grid.npy");
    std::size_t inside = 0, bad = 0;
    for (float v : d.data) {
      if (!std::isfinite(v)) ++bad;
      if (v < 0) ++inside;
    }
    std::printf("points.npy: %zu rows; grid.npy: %d^3, %zu samples inside\n", p.shape[0], n, inside);
    const bool ok = p.shape == std::vector<std::size_t>{count, 4} && d.shape == std::vector<std::size_t>{side, side, side} &&
                    bad == 0 && inside > 0 && inside < d.data.size();
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sample_for_learning: %s\n", e.what());
    return 1;
  }
}
