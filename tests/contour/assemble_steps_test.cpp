// The assembly's steps one at a time: grid edge ids, the triangles of a polygon, the choice of a
// quad's diagonal, the winding and exact checks of a star and of a fan, the cell box and the
// relocation of a vertex in it, the repairs in their order, the output's layout, and (on leaves
// of real fields) the polygons around crossing edges, their face points and incidence.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include "contour/assemble.hpp"
#include "contour/assemble_steps.hpp"
#include "contour/mesher_steps.hpp"
#include "frep/expr/expr.hpp"

namespace frep::contour {
namespace {

bool is_f32(double d) {
  volatile float f = static_cast<float>(d);
  return static_cast<double>(f) == d;
}

bool inside(const Vec3& p, const Box3& b) {
  return p.x >= b.lo.x && p.x <= b.hi.x && p.y >= b.lo.y && p.y <= b.hi.y && p.z >= b.lo.z && p.z <= b.hi.z;
}

EdgePolygon polygon(std::initializer_list<std::uint32_t> v, EdgePolygon::Mode mode) {
  EdgePolygon p;
  for (std::uint32_t x : v) p.v[p.n++] = x;
  p.mode = mode;
  return p;
}

// Twice the signed area of triangle (a, b, c) in the xy plane.
double turn(const Vec3& a, const Vec3& b, const Vec3& c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

// A planar patch of 3x3 dual vertices (id i + 3j at the center of cell [i-1, i] x [j-1, j] x
// [0, 1] of a grid of unit cells), joined by four quads counter-clockwise seen from +z about
// vertex 4, with fan centers on the grid edges along z that the quads go round.
struct Patch {
  MeshGrid grid = make_grid(Box3{{-1, -1, 0}, {2, 2, 1}}, 1.0, 0);
  Assembly as{grid};

  explicit Patch(EdgePolygon::Mode mode) {
    as.dual = 9;
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) as.pos.push_back(Vec3{i - 0.5, j - 0.5, 0.5});
    as.mass = as.pos;
    as.nrm.assign(9, Vec3{0, 0, 1});
    as.piece.assign(9, 0x10);  // one vertex per cell
    for (std::uint32_t a : {0u, 1u, 3u, 4u}) {
      EdgePolygon p = polygon({a, a + 1, a + 4, a + 3}, mode);
      p.axis = 2;
      as.polys.push_back(p);
    }
    center_fans_on_edges();
    index_incident_polygons(as);
  }
  void center_fans_on_edges() {
    for (EdgePolygon& p : as.polys) p.center = Vec3{std::floor(as.mass[p.v[2]].x), std::floor(as.mass[p.v[2]].y), 0.5};
  }
  // The ring of vertex 4's neighbours shrunk to x <= 0.3: vertex 4 (at x = 0.5) is beyond it and
  // its star folds over, but would not at x < 0.3, inside its cell. Fan centers follow.
  void fold() {
    for (std::uint32_t v : {2u, 5u, 8u}) as.pos[v].x = 0.3;
    for (std::uint32_t v : {1u, 7u}) as.pos[v].x = -0.1;
    for (EdgePolygon& p : as.polys) p.center = (as.pos[p.v[0]] + as.pos[p.v[1]] + as.pos[p.v[2]] + as.pos[p.v[3]]) * 0.25;
  }
  bool all_ok() const {
    std::vector<StarTriangle> tris;
    for (std::uint32_t v = 0; v < as.dual; ++v)
      if (!vertex_ok(as, v, tris)) return false;
    return true;
  }
};

TEST(AssembleSteps, EdgeIdsAreDistinctAndGiveTheEdgesMidpoints) {
  const MeshGrid grid = make_grid(Box3{{0, 0, 0}, {3, 2, 2}}, 1.0, 0);
  std::set<std::uint64_t> ids;
  for (int z = 0; z < grid.n[2]; ++z)
    for (int y = 0; y < grid.n[1]; ++y)
      for (int x = 0; x < grid.n[0]; ++x)
        for (int a = 0; a < 3; ++a) {
          const int c[3] = {x, y, z};
          const std::uint64_t id = edge_id(grid, c, a);
          EXPECT_TRUE(ids.insert(id).second);
          const Vec3 lo{grid.coord(0, x), grid.coord(1, y), grid.coord(2, z)};
          Vec3 hi = lo;
          hi[a] = grid.coord(a, c[a] + 1);
          EXPECT_EQ(edge_midpoint(grid, id), (lo + hi) * 0.5);
        }
}

TEST(AssembleSteps, QuadSplitsCoverTheQuadTurningItsWay) {
  // A convex quad, counter-clockwise in the xy plane.
  const std::vector<Vec3> q = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}};
  for (auto mode : {EdgePolygon::SplitA, EdgePolygon::SplitB}) {
    std::vector<std::array<std::uint32_t, 3>> tris;
    triangles_of(polygon({0, 1, 2, 3}, mode), ~0u, ~0u, [&](auto a, auto b, auto c) { tris.push_back({a, b, c}); });
    ASSERT_EQ(tris.size(), 2u);
    double area = 0;
    std::set<std::uint32_t> used;
    for (const auto& t : tris) {
      const double s = turn(q[t[0]], q[t[1]], q[t[2]]);
      EXPECT_GT(s, 0) << "a triangle turns against the quad";
      area += s / 2;
      used.insert(t.begin(), t.end());
    }
    EXPECT_DOUBLE_EQ(area, 2.0);
    EXPECT_EQ(used.size(), 4u);
    // The two triangles share one diagonal: 0-2 for A, 1-3 for B.
    const std::uint32_t d0 = mode == EdgePolygon::SplitA ? 0 : 1, d1 = d0 + 2;
    for (const auto& t : tris) {
      EXPECT_NE(std::find(t.begin(), t.end(), d0), t.end());
      EXPECT_NE(std::find(t.begin(), t.end(), d1), t.end());
    }
  }
}

