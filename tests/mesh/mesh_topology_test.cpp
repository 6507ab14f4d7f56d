// Tests of the mesh topology (mesh/topology.hpp): hand-made meshes with known answers, and a
// naive map-and-search reference compared on every small and mid-size shared mesh, plus
// properties (Euler characteristic, closed meshes, outward pseudonormals, flat vertices).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>

#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/topology.hpp"
#include "frep/mesh/weld.hpp"
#include "mesh_test_util.hpp"

namespace frep {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr std::uint32_t kNone = MeshTopology::kNone;

// The same connectivity computed the obvious way: maps, sets and breadth-first searches.
struct Naive {
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::pair<std::uint32_t, bool>>> edges;  // -> (tri, lo->hi)
  std::vector<std::set<std::uint32_t>> at;  // triangles at each vertex
  std::vector<int> fans;                    // per vertex
  std::vector<std::uint32_t> shell;         // per triangle (kNone if collapsed), dense in order of first triangle

  explicit Naive(const TriMesh& m) : at(m.vertices.size()), fans(m.vertices.size(), 0), shell(m.triangles.size(), kNone) {
    auto ok = [&](std::uint32_t t) {
      const Triangle& x = m.triangles[t];
      return x[0] != x[1] && x[1] != x[2] && x[0] != x[2];
    };
    for (std::uint32_t t = 0; t < m.triangles.size(); ++t) {
      if (!ok(t)) continue;
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t a = m.triangles[t][k], b = m.triangles[t][(k + 1) % 3];
        edges[{std::min(a, b), std::max(a, b)}].push_back({t, a < b});
        at[a].insert(t);
      }
    }
    auto key = [](std::uint32_t a, std::uint32_t b) { return std::make_pair(std::min(a, b), std::max(a, b)); };
    for (std::uint32_t v = 0; v < at.size(); ++v) {
      std::set<std::uint32_t> left = at[v];
      while (!left.empty()) {
        ++fans[v];
        std::vector<std::uint32_t> todo{*left.begin()};
        left.erase(left.begin());
        while (!todo.empty()) {
          const std::uint32_t t = todo.back();
          todo.pop_back();
          for (std::uint32_t w : m.triangles[t]) {
            if (w == v) continue;
            const auto& f = edges.at(key(v, w));
            if (f.size() != 2) continue;
            for (const auto& [g, fw] : f)
              if (left.erase(g)) todo.push_back(g);
          }
        }
      }
    }
    std::uint32_t shells = 0;
    for (std::uint32_t t0 = 0; t0 < m.triangles.size(); ++t0) {
      if (!ok(t0) || shell[t0] != kNone) continue;
      std::vector<std::uint32_t> todo{t0};
      shell[t0] = shells;
      while (!todo.empty()) {
        const std::uint32_t t = todo.back();
        todo.pop_back();
        for (int k = 0; k < 3; ++k)
          for (const auto& [g, fw] : edges.at(key(m.triangles[t][k], m.triangles[t][(k + 1) % 3])))
            if (shell[g] == kNone) shell[g] = shells, todo.push_back(g);
      }
      ++shells;
    }
  }
};

