#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <random>
#include <utility>

#include "frep/error.hpp"
#include "frep/mesh/mesh_distance.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "mesh_test_util.hpp"

namespace frep {
namespace {

// Brute-force distance: closest point on every triangle, via barycentric projection and edges.
double brute_distance(const TriMesh& m, const Vec3& p) {
  double best = INFINITY;
  auto seg = [&](Vec3 a, Vec3 b) {
    const Vec3 ab = b - a;
    double t = dot(ab, ab) > 0 ? dot(p - a, ab) / dot(ab, ab) : 0;  // a point: its distance
    t = std::clamp(t, 0.0, 1.0);
    return length(p - (a + ab * t));
  };
  for (std::size_t t = 0; t < m.num_triangles(); ++t) {
    const Vec3 a = m.corner(t, 0), b = m.corner(t, 1), c = m.corner(t, 2);
    const Vec3 n = cross(b - a, c - a);
    const Vec3 q = p - n * (dot(p - a, n) / dot(n, n));
    const bool inside = dot(cross(b - a, q - a), n) >= 0 && dot(cross(c - b, q - b), n) >= 0 &&
                        dot(cross(a - c, q - c), n) >= 0;
    if (inside) best = std::min(best, length(p - q));
    best = std::min({best, seg(a, b), seg(b, c), seg(c, a)});
  }
  return best;
}

// Brute-force winding number: every triangle's solid angle (Van Oosterom and Strackee).
double brute_winding(const TriMesh& m, const Vec3& p) {
  double sum = 0;
  for (std::size_t t = 0; t < m.num_triangles(); ++t) {
    const Vec3 a = m.corner(t, 0) - p, b = m.corner(t, 1) - p, c = m.corner(t, 2) - p;
    const double la = length(a), lb = length(b), lc = length(c);
    sum += 2 * std::atan2(dot(a, cross(b, c)), la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb);
  }
  return sum / (4 * 3.14159265358979323846);
}

double box_sdf(const Vec3& p, const Vec3& half) {
  const Vec3 q{std::fabs(p.x) - half.x, std::fabs(p.y) - half.y, std::fabs(p.z) - half.z};
  const Vec3 o{std::max(q.x, 0.0), std::max(q.y, 0.0), std::max(q.z, 0.0)};
  return length(o) + std::min(std::max({q.x, q.y, q.z}), 0.0);
}

TEST(MeshDistance, MatchesBruteForceOnSmallMeshes) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2, 2);
  for (const TriMesh& m : {test::make_box(), test::make_sphere(1), test::make_fine_box(2, {-1, -0.5, 0}, {1, 0.5, 0.25})}) {
    const MeshDistance md(m);
    for (int i = 0; i < 2000; ++i) {
      const Vec3 p{u(rng), u(rng), u(rng)};
      const ClosestPoint c = md.closest_point(p);
      EXPECT_NEAR(c.distance, brute_distance(m, p), 1e-12);
      EXPECT_NEAR(length(c.point - p), c.distance, 1e-12);
    }
  }
}