TEST(AssembleSteps, FanTrianglesJoinEachSideToTheCenter) {
  const EdgePolygon p = polygon({10, 11, 12, 13, 14}, EdgePolygon::Fan);
  std::vector<std::array<std::uint32_t, 3>> all, at12;
  triangles_of(p, 99, ~0u, [&](auto a, auto b, auto c) { all.push_back({a, b, c}); });
  triangles_of(p, 99, 12, [&](auto a, auto b, auto c) { at12.push_back({a, b, c}); });
  ASSERT_EQ(all.size(), 5u);
  std::set<std::pair<std::uint32_t, std::uint32_t>> sides;
  for (const auto& t : all) {
    EXPECT_EQ(t[2], 99u);
    sides.insert({t[0], t[1]});
  }
  for (int i = 0; i < 5; ++i) EXPECT_EQ(sides.count({p.v[i], p.v[(i + 1) % 5]}), 1u);
  // Only the triangles with vertex 12: the sides before and after it.
  ASSERT_EQ(at12.size(), 2u);
  for (const auto& t : at12) EXPECT_NE(std::find(t.begin(), t.end(), 12u), t.end());
}

TEST(AssembleSteps, DiagonalKeepsTrianglesFacingOutward) {
  // A dart (vertex 3 inside the triangle 0 1 2): only diagonal 1-3 keeps both halves facing +z.
  const Vec3 q[4] = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0.5, 0.5, 0}};
  const Vec3 n[4] = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  EXPECT_EQ(choose_diagonal(q, n, Vec3{0, 0, 1}), EdgePolygon::SplitB);
  // The same dart numbered from its notch: the diagonal from the notch, now 0-2.
  const Vec3 r[4] = {q[3], q[0], q[1], q[2]};
  EXPECT_EQ(choose_diagonal(r, n, Vec3{0, 0, 1}), EdgePolygon::SplitA);
}