// Everything MeshTopology says about connectivity, against the naive reference.
void expect_matches_naive(const TriMesh& m, const MeshTopology& topo, const std::string& what) {
  const Naive ref(m);
  ASSERT_EQ(topo.num_edges(), ref.edges.size()) << what;
  std::uint32_t e = 0;
  for (const auto& [ab, faces] : ref.edges) {  // the map's order is the topology's edge order
    ASSERT_EQ(topo.edge_vertices(e)[0], ab.first) << what;
    ASSERT_EQ(topo.edge_vertices(e)[1], ab.second) << what;
    const auto f = topo.edge_faces(e);
    ASSERT_EQ(f.size(), faces.size()) << what;
    for (std::size_t i = 0; i < f.size(); ++i) EXPECT_EQ(f[i], faces[i].first) << what;
    EXPECT_EQ(topo.manifold(e), faces.size() == 2);
    EXPECT_EQ(topo.consistent(e), faces.size() == 2 && faces[0].second != faces[1].second) << what;
    for (const auto& [t, fw] : faces) {
      const auto& te = topo.triangle_edges(t);
      EXPECT_EQ(std::count(te.begin(), te.end(), e), 1) << what;
    }
    EXPECT_EQ(topo.find_edge(ab.second, ab.first), e);
    ++e;
  }
  std::size_t used = 0;
  for (std::uint32_t v = 0; v < m.vertices.size(); ++v) {
    const auto f = topo.vertex_faces(v);
    EXPECT_TRUE(std::equal(f.begin(), f.end(), ref.at[v].begin(), ref.at[v].end())) << what << " vertex " << v;
    EXPECT_EQ(int(topo.num_fans(v)), ref.fans[v]) << what << " vertex " << v;
    used += !f.empty();
    // Fan ids: numbered in order of first appearance, and two triangles of the same fan are
    // joined by a chain of manifold edges (checked through the naive count: as many ids as fans).
    std::uint32_t next = 0;
    for (std::uint32_t id : topo.vertex_fan_ids(v)) {
      EXPECT_LE(id, next);
      if (id == next) ++next;
    }
    EXPECT_EQ(next, topo.num_fans(v));
  }
  EXPECT_EQ(topo.num_used_vertices(), used);
  std::uint32_t shells = 0;
  for (std::uint32_t t = 0; t < m.triangles.size(); ++t) {
    EXPECT_EQ(topo.shell_of(t), ref.shell[t]) << what;
    if (ref.shell[t] != kNone) shells = std::max(shells, ref.shell[t] + 1);
    const auto& te = topo.triangle_edges(t);
    if (!topo.usable(t)) {
      EXPECT_EQ(te[0], kNone);
      continue;
    }
    for (int k = 0; k < 3; ++k) {  // edge k joins corners k and k + 1
      const std::uint32_t a = m.triangles[t][k], b = m.triangles[t][(k + 1) % 3];
      EXPECT_EQ(topo.edge_vertices(te[k])[0], std::min(a, b));
      EXPECT_EQ(topo.edge_vertices(te[k])[1], std::max(a, b));
    }
  }
  ASSERT_EQ(topo.num_shells(), shells) << what;
  for (std::uint32_t s = 0; s < shells; ++s) {
    const auto f = topo.shell_faces(s);
    ASSERT_FALSE(f.empty());
    EXPECT_TRUE(std::is_sorted(f.begin(), f.end()));
    for (std::uint32_t t : f) EXPECT_EQ(topo.shell_of(t), s);
  }
}

TriMesh tetrahedron() {
  TriMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.add_triangle(0, 2, 1), m.add_triangle(0, 1, 3), m.add_triangle(1, 2, 3), m.add_triangle(2, 0, 3);
  return m;
}

