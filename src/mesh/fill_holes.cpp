// Hole filling on CGAL's Surface_mesh (fill_holes.hpp). Fairing solves a sparse system with
// Eigen, as CGAL_EIGEN3_ENABLED selects.
#include "mesh/fill_holes.hpp"

#define CGAL_EIGEN3_ENABLED 1
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>

#include <iterator>

namespace frep::holes {

namespace PMP = CGAL::Polygon_mesh_processing;
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<K::Point_3>;

bool fill(const TriMesh& mesh, std::size_t max_boundary, Filled& out, std::string& why) {
  try {
    std::vector<K::Point_3> points;
    points.reserve(mesh.vertices.size());
    for (const Vec3& v : mesh.vertices) points.emplace_back(v.x, v.y, v.z);
    std::vector<std::vector<std::size_t>> polygons;
    polygons.reserve(mesh.triangles.size());
    for (const Triangle& t : mesh.triangles) polygons.push_back({t[0], t[1], t[2]});
    if (!PMP::is_polygon_soup_a_polygon_mesh(polygons)) {
      why = "the surface around the holes is not manifold";
      return false;
    }
    Mesh sm;
    PMP::polygon_soup_to_polygon_mesh(points, polygons, sm);
    std::vector<Mesh::Halfedge_index> borders;
    PMP::extract_boundary_cycles(sm, std::back_inserter(borders));
    out.holes.clear();
    out.unfaired = 0;
    for (Mesh::Halfedge_index h : borders) {
      FilledHole hole;
      hole.at = {sm.point(sm.source(h)).x(), sm.point(sm.source(h)).y(), sm.point(sm.source(h)).z()};
      for (Mesh::Halfedge_index g = h;;) {
        ++hole.boundary_edges;
        g = sm.next(g);
        if (g == h) break;
      }
      if (hole.boundary_edges > max_boundary) {
        why = "a hole has " + std::to_string(hole.boundary_edges) + " boundary edges (more than " +
              std::to_string(max_boundary) + ")";
        return false;
      }
      std::vector<Mesh::Face_index> faces;
      std::vector<Mesh::Vertex_index> vertices;
      const auto result = PMP::triangulate_refine_and_fair_hole(sm, h, std::back_inserter(faces), std::back_inserter(vertices));
      if (faces.empty()) {
        why = "a hole with " + std::to_string(hole.boundary_edges) + " boundary edges could not be triangulated";
        return false;
      }
      if (!std::get<0>(result)) ++out.unfaired;
      for (Mesh::Face_index f : faces) hole.area += PMP::face_area(f, sm);
      out.holes.push_back(hole);
    }
    TriMesh filled;
    filled.name = mesh.name;
    std::vector<std::uint32_t> index(sm.number_of_vertices() + sm.number_of_removed_vertices(), 0);
    for (Mesh::Vertex_index v : sm.vertices()) {
      index[v] = static_cast<std::uint32_t>(filled.vertices.size());
      const K::Point_3& p = sm.point(v);
      filled.vertices.push_back({p.x(), p.y(), p.z()});
    }
    for (Mesh::Face_index f : sm.faces()) {
      std::array<std::uint32_t, 3> t{};
      int k = 0;
      for (Mesh::Vertex_index v : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
        if (k == 3) {
          why = "hole filling made a face that is not a triangle";
          return false;
        }
        t[k++] = index[v];
      }
      filled.triangles.push_back(t);
    }
    out.mesh = std::move(filled);
    return true;
  } catch (const std::exception& e) {  // CGAL::Failure_exception included
    why = std::string("hole filling failed (") + e.what() + ")";
    return false;
  }
}

}  // namespace frep::holes