TEST(AssembleSteps, DiagonalFollowsASharpEdge) {
  // A roof: 0 and 2 on the ridge (x = 0, z = 1), 1 and 3 down its two slopes. The normals are
  // the slopes'; the ridge's vertices lie on both. The diagonal 0-2 stays on the ridge.
  const Vec3 q[4] = {{0, -1, 1}, {1, 0, 0}, {0, 1, 1}, {-1, 0, 0}};
  const Vec3 right = Vec3{1, 0, 1} / std::sqrt(2.0), left = Vec3{-1, 0, 1} / std::sqrt(2.0);
  const Vec3 n[4] = {right, right, left, left};
  EXPECT_EQ(choose_diagonal(q, n, Vec3{0, 0, 1}), EdgePolygon::SplitA);
}

TEST(AssembleSteps, DiagonalAvoidsASliver) {
  // 0, 1 and 2 on one line: the split 0-2 would make the triangle 0 1 2 of no area.
  const Vec3 q[4] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {1, 1, 0}};
  const Vec3 n[4] = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  EXPECT_EQ(choose_diagonal(q, n, Vec3{0, 0, 1}), EdgePolygon::SplitB);
}

// Triangles about the origin to the points at the given angles (degrees), in the xy plane.
std::vector<StarTriangle> fan_at_angles(const std::vector<double>& degrees) {
  std::vector<StarTriangle> tris;
  const std::size_t n = degrees.size();
  for (std::size_t i = 0; i < n; ++i) {
    const double a = degrees[i] * M_PI / 180, b = degrees[(i + 1) % n] * M_PI / 180;
    tris.push_back({{0, unsigned(i + 1), unsigned((i + 1) % n + 1)},
                    {Vec3{}, Vec3{std::cos(a), std::sin(a), 0}, Vec3{std::cos(b), std::sin(b), 0}}});
  }
  return tris;
}

TEST(AssembleSteps, FanWindsOnceAcceptsAFlatFanOnly) {
  auto xy = [](const Vec3& d) { return std::pair{d.x, d.y}; };
  auto yx = [](const Vec3& d) { return std::pair{d.y, d.x}; };  // seen from below
  EXPECT_TRUE(fan_winds_once(fan_at_angles({10, 100, 190, 280}), xy));
  EXPECT_TRUE(fan_winds_once(fan_at_angles({0, 60, 120, 180, 240, 300}), xy));
  EXPECT_FALSE(fan_winds_once(fan_at_angles({10, 100, 190, 280}), yx)) << "turns clockwise";
  // Folded: one wedge turns back.
  EXPECT_FALSE(fan_winds_once(fan_at_angles({10, 100, 80, 190, 280}), xy));
  // Round twice.
  EXPECT_FALSE(fan_winds_once(fan_at_angles({10, 130, 250, 370, 490, 610}), xy));
  // Half a turn and a flat wedge are left to the exact test.
  EXPECT_FALSE(fan_winds_once(fan_at_angles({0, 180, 270}), xy));
  EXPECT_FALSE(fan_winds_once(fan_at_angles({0, 0, 120, 240}), xy));
}

TEST(AssembleSteps, NoTwoMeetRejectsCrossingAndFlatTriangles) {
  std::vector<StarTriangle> tris = fan_at_angles({10, 100, 190, 280});
  EXPECT_TRUE(no_two_meet(tris));
  // A triangle through the others' plane.
  tris.push_back({{10, 11, 12}, {Vec3{0.3, 0.1, -1}, Vec3{0.3, 0.1, 1}, Vec3{0.4, 0.5, 1}}});
  EXPECT_FALSE(no_two_meet(tris));
  tris = fan_at_angles({10, 100, 190, 280});
  tris.push_back({{10, 11, 12}, {Vec3{5, 5, 5}, Vec3{6, 6, 6}, Vec3{7, 7, 7}}});  // no area, far away
  EXPECT_FALSE(no_two_meet(tris));
  // Folded in its plane: wedges overlap.
  EXPECT_FALSE(no_two_meet(fan_at_angles({10, 100, 80, 190, 280})));
}