TEST(Topology, Tetrahedron) {
  const TriMesh m = tetrahedron();
  const MeshTopology topo(m);
  expect_matches_naive(m, topo, "tetrahedron");
  EXPECT_EQ(topo.num_edges(), 6u);
  EXPECT_EQ(topo.num_shells(), 1u);
  EXPECT_EQ(topo.euler_characteristic(), 2);
  const Vec3 centroid{0.25, 0.25, 0.25};
  const std::vector<EdgeShape> shapes = edge_shapes(m, topo);
  for (std::uint32_t e = 0; e < 6; ++e) {
    EXPECT_TRUE(topo.consistent(e));
    EXPECT_EQ(shapes[e], EdgeShape::Convex);
    const auto [a, b] = topo.edge_vertices(e);
    EXPECT_GT(dot(topo.edge_pseudonormal(e), (m.vertices[a] + m.vertices[b]) * 0.5 - centroid), 0);
  }
  for (std::uint32_t v = 0; v < 4; ++v) {
    EXPECT_EQ(topo.num_fans(v), 1u);
    EXPECT_EQ(topo.vertex_faces(v).size(), 3u);
    EXPECT_GT(dot(topo.vertex_pseudonormal(v), m.vertices[v] - centroid), 0);
  }
  // The right-angled corner at the origin: three right angles, normals -x, -y, -z.
  const Vec3 n0 = topo.vertex_pseudonormal(0);
  EXPECT_NEAR(n0.x, -kPi / 2, 1e-15);
  EXPECT_NEAR(n0.y, -kPi / 2, 1e-15);
  EXPECT_NEAR(n0.z, -kPi / 2, 1e-15);
  EXPECT_EQ(topo.face_normal(0), (Vec3{0, 0, -1}));
  for (std::uint32_t t = 0; t < 4; ++t) EXPECT_NEAR(length(topo.face_normal(t)), 1, 1e-15);
  EXPECT_EQ(topo.find_edge(0, 0), kNone);

  // Turned inside out: every edge concave, every pseudonormal inward.
  TriMesh inv = m;
  for (Triangle& t : inv.triangles) std::swap(t[1], t[2]);
  const MeshTopology ti(inv);
  for (EdgeShape sh : edge_shapes(inv, ti)) EXPECT_EQ(sh, EdgeShape::Concave);
  EXPECT_EQ(ti.vertex_pseudonormal(0), -n0);
}

// Two cubes sharing one edge: that edge has four faces, its ends are pinched (two fans each),
// and the cubes are one shell (joined through the edge).
TEST(Topology, TwoCubesSharingAnEdge) {
  TriMesh m = test::make_box({0, 0, 0}, {1, 1, 1});
  const TriMesh other = test::make_box({1, 1, 0}, {2, 2, 1});
  m.vertices.insert(m.vertices.end(), other.vertices.begin(), other.vertices.end());
  for (const Triangle& t : other.triangles) m.add_triangle(t[0] + 8, t[1] + 8, t[2] + 8, 0, 0);
  const WeldResult w = weld(m);
  const MeshTopology topo(w.mesh);
  expect_matches_naive(w.mesh, topo, "two cubes");
  EXPECT_EQ(w.mesh.vertices.size(), 14u);
  int four = 0, pinched = 0;
  const std::vector<EdgeShape> shapes = edge_shapes(w.mesh, topo);
  for (std::uint32_t e = 0; e < topo.num_edges(); ++e) {
    if (topo.edge_face_count(e) == 4) {
      ++four;
      EXPECT_EQ(shapes[e], EdgeShape::NonManifold);
      EXPECT_FALSE(topo.consistent(e));
    } else {
      EXPECT_TRUE(topo.consistent(e));
    }
  }
  for (std::uint32_t v = 0; v < topo.num_vertices(); ++v)
    if (topo.pinched(v)) {
      ++pinched;
      EXPECT_EQ(topo.num_fans(v), 2u);
      const Vec3 p = w.mesh.vertices[v];
      EXPECT_TRUE(p.x == 1 && p.y == 1) << p.x << " " << p.y << " " << p.z;
    }
  EXPECT_EQ(four, 1);
  EXPECT_EQ(pinched, 2);
  EXPECT_EQ(topo.num_shells(), 1u);
  EXPECT_EQ(topo.num_edges(), 35u);  // 2 x 18 - 1
}

