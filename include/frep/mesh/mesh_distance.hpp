// The signed-distance oracle: exact (double precision) distance to a triangle mesh through a BVH,
// with the sign from the generalized winding number (robust to holes and self-intersections) or
// from the angle-weighted pseudonormal of the closest feature (exact on clean closed solids).
// Negative inside, like every field in frep.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <memory>
#include <vector>

#include "frep/mesh/mesh.hpp"

namespace frep {

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

class MeshTopology;
class TriangleBvh;

// Largest query coordinate (absolute) a MeshDistance answers: its squares stay finite in double.
// Farther points, infinities and NaN get NaN.
inline constexpr double kMaxQueryCoordinate = 1e150;

class MeshDistance {
 public:
  // Welds the mesh (options.weld_tolerance), then builds as below. Throws InputError for a mesh
  // without triangles or with coordinates beyond the range handled exactly (|x| > 1e100, or a
  // size below 1e-90).
  explicit MeshDistance(const TriMesh& mesh, const MeshDistanceOptions& options = {});
  // From a mesh that is already welded (weld.hpp) and its topology, without welding again
  // (options.weld_tolerance is not used). `bvh`, if given, must have been built over `welded`
  // (with any options) and is used instead of building one. Nothing passed is referenced later.
  MeshDistance(const TriMesh& welded, const MeshTopology& topology, const MeshDistanceOptions& options = {},
               const TriangleBvh* bvh = nullptr);
  MeshDistance(MeshDistance&&) noexcept;
  MeshDistance& operator=(MeshDistance&&) noexcept;
  ~MeshDistance();

  ClosestPoint closest_point(const Vec3& p) const;
  // The same answer, found faster from a triangle known to be near p (`hint`, a triangle index,
  // or kNoHint): usually the previous query's, for a nearby point. The triangle found is
  // written back to `hint`.
  ClosestPoint closest_point(const Vec3& p, std::uint32_t& hint) const;
  static constexpr std::uint32_t kNoHint = UINT32_MAX;
  // The closest point on one given triangle (an index of the mesh's triangles), computed exactly
  // as closest_point computes it on the triangle it finds: callers that know the nearest
  // triangle by other means (frep/sample/grid.hpp) get the same distance bits.
  ClosestPoint closest_point_on(const Vec3& p, std::uint32_t triangle) const;
  double unsigned_distance(const Vec3& p) const { return closest_point(p).distance; }
  // Generalized winding number: 1 inside a closed outward surface, 0 outside, fractional near holes.
  double winding_number(const Vec3& p) const;
  // Exact winding number (sum of all solid angles, no approximation), O(triangles): for tests.
  double winding_number_exact(const Vec3& p) const;
  // +1 outside, -1 inside, 0 on the surface, from the pseudonormal of the closest feature.
  int pseudonormal_sign(const Vec3& p, const ClosestPoint& c) const;
  // The angle-weighted pseudonormal of the closest feature (not normalized; zero for a
  // degenerate one).
  Vec3 pseudonormal(const ClosestPoint& c) const;
  double signed_distance(const Vec3& p, SignMethod method = SignMethod::WindingNumber) const;
  // The same with a hint, as closest_point.
  double signed_distance(const Vec3& p, SignMethod method, std::uint32_t& hint) const;
  // The sign signed_distance gives p off the surface, from its closest point c: +1 outside, -1
  // inside (pseudonormal, or the winding number where the feature is degenerate).
  int side(const Vec3& p, const ClosestPoint& c, SignMethod method) const;

  // Batch versions over `threads` threads (0: all cores); results do not depend on the count.
  void signed_distance(const double* x, const double* y, const double* z, double* out, std::size_t n,
                       SignMethod method = SignMethod::WindingNumber, int threads = 0) const;
  void unsigned_distance(const double* x, const double* y, const double* z, double* out, std::size_t n,
                         int threads = 0) const;

  // The first point where the ray o + t dir (dir need not be unit) meets a triangle, for t in
  // [0, t_max]: its t and triangle index (the mesh's); nullopt if it meets none.
  struct RayHit {
    double t = 0;
    std::uint32_t triangle = 0;
  };
  std::optional<RayHit> first_hit(const Vec3& o, const Vec3& dir, double t_max = INFINITY) const;

  std::size_t num_triangles() const;

 private:
  struct Data;  // the SIMD query layouts and the normals (mesh_distance.cpp)
  std::unique_ptr<Data> d_;
};

// One-shot: signed distances at points (x, y, z columns), by the winding number or pseudonormals.
std::vector<double> signed_distance(const TriMesh& mesh, const std::vector<double>& x, const std::vector<double>& y,
                                    const std::vector<double>& z, SignMethod method = SignMethod::WindingNumber);

}  // namespace frep
