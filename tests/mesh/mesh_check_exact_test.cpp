// The fast paths of the exact self-intersection test and of the check-then-index sequence give
// the answers of the plain ones: the predicates' exact stages on coplanar points with inexact
// differences, the wedge test of coplanar neighbours at a vertex, known coplanarity and plane
// hints, planar regions of flat-faced parts (against classifying every pair), and the weld,
// topology and hierarchy that validation hands to the distance oracle.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <random>

#include "frep/math/predicates.hpp"
#include "frep/mesh/bvh.hpp"
#include "frep/mesh/mesh_distance.hpp"
#include "frep/mesh/mesh_field.hpp"
#include "frep/mesh/topology.hpp"
#include "frep/mesh/tri_tri.hpp"
#include "frep/mesh/validate.hpp"
#include "frep/mesh/weld.hpp"
#include "mesh_test_util.hpp"

namespace frep {
namespace {

int sign(double v) { return v > 0 ? 1 : (v < 0 ? -1 : 0); }

// Points on the plane x = y are exactly coplanar whatever their coordinates; with exponents far
// apart their differences are not exact in double, which takes the exact stage's general path.
// Off the plane by one step of y, the sign is known from comparisons alone.
TEST(Predicates, ExactStagesWithInexactDifferences) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  const auto wide = [&] { return std::ldexp(u(rng), int(rng() % 120) - 60); };
  int inexact = 0;
  for (int it = 0; it < 20000; ++it) {
    const double s0 = wide(), s1 = wide(), w0 = wide(), w1 = wide();
    if (s0 == s1 || w0 == w1) continue;
    // a, b differ in s only, a, c in w only: (b - a) x (c - a) has y component -(s1 - s0)(w1 - w0).
    const Vec3 a{s0, s0, w0}, b{s1, s1, w0}, c{s0, s0, w1};
    const double x = wide(), z = wide();
    const Vec3 on{x, x, z};
    EXPECT_EQ(exact::orient3d(a, b, c, on), 0) << it;
    EXPECT_EQ(exact::orient3d(b, on, a, c), 0) << it;
    for (double dir : {1.0, -1.0}) {
      const Vec3 off{x, std::nextafter(x, dir * INFINITY), z};
      const int expected = -sign(dir) * sign(s1 - s0) * sign(w1 - w0);
      EXPECT_EQ(exact::orient3d(a, b, c, off), expected) << it;
      EXPECT_EQ(exact::orient3d(b, a, c, off), -expected) << it;  // odd permutation
      EXPECT_EQ(exact::orient3d(c, a, b, off), expected) << it;   // even permutation
    }
    // In the plane: c on the line y = x through a and b; one step off it, the side is the sign
    // of (b.x - a.x) times the step.
    EXPECT_EQ(exact::orient2d(s0, s0, s1, s1, x, x), 0) << it;
    EXPECT_EQ(exact::orient2d(s0, s0, s1, s1, x, std::nextafter(x, INFINITY)), sign(s1 - s0)) << it;
    inexact += (s1 - s0) - s1 != -s0 || (x - s0) - x != -s0;
  }
  EXPECT_GT(inexact, 1000);  // the general path did run
}

Contact classify(std::array<Vec3, 3> p, std::array<Vec3, 3> q, std::array<unsigned, 3> pi,
                 std::array<unsigned, 3> qi, bool coplanar = false) {
  return classify_triangle_pair(p.data(), pi.data(), q.data(), qi.data(), coplanar);
}

// Coplanar triangles sharing one corner: Overlap exactly when their angles at it overlap, in
// either orientation of either triangle, and never Touch.
TEST(TriTri, CoplanarNeighboursAtAVertex) {
  const Vec3 o{0, 0, 0};
  const auto at = [](double deg) {  // a point on the ray at `deg` degrees, in the plane z = x / 2
    const double r = deg * 3.14159265358979323846 / 180;
    const double x = std::round(std::cos(r) * 64) / 64, y = std::round(std::sin(r) * 64) / 64;
    return Vec3{x, y, x / 2};
  };
  struct Case {
    double p1, p2, q1, q2;
    Contact expected;
  };
  const Case cases[] = {
      {0, 60, 60, 120, Contact::None},      // fan neighbours (a shared ray, opposite sides)
      {0, 60, 90, 150, Contact::None},      // apart
      {0, 60, 30, 90, Contact::Overlap},    // q starts inside p
      {30, 90, 0, 60, Contact::Overlap},    // p starts inside q
      {0, 60, 0, 30, Contact::Overlap},     // along the same ray, same side
      {0, 90, 20, 40, Contact::Overlap},    // q inside p
      {0, 60, 180, 240, Contact::None},     // opposite
      {0, 90, 90, 180, Contact::None},      // a shared ray at a right angle
      {0, 120, 240, 360, Contact::None},    // around: q ends where p starts
      {300, 360, 330, 390, Contact::Overlap},
  };
  for (const Case& c : cases)
    for (int flips = 0; flips < 4; ++flips)
      for (bool known : {false, true}) {
        std::array<Vec3, 3> p{o, at(c.p1), at(c.p2)}, q{o, at(c.q1), at(c.q2)};
        if (flips & 1) std::swap(p[1], p[2]);
        if (flips & 2) std::swap(q[1], q[2]);
        EXPECT_EQ(classify(p, q, {0, 1, 2}, {0, 3, 4}, known), c.expected) << c.p1 << " " << c.q1 << " " << flips;
        // The shared corner anywhere in either triangle.
        const std::array<Vec3, 3> pr{p[1], p[2], p[0]}, qr{q[2], q[0], q[1]};
        EXPECT_EQ(classify(pr, qr, {1, 2, 0}, {4, 0, 3}, known), c.expected) << c.p1 << " " << c.q1 << " " << flips;
      }
}

// Known coplanarity and a hint that knows some zeros change no answer: random pairs in one
// tilted plane (exactly: dyadic combinations), sharing 0, 1 or 2 corners.
TEST(TriTri, KnownCoplanarityAndPlaneHintsKeepAnswers) {
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<int> k(-8, 8);
  int counts[4] = {0, 0, 0, 0};
  for (int it = 0; it < 40000; ++it) {
    // The origin is dyadic in half of the pairs (exact sums), decimal in the others (rounded:
    // such pairs are kept where they happen to be exactly coplanar).
    const Vec3 o = it % 2 ? Vec3{0.1 * k(rng), 0.3, -0.7} : Vec3{k(rng) / 4.0, 0.5, -0.75};
    const Vec3 e1{1, 0.5, -0.25}, e2{-0.375, 1, 0.625};
    const auto pt = [&] { return o + e1 * (k(rng) / 8.0) + e2 * (k(rng) / 8.0); };
    std::array<Vec3, 3> p{pt(), pt(), pt()}, q{pt(), pt(), pt()};
    std::array<unsigned, 3> pi{0, 1, 2}, qi{3, 4, 5};
    const int shared = it % 3;
    for (int s = 0; s < shared; ++s) q[s] = p[s], qi[s] = pi[s];
    const auto flat = [](const std::array<Vec3, 3>& t) {
      return exact::orient2d(t[0].x, t[0].y, t[1].x, t[1].y, t[2].x, t[2].y) == 0 &&
             exact::orient2d(t[0].y, t[0].z, t[1].y, t[1].z, t[2].y, t[2].z) == 0 &&
             exact::orient2d(t[0].z, t[0].x, t[1].z, t[1].x, t[2].z, t[2].x) == 0;
    };
    if (flat(p) || flat(q)) continue;
    bool coplanar = true;  // exactly, although o + ... is rounded: the planes must agree
    for (const Vec3& v : p) coplanar = coplanar && exact::orient3d(q[0], q[1], q[2], v) == 0;
    if (!coplanar) continue;
    const Contact plain = classify_triangle_pair(p.data(), pi.data(), q.data(), qi.data());
    ++counts[int(plain)];
    EXPECT_EQ(classify_triangle_pair(p.data(), pi.data(), q.data(), qi.data(), true), plain) << it;
    // A hint that knows every zero (it is asked only where the filter cannot decide).
    const std::array<Vec3, 3>* t[2] = {&p, &q};
    const PlaneHint hint{[](const void* c, int which, int corner) {
                           const auto* const* tt = static_cast<const std::array<Vec3, 3>* const*>(c);
                           const std::array<Vec3, 3>& o = *tt[1 - which];
                           return exact::orient3d(o[0], o[1], o[2], (*tt[which])[corner]) == 0;
                         },
                         t};
    EXPECT_EQ(classify_triangle_pair(p.data(), pi.data(), q.data(), qi.data(), false, &hint), plain) << it;
  }
  EXPECT_GT(counts[int(Contact::Overlap)], 1000);
  EXPECT_GT(counts[int(Contact::None)], 1000);
  EXPECT_GT(counts[int(Contact::Touch)], 100);
}

// A box whose faces are grids of coplanar triangles, sheared so that no face is axis-aligned
// (dyadic coefficients: the faces stay exactly planar).
TriMesh sheared_grid_box(int n) {
  TriMesh m = test::make_fine_box(n);
  for (Vec3& v : m.vertices) v = {v.x + v.y / 2 + v.z / 4, v.y + v.z / 2, v.z - v.x / 4 + 3};
  return m;
}

// Every pair of triangles with non-zero area (what the check tests; the meshes below have no
// duplicate or collapsed triangles), classified plainly.
std::array<std::uint64_t, 3> contacts_by_brute_force(const TriMesh& m) {
  std::array<std::uint64_t, 3> n{0, 0, 0};  // crossing, overlap, touching
  std::vector<char> flat(m.triangles.size());
  for (std::uint32_t t = 0; t < m.triangles.size(); ++t) {
    const Vec3 a = m.corner(t, 0), b = m.corner(t, 1), c = m.corner(t, 2);
    flat[t] = exact::orient2d(a.x, a.y, b.x, b.y, c.x, c.y) == 0 && exact::orient2d(a.y, a.z, b.y, b.z, c.y, c.z) == 0 &&
              exact::orient2d(a.z, a.x, b.z, b.x, c.z, c.x) == 0;
  }
  for (std::uint32_t a = 0; a < m.triangles.size(); ++a)
    for (std::uint32_t b = a + 1; b < m.triangles.size(); ++b) {
      if (flat[a] || flat[b]) continue;
      const Triangle &ta = m.triangles[a], &tb = m.triangles[b];
      const Vec3 p[3] = {m.vertices[ta[0]], m.vertices[ta[1]], m.vertices[ta[2]]};
      const Vec3 q[3] = {m.vertices[tb[0]], m.vertices[tb[1]], m.vertices[tb[2]]};
      const unsigned pi[3] = {ta[0], ta[1], ta[2]}, qi[3] = {tb[0], tb[1], tb[2]};
      const Contact c = classify_triangle_pair(p, pi, q, qi);
      if (c == Contact::Cross) ++n[0];
      if (c == Contact::Overlap) ++n[1];
      if (c == Contact::Touch) ++n[2];
    }
  return n;
}

// Planar regions let the test skip orientation signs inside flat faces: its counts must be those
// of classifying every pair plainly, for a clean part and for folds and crossings in its faces.
TEST(Validate, PlanarRegionsKeepPairCounts) {
  const int n = 8;
  const TriMesh clean = sheared_grid_box(n);
  ValidationReport r = validate_mesh(clean);
  EXPECT_TRUE(r.is_solid()) << r.to_text();
  // Fold a face: one vertex inside a face moved within the face's plane, past its neighbours.
  TriMesh folded = test::make_fine_box(n);
  std::uint32_t inner = 0;
  for (std::uint32_t v = 0; v < folded.vertices.size(); ++v) {
    const Vec3& p = folded.vertices[v];
    if (p.x == -1 && std::fabs(p.y) < 0.5 && std::fabs(p.z) < 0.5) inner = v;
  }
  folded.vertices[inner].y += 0.625;
  folded.vertices[inner].z += 0.375;
  // And a vertex pushed through the opposite face from inside (crossings, touching).
  TriMesh dented = folded;
  for (std::uint32_t v = 0; v < dented.vertices.size(); ++v) {
    const Vec3& p = dented.vertices[v];
    if (p.x == 1 && p.y == 0.25 && p.z == 0.25) dented.vertices[v].x = -1.25;
  }
  for (TriMesh* m : {&folded, &dented})
    for (Vec3& v : m->vertices) v = {v.x + v.y / 2 + v.z / 4, v.y + v.z / 2, v.z - v.x / 4 + 3};
  // (The clean part also runs on the distance oracle's hierarchy, in the file's coordinates.)
  BvhOptions bo;
  bo.max_leaf_size = MeshDistanceOptions{}.max_leaf_size;
  for (const TriMesh* m : {&clean, static_cast<const TriMesh*>(&folded), static_cast<const TriMesh*>(&dented)}) {
    const auto brute = contacts_by_brute_force(*m);
    ValidationProducts products;
    for (const ValidationReport& v : {validate_mesh(*m), validate_mesh(*m, {}, bo, products)}) {
      EXPECT_EQ(v.defect(DefectKind::SelfIntersections).count, brute[0]);
      EXPECT_EQ(v.defect(DefectKind::Overlaps).count, brute[1]);
      EXPECT_EQ(v.defect(DefectKind::TouchingPairs).count, brute[2]);
    }
  }
  EXPECT_GT(validate_mesh(folded).defect(DefectKind::Overlaps).count, 0u);
  EXPECT_GT(validate_mesh(dented).defect(DefectKind::SelfIntersections).count, 0u);
}

void expect_same_bits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)), 0);
}