// Two cones joined at their apex only: the apex has two fans, every edge is manifold, and the
// cones are two shells (shells join through edges, not vertices).
TEST(Topology, PinchedDoubleCone) {
  TriMesh m;
  const int n = 7;
  m.vertices.push_back({0, 0, 0});  // the shared apex
  for (int side = 0; side < 2; ++side) {
    const double z = side ? -1 : 1;
    const auto base = std::uint32_t(m.vertices.size());
    for (int i = 0; i < n; ++i) m.vertices.push_back({std::cos(2 * kPi * i / n), std::sin(2 * kPi * i / n), z});
    m.vertices.push_back({0, 0, z});  // center of the cap
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t a = base + i, b = base + (i + 1) % n, c = base + n;
      if (side == 0) m.add_triangle(0, b, a), m.add_triangle(c, a, b);
      else m.add_triangle(0, a, b), m.add_triangle(c, b, a);
    }
  }
  const MeshTopology topo(m);
  expect_matches_naive(m, topo, "double cone");
  EXPECT_EQ(topo.num_fans(0), 2u);
  for (std::uint32_t v = 1; v < m.vertices.size(); ++v) EXPECT_EQ(topo.num_fans(v), 1u);
  for (std::uint32_t e = 0; e < topo.num_edges(); ++e) EXPECT_TRUE(topo.consistent(e));
  EXPECT_EQ(topo.num_shells(), 2u);
  // The apex's fans are the two cones, in order of their first triangles.
  const auto faces = topo.vertex_faces(0);
  const auto fans = topo.vertex_fan_ids(0);
  for (std::size_t i = 0; i < faces.size(); ++i) EXPECT_EQ(fans[i], topo.shell_of(faces[i]));
  // Glued apex: 2 + 2 - 1 vertices less than two separate cones, so chi = 2 + 2 - 1.
  EXPECT_EQ(topo.euler_characteristic(), 3);
}

// An open strip of quads: boundary edges have one face, inner ones two (flat: coplanar), every
// vertex one fan, and it is a disc (chi = 1).
TEST(Topology, OpenStrip) {
  TriMesh m;
  const std::uint32_t n = 10;
  for (std::uint32_t i = 0; i <= n; ++i) m.vertices.push_back({double(i), 0, 0}), m.vertices.push_back({double(i), 1, 0});
  for (std::uint32_t i = 0; i < n; ++i) {
    m.add_triangle(2 * i, 2 * i + 2, 2 * i + 3);
    m.add_triangle(2 * i, 2 * i + 3, 2 * i + 1);
  }
  const MeshTopology topo(m);
  expect_matches_naive(m, topo, "strip");
  int boundary = 0;
  const std::vector<EdgeShape> shapes = edge_shapes(m, topo);
  for (std::uint32_t e = 0; e < topo.num_edges(); ++e) {
    if (topo.edge_face_count(e) == 1) {
      ++boundary;
      EXPECT_EQ(shapes[e], EdgeShape::Boundary);
      EXPECT_FALSE(topo.manifold(e));
    } else {
      EXPECT_EQ(shapes[e], EdgeShape::Flat);
    }
  }
  EXPECT_EQ(boundary, int(2 * n + 2));
  for (std::uint32_t v = 0; v < m.vertices.size(); ++v) EXPECT_EQ(topo.num_fans(v), 1u);
  EXPECT_EQ(topo.euler_characteristic(), 1);
  // Flat: every pseudonormal is +z; at an inner boundary vertex the angles sum to pi.
  for (std::uint32_t v = 0; v < m.vertices.size(); ++v) {
    const Vec3 nv = topo.vertex_pseudonormal(v);
    EXPECT_EQ(nv.x, 0);
    EXPECT_EQ(nv.y, 0);
    EXPECT_GT(nv.z, 0);
  }
  EXPECT_NEAR(topo.vertex_pseudonormal(4).z, kPi, 1e-14);
}

