// A mesh prepared for measuring its signed distance: welded, checked like `frep check`, with the
// exact distance structure (MeshDistance) and the sign method that is exact for it. Shared by
// grid and point sampling and by mesh leaves of expressions (frep/convert/mesh_oracle.hpp), so a
// mesh is read, checked and indexed once.
#pragma once

#include <memory>
#include <string>

#include "frep/math/vec.hpp"
#include "frep/mesh/mesh.hpp"
#include "frep/mesh/mesh_distance.hpp"
#include "frep/mesh/validate.hpp"

namespace frep {

class MeshTopology;

struct MeshFieldOptions {
  // Sign of valid solids. Pseudonormal (default) is exact there and allows the fast grid
  // algorithm; WindingNumber is slower but also right for meshes with holes or self-intersections.
  // Meshes that are not valid solids always get the winding number.
  SignMethod sign = SignMethod::Pseudonormal;
  double weld_tolerance = 0;  // merge vertices closer than this first (as `frep check --weld-tolerance`)
  int threads = 0;            // worker threads for the check (0: all cores)
};

class MeshField {
 public:
  // Welds and validates the mesh (self-intersections included) and builds the distance oracle
  // on the check's welded mesh, topology and (where it could build it so) hierarchy.
  // Throws InputError for a mesh the oracle cannot handle (no triangles, coordinates out of range).
  explicit MeshField(const TriMesh& mesh, const MeshFieldOptions& options = {});
  ~MeshField();
  MeshField(MeshField&&) noexcept;
  MeshField& operator=(MeshField&&) noexcept;

  // True if the mesh is a valid solid (closed, manifold, consistently and outward oriented, no
  // self-intersections): then pseudonormal signs are exact.
  bool solid() const { return solid_; }
  // The sign method in use: the requested one for solids, WindingNumber otherwise.
  SignMethod sign() const { return sign_; }
  // The check's one-line summary ("valid solid: ..." or "not a solid: ...").
  std::string summary() const { return report_.summary(); }
  // The whole check.
  const ValidationReport& report() const { return report_; }

  const TriMesh& welded() const { return *welded_; }
  const MeshTopology& topology() const { return *topology_; }
  const MeshDistance& distance() const { return *distance_; }
  // Bounding box of the used vertices.
  const Box3& box() const { return box_; }
  double surface_area() const { return area_; }

  // Exact signed distance at p with sign(): negative inside.
  double signed_distance(const Vec3& p) const { return distance_->signed_distance(p, sign_); }

 private:
  std::unique_ptr<TriMesh> welded_;
  std::unique_ptr<MeshTopology> topology_;
  std::unique_ptr<MeshDistance> distance_;
  bool solid_ = false;
  SignMethod sign_ = SignMethod::WindingNumber;
  ValidationReport report_;
  Box3 box_;
  double area_ = 0;
};

}  // namespace frep
