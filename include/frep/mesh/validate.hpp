// Validation: everything that can make a triangle mesh unusable as the boundary of a solid, with
// counts and example locations a user can act on (triangle indices, file lines, coordinates).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "frep/mesh/bvh.hpp"
#include "frep/mesh/mesh.hpp"
#include "frep/mesh/topology.hpp"

namespace frep {

struct ValidationOptions {
  double weld_tolerance = 0;       // vertices closer than this are merged first (0: exact positions)
  bool self_intersections = true;  // run the exact triangle-triangle intersection test
  std::size_t max_examples = 5;    // example locations kept per kind of defect
  double needle_quality = 1e-4;    // triangles with 4*sqrt(3)*area/sum(edge^2) below this are needles
  int threads = 0;                 // worker threads for the intersection test (0: all cores)
};

enum class DefectKind {
  OpenEdges,                // edges with one triangle: holes
  NonManifoldEdges,         // edges with more than two triangles
  NonManifoldVertices,      // vertices whose triangles form several fans (pinched)
  InconsistentOrientation,  // edges whose two triangles traverse them in the same direction
  InwardOrientation,        // closed and consistent, but the enclosed volume is negative
  ShellOrientation,         // several shells, one of them inward where it should be outward or
                            // nested inside a shell of the same orientation (winding number 2)
  DegenerateShells,         // closed shells that enclose no volume (all corners coplanar)
  SelfIntersections,        // pairs of triangles whose interiors cross
  Overlaps,                 // coplanar pairs whose interiors overlap, including folds
  DuplicateTriangles,       // triangles with the same three vertices as an earlier one
  ZeroAreaTriangles,        // three distinct but collinear vertices
  CollapsedTriangles,       // a vertex repeated (after welding); ignored by the other checks
  NeedleTriangles,          // non-zero but tiny area for their edge lengths
  TouchingPairs,            // non-neighbours whose boundaries meet but interiors do not
  UnusedVertices,           // vertices no triangle refers to
  DuplicateVertices,        // vertices at the position of another vertex (merged by welding)
};
inline constexpr int kDefectKinds = 16;

// Where a defect is: a triangle (index into the file's triangles after fan triangulation, with
// the face and line it came from), optionally a second triangle, and a point.
struct DefectLocation {
  std::uint32_t triangle = 0xffffffffu;
  std::uint32_t other = 0xffffffffu;   // second triangle of a pair
  std::uint32_t vertex = 0xffffffffu;  // vertex index in the file
  std::uint32_t face = 0xffffffffu;    // the file's face (facet, polygon) of `triangle`
  std::uint32_t line = 0;              // line of that face in text formats, 0 otherwise
  Vec3 point;                          // a representative position (edge midpoint, vertex...)
};

struct Defect {
  DefectKind kind;
  std::uint64_t count = 0;
  std::vector<DefectLocation> examples;
};

struct ValidationReport {
  std::string file;
  std::size_t file_vertices = 0, triangles = 0, welded_vertices = 0, edges = 0;
  std::size_t components = 0;       // edge-connected pieces
  std::optional<std::int64_t> genus;  // total genus, only for closed manifold meshes
  // Signed volume (positive for outward orientation) and area, in the file's units; +-inf when
  // the true value is beyond the double range (coordinates near 1e200 and up).
  double volume = 0, area = 0;
  Box3 box;
  bool self_intersections_checked = false;
  std::vector<Defect> defects;  // one entry per DefectKind, in enum order

  const Defect& defect(DefectKind k) const { return defects[static_cast<int>(k)]; }
  // True for a closed, manifold, consistently and outward oriented surface without
  // self-intersections, overlaps or duplicate triangles, with at least one usable triangle and
  // no flat shell: usable for exact conversion.
  bool is_solid() const;
  // One line: "valid solid: ..." or "not a solid: <the defects that make it unusable>".
  std::string summary() const;
  std::string to_text() const;
  std::string to_json() const;
};

// Short machine name ("open_edges") and description of a defect kind; whether it is fatal.
const char* defect_key(DefectKind k);
const char* defect_description(DefectKind k);
bool defect_is_fatal(DefectKind k);

// Welds (exactly, or with the tolerance) and validates a mesh as read from a file.
ValidationReport validate_mesh(const TriMesh& mesh, const ValidationOptions& options = {});

// What validation builds on the way, for a caller that goes on to index the mesh (MeshField), so
// that it is not built twice.
struct ValidationProducts {
  TriMesh welded;         // the mesh welded as options.weld_tolerance says (weld.hpp), in the file's coordinates
  MeshTopology topology;  // of `welded`, as MeshTopology(welded) builds it
  // TriangleBvh(welded, hierarchy options), exactly as built from those, when the intersection
  // test could run on it: it ran (options.self_intersections), no triangle is flat (zero area,
  // collapsed, a duplicate: they are left out of the test), and the coordinates are finite with
  // the largest within 2^-60 .. 2^60 (single-precision boxes stay tight). Empty otherwise.
  std::optional<TriangleBvh> hierarchy;
};

// The same validation (the same report), also handing back the products above; `hierarchy`
// gives the options of the hierarchy to hand back.
ValidationReport validate_mesh(const TriMesh& mesh, const ValidationOptions& options, const BvhOptions& hierarchy,
                               ValidationProducts& products);

}  // namespace frep
