// A mesh prepared for distance queries: weld, check, topology, distance oracle, and the sign
// method. The weld, the topology and (usually) the hierarchy are the check's own, built once.
#include "frep/mesh/mesh_field.hpp"

#include <cstdio>
#include <string>

#include "frep/error.hpp"
#include "frep/mesh/bvh.hpp"
#include "frep/mesh/coordinate_range.hpp"
#include "frep/mesh/topology.hpp"
#include "frep/mesh/validate.hpp"

namespace frep {

MeshField::MeshField(const TriMesh& mesh, const MeshFieldOptions& options) {
  mesh.check_consistent();
  check_coordinate_range(mesh);  // beyond float range or precision: refused, naming the vertex
  ValidationOptions vo;
  vo.weld_tolerance = options.weld_tolerance;
  vo.threads = options.threads;
  // The check's intersection test runs on the hierarchy the distance oracle would build (its
  // options, over every triangle of the welded mesh), which is then handed on: the same tree, so
  // the same distances and winding numbers, built once.
  const MeshDistanceOptions distance_options;
  BvhOptions hierarchy;
  hierarchy.max_leaf_size = distance_options.max_leaf_size;
  ValidationProducts products;
  report_ = validate_mesh(mesh, vo, hierarchy, products);
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
  welded_ = std::make_unique<TriMesh>(std::move(products.welded));
  topology_ = std::make_unique<MeshTopology>(std::move(products.topology));
  distance_ = std::make_unique<MeshDistance>(*welded_, *topology_, distance_options,
                                             products.hierarchy ? &*products.hierarchy : nullptr);
  box_ = bounding_box(*welded_);
}

MeshField::~MeshField() = default;
MeshField::MeshField(MeshField&&) noexcept = default;
MeshField& MeshField::operator=(MeshField&&) noexcept = default;

}  // namespace frep