// What validation hands to the distance oracle is what the oracle would build itself: the weld
// (in the file's coordinates, although the check works on a scaled copy), the topology with its
// normals, the hierarchy; and the report is the plain validation's.
TEST(Validate, ProductsAreWhatTheDistanceOracleBuilds) {
  const MeshDistanceOptions distance_options;
  BvhOptions bo;
  bo.max_leaf_size = distance_options.max_leaf_size;
  TriMesh with_zero_area = test::make_box();
  with_zero_area.vertices.push_back({5, 5, 5});
  with_zero_area.add_triangle(8, 8, 0, 12, 0);  // collapsed: no hierarchy to hand on
  const TriMesh meshes[] = {test::make_sphere(3, 1000.0), sheared_grid_box(6), test::make_sphere(2, 0.001),
                            with_zero_area};
  for (const TriMesh& m : meshes) {
    ValidationProducts products;
    const ValidationReport r = validate_mesh(m, {}, bo, products);
    EXPECT_EQ(r.to_json(), validate_mesh(m).to_json());
    const TriMesh welded = weld(m, {}).mesh;
    expect_same_bits(products.welded.vertices, welded.vertices);
    EXPECT_EQ(products.welded.triangles, welded.triangles);
    const MeshTopology topo(welded);
    ASSERT_EQ(products.topology.num_edges(), topo.num_edges());
    for (std::uint32_t e = 0; e < topo.num_edges(); ++e)
      EXPECT_EQ(products.topology.edge_vertices(e), topo.edge_vertices(e));
    expect_same_bits(products.topology.face_normals(), topo.face_normals());
    expect_same_bits(products.topology.vertex_pseudonormals(), topo.vertex_pseudonormals());
    if (&m == &meshes[3]) {
      EXPECT_FALSE(products.hierarchy.has_value());
      continue;
    }
    ASSERT_TRUE(products.hierarchy.has_value());
    const TriangleBvh bvh(welded, bo);
    EXPECT_EQ(products.hierarchy->order(), bvh.order());
    ASSERT_EQ(products.hierarchy->nodes().size(), bvh.nodes().size());
    EXPECT_EQ(std::memcmp(products.hierarchy->nodes().data(), bvh.nodes().data(),
                          bvh.nodes().size() * sizeof(TriangleBvh::Node)),
              0);
    // And so the field's distances and winding numbers, bit for bit.
    const MeshField field(m);
    const MeshDistance own(welded, topo);
    std::mt19937 rng(3);
    const Box3 box = bounding_box(m);
    std::uniform_real_distribution<double> u(-0.2, 1.2);
    for (int i = 0; i < 2000; ++i) {
      const Vec3 d = box.hi - box.lo;
      const Vec3 p{box.lo.x + u(rng) * d.x, box.lo.y + u(rng) * d.y, box.lo.z + u(rng) * d.z};
      const double a = field.signed_distance(p), b = own.signed_distance(p, field.sign());
      EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0) << i;
      const double wa = field.distance().winding_number(p), wb = own.winding_number(p);
      EXPECT_EQ(std::memcmp(&wa, &wb, sizeof wa), 0) << i;
    }
  }
}

}  // namespace
}  // namespace frep