// Triangles with two or three corners at one point (a capsule's poles, shared mesh
// capsule_collapsed_poles.obj) or collinear corners: finite distances equal to brute force. Near
// such a pole the closest-point region test used to divide 0 by 0 and answer NaN.
TEST(MeshDistance, DegenerateTrianglesGiveFiniteDistances) {
  std::vector<TriMesh> meshes(3);
  meshes[0].vertices = {{0, 0, 0}, {0, 0, 0}, {1, 0, 0}};  // two corners at one point (distinct indices)
  meshes[1].vertices = {{0, 0, 0}, {2, 0, 0}, {1, 0, 0}};  // collinear
  meshes[2].vertices = {{0.5, 0.5, 0.5}, {0.5, 0.5, 0.5}, {0.5, 0.5, 0.5}};  // a point
  for (TriMesh& m : meshes) m.add_triangle(0, 1, 2);
  meshes[0].add_triangle(2, 0, 1), meshes[0].add_triangle(1, 2, 0);  // every corner order
  std::vector<std::pair<TriMesh, std::vector<Vec3>>> cases;
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-2, 2);
  for (const TriMesh& m : meshes) {
    std::vector<Vec3> pts;
    for (int i = 0; i < 300; ++i) pts.push_back({u(rng), u(rng), u(rng)});
    cases.push_back({m, pts});
  }
  if (test::have_shared_meshes()) {
    const TriMesh capsule = read_mesh(test::shared_mesh_dir() + "/capsule_collapsed_poles.obj");
    std::vector<Vec3> pts;
    for (int i = 0; i < 300; ++i) pts.push_back(Vec3{0, 0, i % 2 ? 1.5 : -1.5} + Vec3{u(rng), u(rng), u(rng)} * 0.05);
    cases.push_back({capsule, pts});
  }
  for (const auto& [m, pts] : cases) {
    const MeshDistance md(m);
    for (const Vec3& p : pts) {
      const ClosestPoint c = md.closest_point(p);
      ASSERT_TRUE(std::isfinite(c.distance)) << p.x << " " << p.y << " " << p.z;
      EXPECT_NEAR(c.distance, brute_distance(m, p), 1e-12);
      EXPECT_NEAR(length(c.point - p), c.distance, 1e-12);
      EXPECT_TRUE(std::isfinite(md.signed_distance(p, SignMethod::Pseudonormal)));
    }
  }
}

// Queries beyond kMaxQueryCoordinate, infinite or NaN: NaN, promptly (an infinite point used to
// keep the search running forever).
TEST(MeshDistance, QueriesOutOfRangeAreNaN) {
  const MeshDistance md(test::make_box());
  for (const Vec3& p : {Vec3{1e155, 0, 0}, Vec3{0, -INFINITY, 0}, Vec3{0, 0, NAN}, Vec3{INFINITY, INFINITY, 1}}) {
    EXPECT_TRUE(std::isnan(md.unsigned_distance(p)));
    EXPECT_TRUE(std::isnan(md.signed_distance(p, SignMethod::Pseudonormal)));
    EXPECT_TRUE(std::isnan(md.signed_distance(p, SignMethod::WindingNumber)));
  }
  EXPECT_NEAR(md.signed_distance({1e149, 0, 0}, SignMethod::Pseudonormal), 1e149, 1e135);
}

TEST(MeshDistance, AnalyticBox) {
  const Vec3 half{1.5, 0.5, 1};
  const TriMesh box = test::make_fine_box(4, -half, half);
  const MeshDistance md(box);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-3, 3);
  for (int i = 0; i < 5000; ++i) {
    // Half the points near the surface, where the sign matters most.
    Vec3 p{u(rng), u(rng), u(rng)};
    if (i % 2) p = p * (0.5 / std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)})) + Vec3{1e-3 * u(rng), 0, 0};
    const double expect = box_sdf(p, half);
    EXPECT_NEAR(md.signed_distance(p, SignMethod::WindingNumber), expect, 1e-12) << p.x << " " << p.y << " " << p.z;
    EXPECT_NEAR(md.signed_distance(p, SignMethod::Pseudonormal), expect, 1e-12);
  }
  // On the surface: exactly zero; a box corner region uses the vertex pseudonormal.
  EXPECT_EQ(md.signed_distance({1.5, 0, 0}), 0.0);
  EXPECT_NEAR(md.signed_distance({1.6, 0.6, 1.1}, SignMethod::Pseudonormal), std::sqrt(0.03), 1e-12);
  EXPECT_NEAR(md.signed_distance({1.4, 0.45, 0.95}, SignMethod::Pseudonormal), -0.05, 1e-12);
}

