// load_field: expression files as they are, meshes as mesh oracles (their exact signed
// distance through their distance structure).
#include <chrono>

#include "frep/convert/convert.hpp"
#include "frep/convert/mesh_oracle.hpp"
#include "frep/error.hpp"
#include "frep/io/load.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/topology.hpp"

namespace frep {

Model load_field(const std::string& path, const ConvertOptions& options, ConvertStats* stats) {
  if (format_from_extension(path) == MeshFormat::Unknown) return load_expression(path);
  const auto t0 = std::chrono::steady_clock::now();
  const TriMesh mesh = read_mesh(path);
  try {
    auto oracle = std::make_shared<const MeshOracle>(mesh, options);
    if (stats) {
      *stats = ConvertStats{};
      const MeshField& f = oracle->field();
      stats->triangles = f.distance().num_triangles();
      stats->vertices = f.topology().num_used_vertices();
      stats->box = f.box();
      stats->nodes = 1;
      stats->read_warnings = mesh.warnings;
      stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    return mesh_model(std::move(oracle));
  } catch (const InputError& e) {
    // The checks see a mesh, not a file: name the file here.
    if (!e.file().empty()) throw;
    throw InputError(path, e.line(), e.detail(), e.byte_offset());
  }
}

}  // namespace frep
