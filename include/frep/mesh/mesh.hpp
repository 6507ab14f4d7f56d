// The triangle mesh value type every mesh reader produces and every mesh algorithm consumes.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "frep/math/vec.hpp"

namespace frep {

using Triangle = std::array<std::uint32_t, 3>;

// Where a triangle came from in its file: polygons are fan-triangulated, so several triangles
// may share one face.
struct FaceOrigin {
  std::uint32_t face = 0;  // 0-based index of the face (facet, polygon, strip) in the file
  std::uint32_t line = 0;  // 1-based line of that face in text formats, 0 for binary formats
};

// An indexed triangle mesh. Readers record each triangle's origin in the file; meshes made in
// memory (a mesher's output) usually have none.
struct TriMesh {
  std::vector<Vec3> vertices;
  std::vector<Triangle> triangles;
  // Empty (no provenance), or one entry per triangle: use origin_of(), which handles both.
  std::vector<FaceOrigin> origins;
  // True when the file format shares vertices between faces (OBJ, PLY, OFF); false for STL,
  // which repeats the coordinates of every corner.
  bool indexed = true;
  // Name of the file it was read from, for messages (may be empty).
  std::string name;
  // What the reader tolerated and the user should know (a binary STL's wrong triangle count, a
  // missing 'endsolid'), one sentence each, without the file name.
  std::vector<std::string> warnings;

  std::size_t num_vertices() const { return vertices.size(); }
  std::size_t num_triangles() const { return triangles.size(); }
  Vec3 corner(std::size_t t, int k) const { return vertices[triangles[t][k]]; }
  bool has_origins() const { return !origins.empty(); }
  // Triangle t's origin; without recorded provenance, face t on no line.
  FaceOrigin origin_of(std::size_t t) const {
    return origins.empty() ? FaceOrigin{static_cast<std::uint32_t>(t), 0} : origins[t];
  }
  // Adds a triangle without provenance (only while the mesh has none).
  void add_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) { triangles.push_back({a, b, c}); }
  // Adds a triangle with its origin (the mesh must record origins for every triangle).
  void add_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t face, std::uint32_t line) {
    triangles.push_back({a, b, c});
    origins.push_back({face, line});
  }
  // Throws InputError (naming the mesh) unless every index refers to a vertex, and the origins
  // are absent or one per triangle. Algorithms call it on meshes they did not read themselves.
  void check_consistent() const;
};

// Axis-aligned bounding box of the vertices that triangles use (of all vertices if none is used).
Box3 bounding_box(const TriMesh& mesh);

// The mesh of `triangles` with only the vertices they use, renumbered in their old order (what is
// left after triangles were removed or replaced).
TriMesh compact_mesh(const std::vector<Vec3>& vertices, const std::vector<Triangle>& triangles);

// Rounds every vertex coordinate to the nearest float (what formats that store floats, STL, keep).
void round_vertices_to_float(TriMesh& mesh);

}  // namespace frep