TEST(MeshDistance, AnalyticSphere) {
  const double r = 2;
  const TriMesh s = test::make_sphere(3, r);  // 1280 triangles
  // The polyhedron lies between the sphere and the sphere shrunk by the largest sagitta.
  double inradius = INFINITY;
  for (std::size_t t = 0; t < s.num_triangles(); ++t) {
    const Vec3 n = cross(s.corner(t, 1) - s.corner(t, 0), s.corner(t, 2) - s.corner(t, 0));
    inradius = std::min(inradius, std::fabs(dot(s.corner(t, 0), n / length(n))));
  }
  const double sag = r - inradius;
  const MeshDistance md(s);
  std::mt19937 rng(11);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(0, 4);
  for (int i = 0; i < 3000; ++i) {
    Vec3 dir{g(rng), g(rng), g(rng)};
    dir = dir / length(dir);
    const Vec3 p = dir * u(rng);
    const double d = md.signed_distance(p);
    EXPECT_LE(d, length(p) - r + sag + 1e-12);
    EXPECT_GE(d, length(p) - r - 1e-12);
    EXPECT_EQ(d < 0, md.signed_distance(p, SignMethod::Pseudonormal) < 0);
  }
}

// The two sign methods agree on clean solids, including real ones, and the hierarchical winding
// number stays within a small error of the exact one.
TEST(MeshDistance, WindingAndPseudonormalAgreeOnCleanSolids) {
  std::vector<TriMesh> meshes = {test::make_sphere(2), test::make_fine_box(3)};
  if (test::have_shared_meshes()) {
    for (const char* f : {"spot.obj", "fandisk.obj", "bunny_closed_libigl.off", "cube_unit_bin.stl"})
      meshes.push_back(read_mesh(test::shared_mesh_dir() + "/" + f));
  }
  for (const TriMesh& m : meshes) {
    const MeshDistance md(m);
    const Box3 b = bounding_box(m);
    const double diag = length(b.size());
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(0, 1);
    int inside = 0;
    for (int i = 0; i < 2000; ++i) {
      const Vec3 sz = b.size();
      Vec3 p = b.lo - sz * 0.1 + Vec3{u(rng) * sz.x, u(rng) * sz.y, u(rng) * sz.z} * 1.2;
      if (i % 2) {  // pull half the points close to the surface
        const ClosestPoint c = md.closest_point(p);
        p = c.point + (p - c.point) * (1e-4 * diag / std::max(c.distance, 1e-300));
      }
      const double w = md.winding_number(p);
      const int pn = md.pseudonormal_sign(p, md.closest_point(p));
      if (pn == 0) continue;
      EXPECT_EQ(w > 0.5, pn < 0) << m.name << " point " << i << " w=" << w;
      EXPECT_LT(std::fabs(w - std::round(w)), 0.1) << m.name << " w=" << w;
      if (i < 200) {
        EXPECT_NEAR(w, md.winding_number_exact(p), 0.05);
      }
      inside += w > 0.5;
    }
    EXPECT_GT(inside, 100) << m.name;
  }
}

TEST(MeshDistance, WindingNumberIsRobustToAHole) {
  TriMesh open = test::make_sphere(3);
  open.triangles.resize(open.triangles.size() - 3);  // a small hole
  open.origins.resize(open.triangles.size());
  const MeshDistance md(open);
  EXPECT_LT(md.signed_distance({0, 0, 0}), -0.9);
  EXPECT_LT(md.signed_distance({0.3, -0.2, 0.1}), 0);
  EXPECT_GT(md.signed_distance({1.5, 0, 0}), 0.4);
  TriMesh empty;
  EXPECT_THROW(MeshDistance{empty}, InputError);
}

TEST(MeshDistance, BatchIsIndependentOfThreads) {
  const TriMesh s = test::make_sphere(3);
  const MeshDistance md(s);
  std::vector<double> x, y, z;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int i = 0; i < 5000; ++i) x.push_back(u(rng)), y.push_back(u(rng)), z.push_back(u(rng));
  std::vector<double> a(x.size()), b(x.size());
  md.signed_distance(x.data(), y.data(), z.data(), a.data(), x.size(), SignMethod::WindingNumber, 1);
  md.signed_distance(x.data(), y.data(), z.data(), b.data(), x.size(), SignMethod::WindingNumber, 3);
  EXPECT_EQ(a, b);
  EXPECT_EQ(signed_distance(s, x, y, z), a);
}