TEST(AssembleSteps, StarCheckAcceptsAFlatStarAndRejectsAFoldedOne) {
  for (auto mode : {EdgePolygon::SplitA, EdgePolygon::SplitB, EdgePolygon::Fan}) {
    Patch flat(mode);
    std::vector<StarTriangle> tris;
    EXPECT_TRUE(star_ok(flat.as, 4, tris)) << mode;
    EXPECT_EQ(tris.size(), mode == EdgePolygon::Fan ? 8u : 6u) << "triangles at the center vertex";
    for (const StarTriangle& t : tris) EXPECT_EQ(t.id[0], 4u);
    EXPECT_TRUE(flat.all_ok()) << mode;
    Patch folded(mode);
    folded.fold();
    EXPECT_FALSE(star_ok(folded.as, 4, tris)) << mode;
    EXPECT_FALSE(folded.all_ok()) << mode;
  }
}

TEST(AssembleSteps, FanCheckLooksAlongTheEdge) {
  Patch p(EdgePolygon::Fan);
  std::vector<StarTriangle> tris;
  for (std::uint32_t pi = 0; pi < 4; ++pi) EXPECT_TRUE(fan_ok(p.as, pi, tris));
  // Outward along -z, the same fan turns the wrong way (the exact test still finds no overlap).
  p.as.polys[0].dir = -1;
  EXPECT_TRUE(fan_ok(p.as, 0, tris));
  // A bow tie: two corners swapped.
  std::swap(p.as.polys[0].v[1], p.as.polys[0].v[2]);
  p.as.polys[0].dir = 1;
  EXPECT_FALSE(fan_ok(p.as, 0, tris));
  // Split quads are not fans: nothing to check.
  Patch q(EdgePolygon::SplitA);
  std::swap(q.as.polys[0].v[1], q.as.polys[0].v[2]);
  EXPECT_TRUE(fan_ok(q.as, 0, tris));
}

TEST(AssembleSteps, IncidentPolygonsListEachVertexsPolygonsInOrder) {
  Patch p(EdgePolygon::SplitA);
  for (std::uint32_t v = 0; v < p.as.dual; ++v) {
    std::vector<std::uint32_t> expected;
    for (std::uint32_t pi = 0; pi < p.as.polys.size(); ++pi) {
      const EdgePolygon& poly = p.as.polys[pi];
      if (std::find(poly.v, poly.v + poly.n, v) != poly.v + poly.n) expected.push_back(pi);
    }
    const std::vector<std::uint32_t> got(p.as.incident.begin() + p.as.first[v], p.as.incident.begin() + p.as.first[v + 1]);
    EXPECT_EQ(got, expected) << "vertex " << v;
  }
}

TEST(AssembleSteps, CellBoxIsTheVertexsCellInset) {
  const MeshGrid grid = make_grid(Box3{{-1, -1, -1}, {1, 1, 1}}, 0.25, 1, 0.3);
  for (int i = 0; i < 200; ++i) {
    const Vec3 p{-1 + 0.0101 * i, 0.9 - 0.009 * i, std::sin(i) * 0.99};
    const Box3 b = cell_box(grid, p);
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(b.hi[a] - b.lo[a], grid.h * (1 - 2 * kVertexInset), 1e-6);
      // Within kVertexInset of the box: the cell around p.
      EXPECT_GE(p[a], b.lo[a] - kVertexInset * grid.h * 1.01);
      EXPECT_LE(p[a], b.hi[a] + kVertexInset * grid.h * 1.01);
    }
  }
}