// Edge shapes are exact: coplanar faces whose coordinates do not cancel in floating point are
// still flat, a fold is told from a flat continuation, and a sliver neighbour is degenerate.
TEST(Topology, EdgeShapesAreExact) {
  // Points of the plane x = y (as in the predicate test) whose coordinates are not on a grid.
  const Vec3 a{0.1, 0.1, 0.3}, b{0.2, 0.2, 0.7}, c{0.3, 0.3, 0.9}, d{0.7, 0.7, 0.1};
  auto pair = [](Vec3 p, Vec3 q, Vec3 r, Vec3 s) {  // triangles (p, q, r) and (q, p, s) share p-q
    TriMesh m;
    m.vertices = {p, q, r, s};
    m.add_triangle(0, 1, 2), m.add_triangle(1, 0, 3);
    return m;
  };
  auto shape = [](const TriMesh& m) {
    const MeshTopology topo(m);
    return edge_shapes(m, topo)[topo.find_edge(0, 1)];
  };
  // In the plane's (x, z) coordinates b and e lie to the left of a -> c, d to the right.
  const Vec3 e{0.25, 0.25, 0.85};
  EXPECT_EQ(shape(pair(a, c, b, d)), EdgeShape::Flat);
  EXPECT_EQ(shape(pair(a, c, b, e)), EdgeShape::Folded);
  // Off the plane by the smallest step in y: no longer coplanar.
  const Vec3 d_up{0.7, std::nextafter(0.7, 1.0), 0.1}, d_down{0.7, std::nextafter(0.7, 0.0), 0.1};
  const EdgeShape up = shape(pair(a, c, b, d_up)), down = shape(pair(a, c, b, d_down));
  EXPECT_TRUE((up == EdgeShape::Convex && down == EdgeShape::Concave) || (up == EdgeShape::Concave && down == EdgeShape::Convex));
  // Simple cases on the grid.
  EXPECT_EQ(shape(pair({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0})), EdgeShape::Flat);
  EXPECT_EQ(shape(pair({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, 2, 0})), EdgeShape::Folded);
  EXPECT_EQ(shape(pair({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, -1})), EdgeShape::Convex);  // normal +z, d below
  EXPECT_EQ(shape(pair({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 1})), EdgeShape::Concave);
  EXPECT_EQ(shape(pair({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0})), EdgeShape::Degenerate);  // d on the edge's line
  EXPECT_EQ(shape(pair({0, 0, 0}, {1, 0, 0}, {3, 0, 0}, {0, 1, 0})), EdgeShape::Degenerate);  // first face collinear
  TriMesh same = pair({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0});
  std::swap(same.triangles[1][0], same.triangles[1][1]);  // both traverse 0 -> 1
  EXPECT_EQ(shape(same), EdgeShape::Inconsistent);
}

// A collapsed triangle (repeated index) takes no part: no edges, no shell, in no vertex list.
TEST(Topology, CollapsedTrianglesTakeNoPart) {
  TriMesh m = tetrahedron();
  m.add_triangle(0, 0, 1);
  m.add_triangle(3, 2, 3);
  const MeshTopology topo(m);
  expect_matches_naive(m, topo, "tetrahedron with collapsed triangles");
  EXPECT_EQ(topo.num_usable_triangles(), 4u);
  EXPECT_EQ(topo.num_edges(), 6u);
  for (std::uint32_t t : {4u, 5u}) {
    EXPECT_FALSE(topo.usable(t));
    EXPECT_EQ(topo.shell_of(t), kNone);
    EXPECT_EQ(topo.face_normal(t), Vec3{});
  }
  EXPECT_EQ(topo.euler_characteristic(), 2);
}

// The welded shared meshes, by name (skipping the big ones to keep the test fast).
std::vector<std::pair<std::string, TriMesh>> shared_meshes(std::size_t max_triangles) {
  std::vector<std::pair<std::string, TriMesh>> out;
  std::ifstream in(test::shared_mesh_dir() + "/MANIFEST.tsv");
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string name, source, license, format, triangles;
    std::getline(ss, name, '\t'), std::getline(ss, source, '\t'), std::getline(ss, license, '\t');
    std::getline(ss, format, '\t'), std::getline(ss, triangles, '\t');
    if (std::stoul(triangles) > max_triangles) continue;
    out.push_back({name, weld(read_mesh(test::shared_mesh_dir() + "/" + name)).mesh});
  }
  return out;
}

TEST(Topology, MatchesNaiveReferenceOnSharedMeshes) {
  FREP_REQUIRE_SHARED_MESHES();
  int checked = 0;
  for (const auto& [name, m] : shared_meshes(25000)) {
    expect_matches_naive(m, MeshTopology(m), name);
    ++checked;
  }
  EXPECT_GE(checked, 25);
}