// A real mesh (7k triangles, 1600 points) against brute force: every triangle in double
// precision with this file's own closest-point code, and the sign from this file's own exact
// winding number (every triangle's solid angle). Uniform points in the box, and points truly
// near the surface: on faces, edges and vertices, exactly (distance only: no side) or offset by
// 1e-3 down to 1e-12 of the diagonal.
TEST(MeshDistance, MatchesBruteForceOnARealMesh) {
  FREP_REQUIRE_SHARED_MESHES();
  const TriMesh m = read_mesh(test::shared_mesh_dir() + "/bunny_closed_libigl.off");
  const MeshDistance md(m);
  const Box3 box = bounding_box(m);
  const double diag = length(box.size());
  auto winding = [&](const Vec3& p) { return brute_winding(m, p); };
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g;
  std::uniform_int_distribution<std::size_t> pick(0, m.num_triangles() - 1);
  const double offsets[] = {0, 1e-12, -1e-12, 1e-9, -1e-9, 1e-6, -1e-6, 1e-3, -1e-3};
  int signed_checked = 0, inside = 0;
  for (int i = 0; i < 1600; ++i) {
    Vec3 p;
    const std::size_t t = pick(rng);
    const Vec3 a = m.corner(t, 0), b = m.corner(t, 1), c = m.corner(t, 2);
    const double off = offsets[i % 9] * diag;
    Vec3 dir{g(rng), g(rng), g(rng)};
    dir = dir / length(dir);
    switch (i % 4) {
      case 0:  // uniform in the box, a little beyond it
        p = box.lo - box.size() * 0.1 + Vec3{u(rng) * box.size().x, u(rng) * box.size().y, u(rng) * box.size().z} * 1.2;
        break;
      case 1: {  // on a face, offset along its normal
        double s = u(rng), r = u(rng);
        if (s + r > 1) s = 1 - s, r = 1 - r;
        const Vec3 n = cross(b - a, c - a);
        p = a + (b - a) * s + (c - a) * r + n * (off / length(n));
        break;
      }
      case 2:  // on an edge, offset in a random direction
        p = a + (b - a) * u(rng) + dir * off;
        break;
      default:  // on a vertex, offset in a random direction
        p = a + dir * off;
    }
    const double expect = brute_distance(m, p);
    const ClosestPoint cp = md.closest_point(p);
    ASSERT_NEAR(cp.distance, expect, 1e-13 * diag) << "point " << i;
    EXPECT_NEAR(length(cp.point - p), cp.distance, 1e-13 * diag) << "point " << i;
    const double w = md.winding_number(p), sw = md.signed_distance(p), sp = md.signed_distance(p, SignMethod::Pseudonormal);
    EXPECT_EQ(std::fabs(sw), cp.distance);
    EXPECT_EQ(std::fabs(sp), cp.distance);
    if (off == 0 && i % 4 != 0) continue;  // on the surface (up to rounding): no side
    const double ref = winding(p);
    EXPECT_LT(std::fabs(ref - std::round(ref)), 1e-3) << "point " << i;  // closed: 0 or 1 off the surface
    EXPECT_NEAR(w, ref, 0.1) << "point " << i;  // the far field is approximated
    const bool in = ref > 0.5;
    EXPECT_EQ(sw < 0, in) << "winding sign, point " << i << " offset " << off;
    EXPECT_EQ(sp < 0, in) << "pseudonormal sign, point " << i << " offset " << off;
    ++signed_checked;
    inside += in;
  }
  EXPECT_GT(signed_checked, 1400);
  EXPECT_GT(inside, 300);

}

