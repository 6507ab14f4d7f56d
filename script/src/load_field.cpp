// load_field: expression files as they are (scripts may load meshes with mesh("...")), meshes as
// mesh oracles (their exact signed distance through their distance structure).
#include <chrono>

#include "frep/convert/convert.hpp"
#include "frep/convert/make_solid.hpp"
#include "frep/convert/mesh_oracle.hpp"
#include "frep/error.hpp"
#include "frep/script/load.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/topology.hpp"

namespace frep {
namespace {

// Reads and checks a mesh file; `warnings` receives what the reader tolerated.
std::shared_ptr<const MeshOracle> load_mesh_oracle(const std::string& path, const ConvertOptions& options,
                                                   std::vector<std::string>* warnings = nullptr,
                                                   std::string* repaired = nullptr) {
  TriMesh mesh = read_mesh(path);
  if (warnings) *warnings = mesh.warnings;
  try {
    if (options.repair) {
      RepairOptions ro;
      ro.weld_tolerance = options.weld_tolerance;
      ro.threads = options.threads;
      RepairResult r = make_solid(mesh, ro);
      if (r.report.changed && repaired) *repaired = repair_summary(r.report);
      mesh = std::move(r.mesh);
      mesh.name = path;
    }
    return std::make_shared<const MeshOracle>(mesh, options);
  } catch (const InputError& e) {
    // The checks see a mesh, not a file: name the file here.
    if (!e.file().empty()) throw;
    throw InputError(path, e.line(), e.detail(), e.byte_offset());
  }
}

}  // namespace

Model load_field(const std::string& path, const ConvertOptions& options, ConvertStats* stats) {
  if (format_from_extension(path) == MeshFormat::Unknown) {
    RhaiOptions rhai;
    rhai.load_mesh = [options](const std::string& mesh_path) -> std::shared_ptr<const Oracle> {
      return load_mesh_oracle(mesh_path, options);
    };
    return load_expression(path, rhai, &mesh_oracle_codec());
  }
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::string> warnings;
  std::string repaired;
  auto oracle = load_mesh_oracle(path, options, &warnings, &repaired);
  if (stats) {
    *stats = ConvertStats{};
    const MeshField& f = oracle->field();
    stats->triangles = f.distance().num_triangles();
    stats->vertices = f.topology().num_used_vertices();
    stats->box = f.box();
    stats->nodes = 1;
    stats->read_warnings = std::move(warnings);
    stats->repaired = std::move(repaired);
    stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return mesh_model(std::move(oracle));
}

}  // namespace frep
