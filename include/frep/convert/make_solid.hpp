// make_solid: repair (frep/mesh/repair.hpp), and where no exact repair is found, the stated
// approximation: the mesh's winding-number signed distance (inside where the generalized winding
// number is at least 1/2) meshed by dual contouring. What `frep repair` and `--repair` run.
#pragma once

#include "frep/mesh/repair.hpp"

namespace frep {

// repair_mesh; if that fails for any reason but the time limit or an empty mesh, and
// options.remesh_resolution > 0, the approximation at that many cells across the mesh's box
// (report.remeshed says so, report.notes says why). Throws InputError if neither gives a solid.
RepairResult make_solid(const TriMesh& mesh, const RepairOptions& options = {});

}  // namespace frep