// The hard case of the pseudonormal sign: points whose closest feature is a vertex where the
// normals of its faces disagree about the side. Just outside the tip of a needle-sharp pyramid,
// in the tip's normal cone, every point is nearest to the tip and lies behind the opposite face's
// plane: only the angle-weighted sum of the normals tells the side (checked against the
// brute-force winding number).
TEST(MeshDistance, PseudonormalSignAtASharpTip) {
  TriMesh m;
  m.vertices = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, {0, 0, 10}};
  m.add_triangle(0, 1, 4), m.add_triangle(1, 2, 4), m.add_triangle(2, 3, 4), m.add_triangle(3, 0, 4);
  m.add_triangle(0, 2, 1), m.add_triangle(0, 3, 2);
  const MeshDistance md(m);
  Vec3 n[4];
  for (int f = 0; f < 4; ++f) {
    const Vec3 c = cross(m.corner(f, 1) - m.corner(f, 0), m.corner(f, 2) - m.corner(f, 0));
    n[f] = c / length(c);
  }
  int hard = 0;
  for (int f = 0; f < 4; ++f)
    for (double w : {0.0, 0.1, 0.3, 0.5}) {
      // Inside the cone of the tip's normals (not on its boundary, where an edge is as near).
      const Vec3 d = n[f] * (1 - w) + n[(f + 1) % 4] * w + (n[(f + 2) % 4] + n[(f + 3) % 4]) * 0.05;
      const Vec3 p = m.vertices[4] + d * (1e-3 / length(d));
      const ClosestPoint cp = md.closest_point(p);
      EXPECT_EQ(cp.point, m.vertices[4]);
      EXPECT_GE(cp.feature, Feature::Vertex0);
      hard += dot(d, n[(f + 2) % 4]) < 0;  // behind the opposite face's plane
      EXPECT_LT(brute_winding(m, p), 0.5);
      EXPECT_GT(md.signed_distance(p, SignMethod::Pseudonormal), 0) << f << " " << w;
      EXPECT_GT(md.signed_distance(p), 0) << f << " " << w;
    }
  EXPECT_GE(hard, 12);
}

// Beyond these scales squared distances or triple products would overflow or underflow: a
// clear error instead of a wrong sign.
TEST(MeshDistance, RefusesScalesItCannotHandleExactly) {
  EXPECT_THROW(MeshDistance(test::make_box({-1e150, -1e150, -1e150}, {1e150, 1e150, 1e150})), InputError);
  EXPECT_THROW(MeshDistance(test::make_box({0, 0, 0}, {1e-110, 1e-110, 1e-110})), InputError);
  EXPECT_NO_THROW(MeshDistance(test::make_box({-1e30, -1e30, -1e30}, {1e30, 1e30, 1e30})));
}

// A box as wide as single precision allows (like the shared cray_right_fltmax.obj): the distance
// to a face must not inherit the rounding of coordinates near 3.4e38.
TEST(MeshDistance, HugeFacesGiveExactPlaneDistances) {
  const double big = 3.4028234663852886e38;
  const MeshDistance md(test::make_box({-big, -big, -big}, {big, big, -100}));
  EXPECT_EQ(md.signed_distance({1e30, 0, 0}), 100.0);
  EXPECT_EQ(md.signed_distance({0, 0, 0}, SignMethod::Pseudonormal), 100.0);
  EXPECT_EQ(md.signed_distance({0, 0, -200}), -100.0);
}

// End to end: the CLI commands on small files written here.
std::string run(const std::string& cmd, int& status) {
  std::string out;
  FILE* f = popen((cmd + " 2>&1").c_str(), "r");
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) out.append(buf, n);
  status = WEXITSTATUS(pclose(f));
  return out;
}

