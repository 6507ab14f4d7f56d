// make_solid: the exact repair, else the winding-number field remeshed.
#include "frep/convert/make_solid.hpp"

#include <cstdio>

#include "frep/contour/mesher.hpp"
#include "frep/convert/mesh_oracle.hpp"
#include "frep/eval/tape.hpp"
#include "frep/error.hpp"

namespace frep {

RepairResult make_solid(const TriMesh& mesh, const RepairOptions& options) {
  try {
    return repair_mesh(mesh, options);
  } catch (const RepairStopped&) {
    throw;
  } catch (const InputError& e) {
    if (options.remesh_resolution <= 0 || mesh.triangles.empty()) throw;
    if (!options.quiet)
      std::fprintf(stderr, "frep: repair: no exact repair (%s); remeshing the winding-number field at %d cells\n",
                   e.detail().c_str(), options.remesh_resolution);
    ConvertOptions co;
    co.weld_tolerance = options.weld_tolerance;
    co.threads = options.threads;
    const Model model = mesh_model(MeshOracle::any_mesh(mesh, co));
    const Tape tape = Tape::compile(*model.graph, model.root);
    MeshOptions mo;
    mo.resolution = options.remesh_resolution;
    mo.lipschitz = 1;
    mo.known_bounds = model.info.bounds;
    mo.threads = options.threads;
    MeshStats stats;
    RepairResult r;
    try {
      r.mesh = mesh_expression(tape, mo, &stats);
    } catch (const InternalError&) {
      // The winding-number sign jumps where holes are wide open (a soup of triangles), and the
      // mesher's pruning assumes a field that changes no faster than the distance.
      throw InputError(mesh.name, 0, "no exact repair (" + e.detail() +
                                         "), and its winding number is too irregular to remesh (a soup of triangles "
                                         "with wide holes bounds no clear volume)");
    }
    r.mesh.name = mesh.name;
    if (options.float_coordinates) round_vertices_to_float(r.mesh);
    if (r.mesh.triangles.empty())
      throw InputError(mesh.name, 0, "the mesh encloses no volume (no part of it has winding number 1/2 or more)");
    RepairReport& rep = r.report;
    rep.file = mesh.name;
    rep.triangles_in = mesh.triangles.size();
    rep.triangles_out = r.mesh.triangles.size();
    ValidationOptions vo;
    vo.weld_tolerance = options.weld_tolerance;
    vo.threads = options.threads;
    rep.before = validate_mesh(mesh, vo);
    rep.after = validate_mesh(r.mesh, {});
    rep.volume_before = rep.before.volume;
    rep.volume_after = rep.after.volume;
    rep.changed = true;
    rep.exact = false;
    rep.remeshed = options.remesh_resolution;
    rep.notes.push_back("no exact repair: " + e.detail());
    if (!rep.after.is_solid())
      throw InputError(mesh.name, 0, "no exact repair (" + e.detail() + "), and the remeshed approximation is not a solid either: " +
                                         rep.after.summary());
    return r;
  }
}

}  // namespace frep
