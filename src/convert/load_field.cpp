// load_field: expression files as they are, meshes converted on the way in.
#include "frep/convert/convert.hpp"
#include "frep/error.hpp"
#include "frep/io/load.hpp"
#include "frep/mesh/mesh_io.hpp"

namespace frep {

Model load_field(const std::string& path, const ConvertOptions& options, ConvertStats* stats) {
  if (format_from_extension(path) == MeshFormat::Unknown) return load_expression(path);
  const TriMesh mesh = read_mesh(path);
  try {
    ConvertResult r = convert_mesh(mesh, options);
    if (stats) {
      *stats = r.stats;
      stats->read_warnings = mesh.warnings;
    }
    return std::move(r.model);
  } catch (const InputError& e) {
    // The converter sees a mesh, not a file: name the file here.
    if (!e.file().empty()) throw;
    throw InputError(path, e.line(), e.detail(), e.byte_offset());
  }
}

}  // namespace frep
