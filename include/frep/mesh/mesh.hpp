// The triangle mesh value type every mesh reader produces and every mesh algorithm consumes.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "frep/mesh/vec3.hpp"

namespace frep {

using Triangle = std::array<std::uint32_t, 3>;

// An indexed triangle mesh. Readers fill `face_source` so that a triangle can be traced back to
// the file: polygons are fan-triangulated, so several triangles may share one source face.
struct TriMesh {
  std::vector<Vec3> vertices;
  std::vector<Triangle> triangles;
  // Per triangle: the 0-based index of the face (facet, polygon, strip) it came from in the file.
  std::vector<std::uint32_t> face_source;
  // Per triangle: the 1-based line of that face in text formats, 0 for binary formats.
  std::vector<std::uint32_t> face_line;
  // True when the file format shares vertices between faces (OBJ, PLY, OFF); false for STL,
  // which repeats the coordinates of every corner.
  bool indexed = true;
  // Name of the file it was read from, for messages (may be empty).
  std::string name;

  std::size_t num_vertices() const { return vertices.size(); }
  std::size_t num_triangles() const { return triangles.size(); }
  Vec3 corner(std::size_t t, int k) const { return vertices[triangles[t][k]]; }
  // Adds a triangle with its provenance.
  void add_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t face,
                    std::uint32_t line) {
    triangles.push_back({a, b, c});
    face_source.push_back(face);
    face_line.push_back(line);
  }
};

// Axis-aligned bounding box of the used vertices (of all vertices if none is used).
struct Box3 {
  Vec3 lo{1e308, 1e308, 1e308}, hi{-1e308, -1e308, -1e308};
  void add(Vec3 p) { lo = min(lo, p); hi = max(hi, p); }
  bool empty() const { return lo.x > hi.x; }
  Vec3 center() const { return (lo + hi) * 0.5; }
  Vec3 size() const { return hi - lo; }
};
Box3 bounding_box(const TriMesh& mesh);

}  // namespace frep
