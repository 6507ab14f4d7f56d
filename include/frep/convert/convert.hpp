// Mesh -> expression: turns a closed triangle mesh into a closed-form expression whose value at
// every point of space is the exact signed distance to the mesh's surface (negative inside),
// written with Fidget's opcodes only.
//
// The unsigned part is a minimum over features: each flat region (coplanar neighbouring
// triangles, merged) contributes its plane distance inside its prism, each crease edge the
// distance to its segment (which also covers its endpoints), and the few vertices whose sign the
// edges cannot settle contribute their own distance. Edges between coplanar, consistently
// oriented triangles get no term at all. All terms are squared distances, combined in a balanced
// tree that follows the mesh's spatial order, so interval pruning drops whole far subtrees.
//
// The sign comes from one of two methods:
//   Pseudonormal: every term is tested by its feature's angle-weighted pseudonormal (Baerentzen
//     and Aanaes 2005) and joins one of two minima, P (the test says outside) or N (inside); the
//     value is sqrt(P) where P <= N, else -sqrt(N). Exact for closed, consistently oriented
//     meshes; no external program; intervals settle the sign away from the surface.
//   Tetrahedra: TetGen tetrahedralizes the solid preserving its surface (the separate `tetgen`
//     program, run as a child process: it is AGPL and crashes on bad input); the value is negated
//     inside the union of the tetrahedra.
// Running TetGen: the calling thread forks and execs it in a process group of its own, in a
// scratch directory under $TMPDIR (output to a log file there, no pipes), waits for exactly that
// child (polling, up to tetgen_timeout; then the group is killed) and reaps it. No signal handler
// is installed and no signal blocked unless the program called install_interrupt_cleanup()
// (frep/util/atomic_file.hpp). TetGen inherits stdin and descriptors not marked close-on-exec; a
// program that ignores SIGCHLD or reaps every child itself makes such conversions fail.
// See docs/convert.md for the construction, its cost per triangle and the numerics.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "frep/expr/model.hpp"
#include "frep/mesh/mesh.hpp"
#include "frep/mesh/validate.hpp"

namespace frep {

enum class SignMode {
  Pseudonormal,  // sign of the nearest feature's pseudonormal (default)
  Tetrahedra,    // inside the union of TetGen's tetrahedra
};

struct ConvertOptions {
  SignMode sign = SignMode::Pseudonormal;  // how the inside is told from the outside
  double weld_tolerance = 0;  // merge vertices closer than this before checking (0: identical only)
  int threads = 0;            // worker threads for the mesh check (0: all cores)
  std::string tetgen = "tetgen";  // the TetGen program (SignMode::Tetrahedra), found on PATH
  double tetgen_timeout = 600;    // seconds before TetGen is stopped and the conversion fails
  // load_field: repair meshes that are not valid solids first (make_solid), instead of refusing them.
  bool repair = false;
  // Called now and then with a stage name and the fraction of the whole job done (0 to 1).
  std::function<void(const char* stage, double fraction)> progress;
};

struct ConvertStats {
  std::size_t triangles = 0;       // usable triangles of the welded mesh
  std::size_t vertices = 0;        // welded vertices
  std::size_t flat_regions = 0;    // plane terms (coplanar neighbours share one)
  std::size_t polygons = 0;        // convex pieces of the flat regions (one prism test each)
  std::size_t edge_terms = 0;      // crease edges (edges inside flat regions need none)
  std::size_t vertex_terms = 0;    // vertices whose sign the edges cannot settle
  std::size_t tetrahedra = 0;      // TetGen's tetrahedra (SignMode::Tetrahedra)
  std::size_t nodes = 0;           // nodes of the expression
  double seconds = 0;              // wall time of the conversion, check included
  Box3 box;                        // bounding box of the triangles' corners (the solid's extent)
  std::vector<std::string> read_warnings;  // load_field: what the mesh reader tolerated (TriMesh::warnings)
  std::string repaired;                    // load_field with repair: what the repair did (one line), if anything
};

struct ConvertResult {
  Model model;
  ConvertStats stats;
};

// Throws the InputError convert_mesh gives a mesh it refuses, from the mesh's check (`name`
// names the file): not a usable solid, or zero-area triangles (no normal, so no sign next to
// them).
void check_convertible(const std::string& name, const ValidationReport& check);

// Converts a mesh as read from a file. The mesh is welded and checked like `frep check` does
// first: a mesh that is not a usable solid (open, non-manifold, inconsistently or inward
// oriented, self-intersecting...) is refused with InputError carrying the check's summary.
// TetGen failures (missing program, crash, timeout, changed surface) are InputErrors too.
ConvertResult convert_mesh(const TriMesh& mesh, const ConvertOptions& options = {});


}  // namespace frep