TEST(MeshCli, CheckAndSdf) {
  const std::string dir = ::testing::TempDir();
  const std::string good = dir + "/frep_cli_box.stl", bad = dir + "/frep_cli_open.obj", pts = dir + "/frep_cli_pts.txt";
  write_mesh(good, test::make_box());
  TriMesh open = test::make_box();
  open.triangles.pop_back(), open.origins.pop_back();
  write_mesh(bad, open);
  { std::ofstream(pts) << "# points\n0 0 0\n2, 0, 0\n0.5 0.5\n"; }
  int st;
  std::string out = run(std::string(FREP_CLI_PATH) + " check " + good, st);
  EXPECT_EQ(st, 0) << out;
  EXPECT_NE(out.find("valid solid: 12 triangles"), std::string::npos) << out;
  out = run(std::string(FREP_CLI_PATH) + " check --json " + bad, st);
  EXPECT_EQ(st, 4) << out;
  EXPECT_NE(out.find("\"open_edges\": {\"count\": 3"), std::string::npos) << out;
  out = run(std::string(FREP_CLI_PATH) + " sdf " + good + " --points " + pts, st);
  EXPECT_EQ(st, 0);
  EXPECT_EQ(out, "-1\n1\n-0.5\n");
  out = run(std::string(FREP_CLI_PATH) + " sdf " + good + " --sign pseudonormal -p " + pts, st);
  EXPECT_EQ(out, "-1\n1\n-0.5\n");
  out = run(std::string(FREP_CLI_PATH) + " check " + dir + "/does_not_exist.stl", st);
  EXPECT_EQ(st, 1);
  // Bad points are input errors naming the line: a bad number; a non-finite point (a distance to
  // it means nothing); one whose squared distance would overflow (it printed nan); a missing value.
  const std::pair<const char*, const char*> bad_points[] = {
      {"1 2 3\n4 five 6\n", "frep_cli_pts.txt:2: bad number 'five'"},
      {"1 2 3\n4 nan 6\n", "frep_cli_pts.txt:2: coordinate 'nan' is not a number"},
      {"1 2 3\n1e155 0 0\n", "frep_cli_pts.txt:2: coordinate '1e155' is out of range"},
      {"1,,2\n", "frep_cli_pts.txt:1: a value is missing"},
  };
  for (const auto& [text, message] : bad_points) {
    { std::ofstream(pts) << text; }
    out = run(std::string(FREP_CLI_PATH) + " sdf " + good + " -p " + pts, st);
    EXPECT_EQ(st, 1) << text;
    EXPECT_NE(out.find(message), std::string::npos) << out;
  }
  // Usage errors exit 2.
  run(std::string(FREP_CLI_PATH) + " sdf " + good + " -p " + pts + " --weld-tolerance nan", st);
  EXPECT_EQ(st, 2);
  run(std::string(FREP_CLI_PATH) + " sdf " + good + " -p " + pts + " --threads 100000", st);
  EXPECT_EQ(st, 2);
  for (const std::string& f : {good, bad, pts}) std::remove(f.c_str());
}

}  // namespace
}  // namespace frep

namespace frep {
namespace {

// Rays against every triangle: the first hit's t (and its triangle, up to ties) as found by
// testing them all, for rays through random points, along axes, and missing.
TEST(MeshDistance, FirstHitMatchesTestingEveryTriangle) {
  const TriMesh mesh = test::make_sphere(3, 1.0);
  const MeshDistance md(mesh);
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 o{u(rng), u(rng), 2.5};
    Vec3 dir{u(rng) * 0.3, u(rng) * 0.3, -1};
    if (i % 7 == 0) dir = {0, 0, -1};
    // Brute force: the smallest t over all triangles (Moller-Trumbore in double).
    double best = INFINITY;
    for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
      const Vec3 a = mesh.corner(t, 0), e1 = mesh.corner(t, 1) - a, e2 = mesh.corner(t, 2) - a;
      const Vec3 p = cross(dir, e2);
      const double det = dot(e1, p);
      if (det == 0) continue;
      const Vec3 s = o - a, q = cross(s, e1);
      const double uu = dot(s, p) / det, vv = dot(dir, q) / det, tt = dot(e2, q) / det;
      if (uu >= 0 && vv >= 0 && uu + vv <= 1 && tt >= 0) best = std::min(best, tt);
    }
    const auto h = md.first_hit(o, dir);
    if (!std::isfinite(best)) {
      // A miss, or a graze within the widened barycentric tests.
      if (h) { EXPECT_NEAR(length(o + dir * h->t), 1.0, 0.05); }
      continue;
    }
    ASSERT_TRUE(h.has_value()) << "missed a hit at t = " << best;
    EXPECT_NEAR(h->t, best, 1e-12 * (1 + best));
    ++hits;
  }
  EXPECT_GT(hits, 500);
  EXPECT_FALSE(md.first_hit({0, 0, 2.5}, {0, 0, 1}).has_value());            // away from it
  EXPECT_FALSE(md.first_hit({0, 0, 2.5}, {0, 0, -1}, 1.0).has_value());       // stops short
  EXPECT_FALSE(md.first_hit({NAN, 0, 2.5}, {0, 0, -1}).has_value());
}

}  // namespace
}  // namespace frep