TEST(AssembleSteps, RelocationCandidatesStayInTheBoxNearestFirst) {
  const Box3 box{{0.0001, 0.0001, 0.0001}, {0.9999, 0.9999, 0.9999}};
  const Vec3 orig{0.3, 0.6, 0.5};
  for (const Vec3 centroid : {Vec3{0.1, 0.2, 0.7}, Vec3{-3, 0.2, 2}}) {
    const std::vector<Vec3> c = relocation_candidates(orig, centroid, box);
    ASSERT_EQ(c.size(), 4u + 125u);
    for (const Vec3& p : c) {
      EXPECT_TRUE(inside(p, box));
      EXPECT_TRUE(is_f32(p.x) && is_f32(p.y) && is_f32(p.z));
    }
    // The lattice, nearest first.
    for (std::size_t i = 5; i < c.size(); ++i) EXPECT_LE(length2(c[i - 1] - orig), length2(c[i] - orig));
    if (!inside(centroid, box)) {
      EXPECT_NEAR(c[0].x, box.lo.x, 1e-7) << "towards the centroid, stopped at the box";
      continue;
    }
    // Towards the centroid: all the way, half, three quarters, a quarter (to f32).
    const double w[4] = {1, 0.5, 0.75, 0.25};
    for (int i = 0; i < 4; ++i)
      for (int a = 0; a < 3; ++a) EXPECT_NEAR(c[static_cast<std::size_t>(i)][a], orig[a] + (centroid[a] - orig[a]) * w[i], 1e-7);
  }
}

TEST(AssembleSteps, RelocationMovesAFoldedVertexInsideItsCell) {
  Patch p(EdgePolygon::Fan);
  p.fold();
  const Box3 cell = cell_box(p.grid, p.as.pos[4]);
  std::vector<StarTriangle> tris;
  ASSERT_TRUE(relocate(p.as, 4, tris));
  EXPECT_TRUE(inside(p.as.pos[4], cell));
  EXPECT_TRUE(is_f32(p.as.pos[4].x) && is_f32(p.as.pos[4].y) && is_f32(p.as.pos[4].z));
  EXPECT_TRUE(p.all_ok());
  // No place in its cell untangles a vertex whose neighbours are all on one side of the cell.
  Patch q(EdgePolygon::Fan);
  for (std::uint32_t v : {0u, 1u, 2u, 3u, 5u, 6u, 7u, 8u}) q.as.pos[v].x = q.as.pos[v].x * 0.1 - 3;
  const Vec3 before = q.as.pos[4];
  EXPECT_FALSE(relocate(q.as, 4, tris));
  EXPECT_EQ(q.as.pos[4], before) << "left in place";
}

TEST(AssembleSteps, RepairsGoFromFansToMassPointsToRelocation) {
  Patch p(EdgePolygon::SplitA);
  p.fold();
  std::vector<char> mass_points(p.as.dual, 0);
  std::vector<StarTriangle> tris;
  std::vector<std::uint32_t> touched;
  // First the split quads at the vertex become fans.
  EXPECT_EQ(repair_vertex(p.as, 4, mass_points, tris, touched), Repair::Fans);
  for (const EdgePolygon& poly : p.as.polys) EXPECT_EQ(poly.mode, EdgePolygon::Fan);
  EXPECT_EQ(std::set<std::uint32_t>(touched.begin(), touched.end()), (std::set<std::uint32_t>{0, 1, 2, 3}));
  // Then its cell's vertex goes to its mass point, once.
  p.as.mass[4] = Vec3{0.9, 0.5, 0.5};
  touched.clear();
  EXPECT_EQ(repair_vertex(p.as, 4, mass_points, tris, touched), Repair::MassPoints);
  EXPECT_EQ(p.as.pos[4], p.as.mass[4]);
  EXPECT_EQ(touched.size(), 4u);
  EXPECT_TRUE(mass_points[4]);
  // Then it is relocated (the mass point was no better).
  touched.clear();
  EXPECT_EQ(repair_vertex(p.as, 4, mass_points, tris, touched), Repair::Relocated);
  EXPECT_TRUE(p.all_ok());
}

