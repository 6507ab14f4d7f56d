// The signed-distance oracle: exact (double precision) distance to a triangle mesh through a BVH,
// with the sign from the generalized winding number (robust to holes and self-intersections) or
// from the angle-weighted pseudonormal of the closest feature (exact on clean closed solids).
// Negative inside, like every field in frep.
#pragma once

#include <cstdint>
#include <vector>

#include "frep/mesh/bvh.hpp"
#include "frep/mesh/mesh.hpp"

namespace frep {

namespace mesh_detail {
// The query structure, 4-wide so one SIMD register of doubles (AVX2; two on SSE4) tests four
// boxes or four triangles at once. Built from the binary BVH by pulling grandchildren up.
constexpr int kWidth = 4;
struct alignas(32) WideNode {
  double lo[3][kWidth], hi[3][kWidth];  // child boxes; an empty slot has lo = +inf, hi = -inf
  std::int32_t child[kWidth];           // >= 0: inner node; < 0: leaf, packets ~child, ~child + 1, ...
  std::uint32_t packets[kWidth];        // number of packets of a leaf child
};
// Four triangles, structure of arrays. Padding lanes repeat the packet's last triangle.
struct alignas(32) TriPacket {
  double a[3][kWidth], b[3][kWidth], c[3][kWidth];  // corners
  double n[3][kWidth];                              // cross(b - a, c - a); zero if degenerate
  double inv_n2[kWidth];                            // 1 / |n|^2, zero if degenerate
  double inv_e2[3][kWidth];  // 1 / |edge k|^2 (edge k joins corners k and k+1), zero if a point
  std::uint32_t tri[kWidth];  // leaf-order triangle index
  double real[kWidth];        // 1 for a triangle, 0 for padding (sums must not count it twice)
};
// Winding-number data of a wide node's children: far from a child, its triangles act as one
// dipole (the area-weighted sum of their normals at their area-weighted centroid).
struct alignas(32) WideDipoles {
  double center[3][kWidth], area_normal[3][kWidth];
  double far2[kWidth];  // (beta * radius)^2: the dipole is used beyond this squared distance
};
}  // namespace mesh_detail

enum class SignMethod {
  WindingNumber,  // inside where the generalized winding number exceeds 1/2
  Pseudonormal,   // side of the closest feature's angle-weighted pseudonormal (Baerentzen-Aanaes)
};

struct MeshDistanceOptions {
  double weld_tolerance = 0;  // vertices are welded (exactly, or within this) for pseudonormals
  double winding_beta = 2.5;  // far-field (dipole) approximation for nodes farther than beta x radius
  int max_leaf_size = 8;      // BVH leaf size
};

// Which part of a triangle the closest point lies on.
enum class Feature : std::uint8_t { Face, Edge0, Edge1, Edge2, Vertex0, Vertex1, Vertex2 };

struct ClosestPoint {
  double distance = 0;  // Euclidean distance to the mesh
  Vec3 point;           // closest point on the mesh
  std::uint32_t triangle = 0;  // index of the triangle it lies on (the mesh's triangle order)
  Feature feature = Feature::Face;  // edge k joins corners k and k+1
};

class MeshDistance {
 public:
  // Builds the hierarchy and the normals. Throws InputError for a mesh without triangles.
  explicit MeshDistance(const TriMesh& mesh, const MeshDistanceOptions& options = {});

  ClosestPoint closest_point(const Vec3& p) const;
  double unsigned_distance(const Vec3& p) const { return closest_point(p).distance; }
  // Generalized winding number: 1 inside a closed outward surface, 0 outside, fractional near holes.
  double winding_number(const Vec3& p) const;
  // Exact winding number (sum of all solid angles, no approximation), O(triangles): for tests.
  double winding_number_exact(const Vec3& p) const;
  // +1 outside, -1 inside, 0 on the surface, from the pseudonormal of the closest feature.
  int pseudonormal_sign(const Vec3& p, const ClosestPoint& c) const;
  double signed_distance(const Vec3& p, SignMethod method = SignMethod::WindingNumber) const;

  // Batch versions over `threads` threads (0: all cores); results do not depend on the count.
  void signed_distance(const double* x, const double* y, const double* z, double* out, std::size_t n,
                       SignMethod method = SignMethod::WindingNumber, int threads = 0) const;
  void unsigned_distance(const double* x, const double* y, const double* z, double* out, std::size_t n,
                         int threads = 0) const;

  std::size_t num_triangles() const { return tri_.size(); }

 private:
  struct Tri {
    Vec3 a, b, c;
  };
  std::vector<mesh_detail::WideNode> wide_;        // the query hierarchy
  std::vector<mesh_detail::WideDipoles> dipoles_;  // per wide node
  std::vector<mesh_detail::TriPacket> packets_;
  std::vector<Tri> tri_;                     // in BVH leaf order
  std::vector<std::uint32_t> tri_id_;        // leaf order -> mesh triangle index
  std::vector<Vec3> face_normal_;            // per mesh triangle, unit (zero if degenerate)
  std::vector<Vec3> edge_normal_;            // per mesh triangle and edge (3 per triangle)
  std::vector<Vec3> vertex_normal_;          // per welded vertex
  std::vector<Triangle> welded_;             // per mesh triangle, welded vertex indices
  MeshDistanceOptions options_;
};

// One-shot: signed distances at points (x, y, z columns), by the winding number or pseudonormals.
std::vector<double> signed_distance(const TriMesh& mesh, const std::vector<double>& x, const std::vector<double>& y,
                                    const std::vector<double>& z, SignMethod method = SignMethod::WindingNumber);

}  // namespace frep