// Closed shared meshes: every edge has two consistently oriented faces, every vertex one fan,
// and V - E + F = 2 (shells - genus) with the genus the manifest states.
TEST(Topology, ClosedSharedMeshes) {
  FREP_REQUIRE_SHARED_MESHES();
  const std::map<std::string, int> genus = {{"cube_unit_bin.stl", 0}, {"sphere_icosa_1280.stl", 0},
                                            {"spot.obj", 0},          {"plate_holes.stl", 5},
                                            {"tray_bottom_ascii.stl", 23}, {"menger_sponge_l3.obj", 1409}};
  for (const auto& [name, g] : genus) {
    const TriMesh m = weld(read_mesh(test::shared_mesh_dir() + "/" + name)).mesh;
    const MeshTopology topo(m);
    EXPECT_EQ(topo.num_shells(), 1u) << name;
    EXPECT_EQ(topo.euler_characteristic(), 2 - 2 * g) << name;
    EXPECT_EQ(2 * topo.num_edges(), 3 * topo.num_usable_triangles()) << name;
    for (std::uint32_t e = 0; e < topo.num_edges(); ++e) ASSERT_TRUE(topo.consistent(e)) << name << " edge " << e;
    for (std::uint32_t v = 0; v < topo.num_vertices(); ++v) ASSERT_EQ(topo.num_fans(v), 1u) << name << " vertex " << v;
    // The menger sponge is a union of cubes: its edges are flat, convex or concave, never folded.
    if (name == "menger_sponge_l3.obj") {
      int count[8] = {};
      for (EdgeShape sh : edge_shapes(m, topo)) ++count[int(sh)];
      EXPECT_GT(count[int(EdgeShape::Flat)], 0);
      EXPECT_GT(count[int(EdgeShape::Convex)], 0);
      EXPECT_GT(count[int(EdgeShape::Concave)], 0);
      EXPECT_EQ(count[int(EdgeShape::Folded)] + count[int(EdgeShape::Degenerate)], 0);
    }
  }
}

// On a sphere every normal points away from the center: face normals, edge and vertex
// pseudonormals; a convex polyhedron has only convex edges.
TEST(Topology, SpherePseudonormalsPointOutward) {
  std::vector<std::pair<std::string, TriMesh>> spheres = {{"make_sphere(3)", test::make_sphere(3)}};
  if (test::have_shared_meshes())
    spheres.push_back({"sphere_icosa_1280.stl", weld(read_mesh(test::shared_mesh_dir() + "/sphere_icosa_1280.stl")).mesh});
  for (const auto& [name, m] : spheres) {
    const MeshTopology topo(m);
    auto cosine = [](Vec3 a, Vec3 b) { return dot(a, b) / (length(a) * length(b)); };
    for (std::uint32_t t = 0; t < m.triangles.size(); ++t)
      EXPECT_GT(cosine(topo.face_normal(t), m.corner(t, 0) + m.corner(t, 1) + m.corner(t, 2)), 0.98) << name;
    const std::vector<EdgeShape> shapes = edge_shapes(m, topo);
    for (std::uint32_t e = 0; e < topo.num_edges(); ++e) {
      const auto [a, b] = topo.edge_vertices(e);
      EXPECT_GT(cosine(topo.edge_pseudonormal(e), m.vertices[a] + m.vertices[b]), 0.98) << name;
      EXPECT_EQ(shapes[e], EdgeShape::Convex) << name;
    }
    for (std::uint32_t v = 0; v < topo.num_vertices(); ++v)
      EXPECT_GT(cosine(topo.vertex_pseudonormal(v), m.vertices[v]), 0.99) << name;
  }
}