TEST(AssembleSteps, RepairRoundsUntangleAFoldedPatch) {
  ThreadPool pool(2);
  // Folded with the fans about the grid's edges: the mass points (where the vertices were) undo it.
  Patch p(EdgePolygon::SplitB);
  p.fold();
  p.center_fans_on_edges();
  ASSERT_FALSE(p.all_ok());
  repair_vertices(p.as, pool);  // (it may list vertices that failed on the way)
  EXPECT_TRUE(p.all_ok());
  EXPECT_EQ(p.as.pos, p.as.mass);
  // Nothing to do on a flat one: nothing changes.
  Patch flat(EdgePolygon::SplitB);
  const std::vector<Vec3> before = flat.as.pos;
  EXPECT_TRUE(repair_vertices(flat.as, pool).empty());
  EXPECT_EQ(flat.as.pos, before);
  for (const EdgePolygon& poly : flat.as.polys) EXPECT_EQ(poly.mode, EdgePolygon::SplitB);
}

TEST(AssembleSteps, OutputHasVerticesFacePointsThenFanCenters) {
  Patch p(EdgePolygon::SplitA);
  p.as.polys[1].mode = EdgePolygon::Fan;
  p.as.polys[3].mode = EdgePolygon::Fan;
  p.as.face_points = {Vec3{7, 7, 7}};
  const std::vector<EdgePolygon> polys = p.as.polys;
  const TriMesh m = emit_mesh(std::move(p.as));
  ASSERT_EQ(m.vertices.size(), 9u + 1u + 2u);
  EXPECT_EQ(m.vertices[9], (Vec3{7, 7, 7}));
  EXPECT_EQ(m.vertices[10], polys[1].center);
  EXPECT_EQ(m.vertices[11], polys[3].center);
  ASSERT_EQ(m.triangles.size(), 2u + 4u + 2u + 4u);
  // In polygon order: the fan of polygon 1 comes after the split of polygon 0.
  for (int k = 2; k < 6; ++k) EXPECT_EQ(m.triangles[static_cast<std::size_t>(k)][2], 10u);
  for (const auto& t : m.triangles)
    for (std::uint32_t v : t) EXPECT_LT(v, m.vertices.size());
}

// Leaves of a real field, through the mesher's steps (as one pass runs them).
struct RealLeaves {
  MeshGrid grid;
  std::unique_ptr<Subdivider> sub;
  Leaves leaves;
  int leaf_size = 0;

  RealLeaves(const Expr& e, int resolution) {
    MeshOptions o;
    o.resolution = resolution;
    o.threads = 2;
    o.tiles = {8, 4};
    const Box3 region{{-1, -1, -1}, {1, 1, 1}};
    grid = make_grid(region, cell_edge(region, o), 1, 1.0 / 64);
    const Box3 cut = cut_box(grid, region, true);
    const Tape closed = close_at_box(Tape::compile(e.graph(), e.id()), cut);
    MeshControl control(o);
    Subdivider& s = subdivider_for(sub, o.tiles, o.threads, 0);
    leaves = build_leaves(s, closed, grid, cut, o, control, false);
    leaf_size = o.tiles.back();
  }
};

// Every polygon edge (a, b) has its opposite (b, a) in exactly one other polygon: the polygons
// make a closed, oriented surface.
void expect_closed_and_oriented(const std::vector<EdgePolygon>& polys) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> sides;
  for (const EdgePolygon& p : polys)
    for (int i = 0; i < p.n; ++i) ++sides[{p.v[i], p.v[(i + 1) % p.n]}];
  for (const auto& [side, count] : sides) {
    EXPECT_EQ(count, 1) << side.first << "-" << side.second;
    const auto back = sides.find({side.second, side.first});
    EXPECT_TRUE(back != sides.end() && back->second == 1) << side.first << "-" << side.second;
  }
}

