// A mesh prepared for distance queries: weld, check, topology, distance oracle, and the sign method.
#include "frep/mesh/mesh_field.hpp"

#include <cstdio>
#include <string>

#include "frep/error.hpp"
#include "frep/mesh/topology.hpp"
#include "frep/mesh/validate.hpp"
#include "frep/mesh/weld.hpp"

namespace frep {

MeshField::MeshField(const TriMesh& mesh, const MeshFieldOptions& options) {
  mesh.check_consistent();
  ValidationOptions vo;
  vo.weld_tolerance = options.weld_tolerance;
  vo.threads = options.threads;
  report_ = validate_mesh(mesh, vo);
  solid_ = report_.is_solid();
  area_ = report_.area;
  if (!(area_ > 0)) {
    // Nothing to measure distances to (every triangle collapsed: degenerate, or merged by a weld
    // tolerance as large as the mesh).
    char tol[64] = "";
    if (options.weld_tolerance > 0) std::snprintf(tol, sizeof tol, " after welding within %g", options.weld_tolerance);
    throw InputError(mesh.name, 0, std::string("the mesh has no area") + tol + ": " + summary());
  }
  sign_ = solid_ ? options.sign : SignMethod::WindingNumber;
  WeldResult w = weld(mesh, {options.weld_tolerance});
  welded_ = std::make_unique<TriMesh>(std::move(w.mesh));
  topology_ = std::make_unique<MeshTopology>(*welded_);
  distance_ = std::make_unique<MeshDistance>(*welded_, *topology_);
  box_ = bounding_box(*welded_);
}

MeshField::~MeshField() = default;
MeshField::MeshField(MeshField&&) noexcept = default;
MeshField& MeshField::operator=(MeshField&&) noexcept = default;

}  // namespace frep
