// An independent check of frep's meshes: CGAL's does_self_intersect (exact predicates), for tests
// that must not rely on frep's own triangle-pair predicate. Tests link CGAL's GMP and MPFR.
#pragma once

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <vector>

#include "frep/mesh/mesh.hpp"

namespace frep::test {

inline bool cgal_self_intersects(const TriMesh& tri) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Mesh = CGAL::Surface_mesh<K::Point_3>;
  Mesh m;
  std::vector<Mesh::Vertex_index> vs;
  for (const Vec3& v : tri.vertices) vs.push_back(m.add_vertex(K::Point_3(v.x, v.y, v.z)));
  for (const Triangle& t : tri.triangles) m.add_face(vs[t[0]], vs[t[1]], vs[t[2]]);
  return CGAL::Polygon_mesh_processing::does_self_intersect(m);
}

}  // namespace frep::test