TEST(AssembleSteps, PolygonsAroundCrossingEdgesCloseTheSurface) {
  Graph g;
  const Expr x = g.x(), y = g.y(), z = g.z();
  const Expr ball = sqrt(square(x - 0.1f) + square(y) + square(z)) - 0.6f;
  // Under-sampled: cells with several pieces of surface, whose polygons go through face points.
  const Expr gyroid = max(sqrt(square(x) + square(y) + square(z)) - 0.9f,
                          abs(sin(x * 20.0f) * cos(y * 20.0f) + sin(y * 20.0f) * cos(z * 20.0f) + sin(z * 20.0f) * cos(x * 20.0f)) - 0.3f);
  ThreadPool pool(2);
  for (const auto& [name, e, with_face_points] : std::vector<std::tuple<const char*, Expr, bool>>{
           {"ball", ball, false}, {"gyroid", gyroid, true}}) {
    SCOPED_TRACE(name);
    RealLeaves r(e, 16);
    const std::vector<LeafRecord*> leaves = r.leaves.in_key_order();
    ASSERT_FALSE(leaves.empty());
    Assembly as(r.grid);
    gather_vertices(as, leaves);
    std::size_t vertices = 0, crossings = 0;
    for (const LeafRecord* l : leaves) {
      EXPECT_EQ(l->vertex_offset, vertices) << "numbered in leaf order";
      vertices += l->positions.size();
      for (const SurfaceCell& c : l->cells)
        for (float t : c.t) crossings += !std::isnan(t);
    }
    EXPECT_EQ(as.dual, vertices);
    const std::vector<LeafFacePoints> fps = collect_polygons(as, leaves, r.leaf_size, pool);
    ASSERT_EQ(as.polys.size(), crossings) << "one polygon per crossing edge";
    std::size_t keys = 0;
    for (const LeafFacePoints& f : fps) keys += f.keys.size();
    EXPECT_EQ(keys > 0, with_face_points);
    number_face_points(as, fps);
    EXPECT_LE(as.face_points.size(), keys);
    EXPECT_EQ(as.face_points.size() > 0, with_face_points);
    std::set<std::tuple<double, double, double>> distinct;
    for (const Vec3& f : as.face_points) {
      EXPECT_TRUE(is_f32(f.x) && is_f32(f.y) && is_f32(f.z));
      distinct.insert({f.x, f.y, f.z});
    }
    EXPECT_EQ(distinct.size(), as.face_points.size());
    for (const EdgePolygon& p : as.polys) {
      EXPECT_GE(p.n, 4);
      EXPECT_LE(p.n, 12);
      if (p.n != 4) {
        EXPECT_EQ(p.mode, EdgePolygon::Fan);
      }
      for (int i = 0; i < p.n; ++i) EXPECT_LT(p.v[i], as.dual + as.face_points.size());
    }
    expect_closed_and_oriented(as.polys);
    index_incident_polygons(as);
    // The steps in a row make what assemble makes.
    const std::vector<std::uint32_t> stuck = repair_vertices(as, pool);
    std::vector<StarTriangle> tris;
    for (std::uint32_t v = 0; v < as.dual; ++v)
      if (!std::binary_search(stuck.begin(), stuck.end(), v)) {
        EXPECT_TRUE(vertex_ok(as, v, tris)) << "vertex " << v;
      }
    const TriMesh steps = emit_mesh(std::move(as));
    std::size_t unresolved = 0;
    const TriMesh whole = assemble(leaves, r.grid, r.leaf_size, pool, &unresolved);
    EXPECT_EQ(steps.vertices, whole.vertices);
    EXPECT_EQ(steps.triangles, whole.triangles);
    EXPECT_LE(unresolved, stuck.size());
  }
}

}  // namespace
}  // namespace frep::contour