// At a flat interior vertex the corner angles sum to 2 pi, so the pseudonormal is 2 pi times
// the common face normal. Found on a subdivided box and on flat-faced CAD parts.
TEST(Topology, FlatVerticesWeighTwoPi) {
  std::vector<std::pair<std::string, TriMesh>> meshes = {{"make_fine_box(4)", test::make_fine_box(4)}};
  if (test::have_shared_meshes())
    for (const char* f : {"tray_bottom_ascii.stl", "fandisk.obj"})
      meshes.push_back({f, weld(read_mesh(test::shared_mesh_dir() + "/" + f)).mesh});
  for (const auto& [name, m] : meshes) {
    const MeshTopology topo(m);
    int flat = 0;
    for (std::uint32_t v = 0; v < topo.num_vertices(); ++v) {
      const auto faces = topo.vertex_faces(v);
      if (faces.empty()) continue;
      const Vec3 n = topo.face_normal(faces[0]);
      bool same = true;
      for (std::uint32_t t : faces) same = same && length(topo.face_normal(t) - n) < 1e-12;
      if (!same) continue;
      ++flat;
      double sum = 0;
      for (std::uint32_t t : faces) {
        const int k = m.triangles[t][0] == v ? 0 : (m.triangles[t][1] == v ? 1 : 2);
        sum += corner_angle(m.corner(t, k), m.corner(t, (k + 1) % 3), m.corner(t, (k + 2) % 3));
      }
      EXPECT_NEAR(sum, 2 * kPi, 1e-9) << name << " vertex " << v;
      EXPECT_NEAR(length(topo.vertex_pseudonormal(v) - n * (2 * kPi)), 0, 1e-9) << name << " vertex " << v;
    }
    EXPECT_GT(flat, 10) << name;
  }
}

// The solid angle against L'Huilier's theorem (spherical excess from the three arc lengths),
// an independent formula; the sign is the side of the plane.
TEST(Topology, SolidAngleMatchesLhuilier) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p{u(rng), u(rng), u(rng)}, a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)}, c{u(rng), u(rng), u(rng)};
    auto arc = [&](Vec3 x, Vec3 y) {
      x = x - p, y = y - p;
      return std::atan2(length(cross(x, y)), dot(x, y));
    };
    const double ta = arc(b, c), tb = arc(c, a), tc = arc(a, b), s = (ta + tb + tc) / 2;
    const double excess = 4 * std::atan(std::sqrt(std::max(
                                  0.0, std::tan(s / 2) * std::tan((s - ta) / 2) * std::tan((s - tb) / 2) * std::tan((s - tc) / 2))));
    const double side = dot(a - p, cross(b - p, c - p));  // > 0: p behind the right-hand normal
    const double omega = solid_angle(p, a, b, c);
    EXPECT_NEAR(std::fabs(omega), excess, 1e-9 * (1 + excess)) << i;
    if (std::fabs(omega) > 1e-9) {
      EXPECT_EQ(omega > 0, side > 0) << i;
    }
    // The three corner angles of a triangle sum to pi.
    EXPECT_NEAR(corner_angle(a, b, c) + corner_angle(b, c, a) + corner_angle(c, a, b), kPi, 1e-12);
  }
  // Summed over a closed outward surface: 4 pi inside, 0 outside; inside out: -4 pi.
  const TriMesh s = test::make_sphere(2);
  auto total = [&](const TriMesh& m, Vec3 p) {
    double sum = 0;
    for (std::size_t t = 0; t < m.num_triangles(); ++t) sum += solid_angle(p, m.corner(t, 0), m.corner(t, 1), m.corner(t, 2));
    return sum;
  };
  TriMesh inv = s;
  for (Triangle& t : inv.triangles) std::swap(t[1], t[2]);
  for (const Vec3 p : {Vec3{0, 0, 0}, Vec3{0.3, -0.5, 0.2}, Vec3{0.9, 0, 0}}) {
    EXPECT_NEAR(total(s, p), 4 * kPi, 1e-10);
    EXPECT_NEAR(total(inv, p), -4 * kPi, 1e-10);
  }
  for (const Vec3 p : {Vec3{2, 0, 0}, Vec3{1.1, 0.1, 0}, Vec3{-5, 7, 1}}) EXPECT_NEAR(total(s, p), 0, 1e-10);
}

}  // namespace
}  // namespace frep
