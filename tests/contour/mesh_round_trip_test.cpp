// Round trip mesh -> expression -> mesh: the clean shared meshes (fandisk, spot, the closed bunny,
// the unit cube) are converted with convert_mesh and meshed back by dual contouring at a modest
// resolution. The result must be a valid solid (the validator behind `frep check`) and lie within
// one cell of the input in both directions, measured with the exact distance oracle: every output
// vertex and triangle centroid to the input surface, and the input's vertices plus random points
// on its triangles to the output surface. Also `frep mesh MESH` end to end (a mesh argument is
// converted first), on the repository's example mesh.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "contour_test_util.hpp"
#include "frep/convert/convert.hpp"
#include "frep/mesh/mesh_distance.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "mesh_test_util.hpp"

#include "cli_test_util.hpp"

namespace frep {
namespace {

// Points on a mesh's surface: all its vertices, then `random` points uniform over its area.
std::vector<Vec3> surface_points(const TriMesh& m, std::size_t random, unsigned seed) {
  std::vector<Vec3> pts(m.vertices);
  std::vector<double> area_sum;
  double total = 0;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const Vec3 a = m.corner(t, 0), b = m.corner(t, 1), c = m.corner(t, 2);
    total += 0.5 * length(cross(b - a, c - a));
    area_sum.push_back(total);
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  for (std::size_t i = 0; i < random; ++i) {
    const double r = u(rng) * total;
    const std::size_t t = std::min<std::size_t>(
        static_cast<std::size_t>(std::lower_bound(area_sum.begin(), area_sum.end(), r) - area_sum.begin()),
        m.triangles.size() - 1);
    double s = u(rng), w = u(rng);
    if (s + w > 1) s = 1 - s, w = 1 - w;
    const Vec3 a = m.corner(t, 0), b = m.corner(t, 1), c = m.corner(t, 2);
    pts.push_back(a + (b - a) * s + (c - a) * w);
  }
  return pts;
}

// The largest distance from `pts` to the surface of `to`.
double max_distance(const std::vector<Vec3>& pts, const TriMesh& to) {
  const MeshDistance d(to);
  double worst = 0;
  for (const Vec3& p : pts) worst = std::max(worst, d.unsigned_distance(p));
  return worst;
}

struct RoundTrip {
  double out_to_in = 0, in_to_out = 0;  // in cells
  std::size_t triangles = 0;
};

// The input's bounding box grown by 1% of its longest side: as known_bounds (plus the margin cell)
// it puts the box's faces about half a cell off the grid planes along the longest axis. (Faces on
// grid planes put corners exactly on the surface, which count as outside; the cells at a box's
// corner then have one inside corner and the corner is not recovered: 1.15 cells on the unit cube.)
Box3 grown_box(const TriMesh& m) {
  Box3 b = validate_mesh(m).box;
  const Vec3 e = b.hi - b.lo;
  const double g = 0.01 * std::max({e.x, e.y, e.z});
  b.lo = b.lo - Vec3{g, g, g};
  b.hi = b.hi + Vec3{g, g, g};
  return b;
}

// Converts, meshes back at `resolution` over the input's box (grown_box), validates and measures both directions in cells. The tiles keep the
// subdivision's breadth-first frontier small: it stores one simplified tape per open box, and
// the tapes of converted meshes are large (fandisk: 669k nodes) near the surface.
RoundTrip round_trip(const TriMesh& input, int resolution, const std::string& what) {
  const ConvertResult conv = convert_mesh(input);
  MeshOptions o;
  o.resolution = resolution;
  o.known_bounds = grown_box(input);
  o.tiles = {64, 32, 8};
  MeshStats st;
  const TriMesh out = test::mesh_solid(Tape::compile(*conv.model.graph, conv.model.root), o, what, &st);
  RoundTrip r;
  r.triangles = out.triangles.size();
  if (out.triangles.empty()) {
    ADD_FAILURE() << what << ": empty mesh";
    return r;
  }
  // The output's vertices and triangle centroids against the input surface.
  std::vector<Vec3> out_pts(out.vertices);
  for (std::size_t t = 0; t < out.triangles.size(); ++t)
    out_pts.push_back((out.corner(t, 0) + out.corner(t, 1) + out.corner(t, 2)) * (1.0 / 3.0));
  r.out_to_in = max_distance(out_pts, input) / st.cell_size;
  r.in_to_out = max_distance(surface_points(input, 20000, 7), out) / st.cell_size;
  std::printf("[round-trip] %-24s %d cells across (cell %.4g): %zu -> %zu triangles; max distance output->input "
              "%.3f cells, input->output %.3f cells\n",
              what.c_str(), resolution, st.cell_size, input.triangles.size(), out.triangles.size(), r.out_to_in,
              r.in_to_out);
  return r;
}

TEST(MeshRoundTrip, SharedCleanMeshesComeBackWithinOneCell) {
  FREP_REQUIRE_SHARED_MESHES();
  for (const char* name : {"fandisk.obj", "spot.obj", "bunny_closed_libigl.off", "cube_unit_bin.stl"}) {
    const std::string path = test::shared_mesh_dir() + "/" + name;
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared mesh absent: " << path;
    const RoundTrip r = round_trip(read_mesh(path), 32, name);
    EXPECT_LE(r.out_to_in, 1.0) << name;
    EXPECT_LE(r.in_to_out, 1.0) << name;
  }
}

// The measure is not vacuous: a converted box meshed back passes, and the same mesh compared with
// a box one and a half cells larger fails the one-cell bound in the input->output direction.
TEST(MeshRoundTrip, DistanceDetectsAnOffset) {
  const TriMesh box = test::make_box({-1, -0.5, -0.25}, {1, 0.5, 0.25});
  const ConvertResult conv = convert_mesh(box);
  MeshOptions o;
  o.resolution = 32;
  o.known_bounds = grown_box(box);
  MeshStats st;
  const TriMesh out = test::mesh_solid(Tape::compile(*conv.model.graph, conv.model.root), o, "box", &st);
  EXPECT_LE(max_distance(surface_points(box, 2000, 3), out) / st.cell_size, 1.0);
  EXPECT_LE(max_distance(out.vertices, box) / st.cell_size, 1.0);
  const double g = 1.5 * st.cell_size;
  const TriMesh big = test::make_box({-1 - g, -0.5 - g, -0.25 - g}, {1 + g, 0.5 + g, 0.25 + g});
  EXPECT_GT(max_distance(surface_points(big, 2000, 3), out) / st.cell_size, 1.0);
}

// `frep mesh part.stl`: the mesh is read, converted and meshed without --bounds; the output is a
// valid solid within a cell of the input, with the input's volume.
TEST(MeshRoundTrip, CliMeshesAMeshFile) {
  const test::ScratchDir dir;
  const TriMesh input = read_mesh(FREP_SOURCE_DIR "/examples/bracket.obj");
  const std::string in_stl = dir.path("bracket.stl"), out_stl = dir.path("out.stl");
  write_mesh(in_stl, input);  // binary STL: exercises the STL reader and welding on the way in
  const test::CliRun r = test::run_frep(dir, "mesh '" + in_stl + "' -o '" + out_stl + "' -r 64");
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("triangles"), std::string::npos) << r.out;
  const TriMesh out = read_mesh(out_stl);
  const ValidationReport v = test::expect_solid(out, "bracket via the CLI");
  const ValidationReport vin = validate_mesh(input);
  ASSERT_TRUE(vin.is_solid());
  EXPECT_NEAR(v.volume, vin.volume, 0.01 * vin.volume);
  EXPECT_EQ(v.genus, vin.genus);
  // A cell: 64 across the longest side of the (slightly grown) found bounds.
  const Vec3 ext = vin.box.hi - vin.box.lo;
  const double cell = std::max({ext.x, ext.y, ext.z}) / 64;
  EXPECT_LE(max_distance(out.vertices, input), 1.1 * cell);
  EXPECT_LE(max_distance(surface_points(input, 5000, 5), out), 1.1 * cell);
}

}  // namespace
}  // namespace frep
