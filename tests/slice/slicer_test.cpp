// Whole slices checked from the G-code text alone (tests/slice/gcode_checker.hpp) against the
// field and, for a real mesh, against the mesh's exact plane sections computed here.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/expr/graph.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/model/csg.hpp"
#include "frep/model/shapes.hpp"
#include "frep/script/load.hpp"
#include "frep/slice/gcode.hpp"
#include "frep/slice/slicer.hpp"
#include "cli_test_util.hpp"
#include "mesh_test_util.hpp"
#include "slice/gcode_checker.hpp"

namespace frep::slice {
namespace {

std::string gcode_of(const SlicedPart& part, const PrintSettings& s, GcodeStats* stats = nullptr) {
  std::ostringstream out;
  const GcodeStats st = write_gcode(out, part, s, "test");
  if (stats) *stats = st;
  return out.str();
}

// A 20 x 16 x 10 block with a spherical pocket of radius 6 centred on its top face.
struct Pocket {
  Graph g;
  Field f = subtract(box(g, {-10, -8, 0}, {10, 8, 10}), sphere(g, {0, 0, 10}, 6));
  Tape tape = Tape::compile(g, f.id());
  static double volume() { return 20 * 16 * 10 - 2.0 / 3 * M_PI * 216; }
  // In-plane distance from (x, y) inside the section at height z to its boundary.
  static double edge_distance(double x, double y, double z) {
    const double r2 = 36 - (z - 10) * (z - 10);
    double d = std::min({x + 10, 10 - x, y + 8, 8 - y});
    if (r2 > 0) d = std::min(d, std::hypot(x, y) - std::sqrt(r2));
    return d;
  }
};

TEST(Slicer, PocketGcodePassesTheCheckerWithWallsAtExactOffsets) {
  Pocket p;
  PrintSettings s;
  const SlicedPart part = slice_field(p.tape, p.f.info, s);
  ASSERT_EQ(part.layers.size(), 50u);
  const test::GcodeFacts facts = test::read_gcode(gcode_of(part, s));
  EXPECT_TRUE(facts.problems.empty()) << facts.problems.front();
  ASSERT_TRUE(facts.has_shift);
  // Centred on the bed.
  EXPECT_NEAR(facts.shift[0], 110, 1e-3);
  EXPECT_NEAR(facts.shift[1], 110, 1e-3);
  EXPECT_NEAR(facts.shift[2], 0, 1e-4);
  std::size_t outer = 0;
  double worst = 0;
  for (const test::GcodeMove& m : facts.extrusions) {
    if (m.type != "WALL-OUTER") continue;
    const double z = m.z - s.layer_height / 2;
    const double d = Pocket::edge_distance(m.x1 - facts.shift[0], m.y1 - facts.shift[1], z);
    worst = std::max(worst, std::fabs(d - s.line_width / 2));
    ++outer;
  }
  EXPECT_GT(outer, 1000u);
  EXPECT_LT(worst, 0.01 * s.line_width);
}

TEST(Slicer, ExtrudesOnlyInsideThePart) {
  Pocket p;
  PrintSettings s;
  s.infill_pattern = InfillPattern::Grid;
  const SlicedPart part = slice_field(p.tape, p.f.info, s);
  const test::GcodeFacts facts = test::read_gcode(gcode_of(part, s));
  ASSERT_TRUE(facts.problems.empty()) << facts.problems.front();
  PointEvaluator pe;
  double most = -1;
  test::for_each_extruded_point(facts, 0.2, [&](const test::GcodeMove& m, double x, double y) {
    const double z = m.z - s.layer_height / 2 - facts.shift[2];
    most = std::max<double>(most, pe.eval(p.tape, static_cast<float>(x - facts.shift[0]), static_cast<float>(y - facts.shift[1]),
                                          static_cast<float>(z)));
  });
  EXPECT_LT(most, 1e-4);
}

TEST(Slicer, FullInfillExtrudesTheModelsVolume) {
  Pocket p;
  PrintSettings s;
  s.infill = 100;
  const SlicedPart part = slice_field(p.tape, p.f.info, s);
  GcodeStats st;
  const test::GcodeFacts facts = test::read_gcode(gcode_of(part, s, &st));
  ASSERT_TRUE(facts.problems.empty()) << facts.problems.front();
  const double volume = facts.filament * M_PI * s.filament_diameter * s.filament_diameter / 4;
  EXPECT_NEAR(volume / Pocket::volume(), 1, 0.03);
  EXPECT_NEAR(part.volume / Pocket::volume(), 1, 0.01);
}

TEST(Slicer, GyroidInfillAtItsDensity) {
  Pocket p;
  PrintSettings s;
  s.infill_pattern = InfillPattern::Gyroid;
  s.infill = 15;
  const SlicedPart part = slice_field(p.tape, p.f.info, s);
  const LayerPlan& mid = part.layers[20];  // z = 4.1: sparse in the middle
  double fill = 0;
  for (const ToolPath& t : mid.paths)
    if (t.role == PathRole::Fill) fill += length(t.points, t.closed);
  // The infill region is the section shrunk by the walls.
  const double region = area(offset(mid.outline, -2 * s.line_width, 0.001));
  EXPECT_NEAR(fill * s.line_width / region, 0.15, 0.15 * 0.25);
  const test::GcodeFacts facts = test::read_gcode(gcode_of(part, s));
  EXPECT_TRUE(facts.problems.empty()) << facts.problems.front();
}

TEST(Slicer, SameGcodeOnOneThreadAndOnTwo) {
  Pocket p;
  PrintSettings s;
  SlicerOptions one, two;
  one.threads = 1;
  two.threads = 2;
  EXPECT_EQ(gcode_of(slice_field(p.tape, p.f.info, s, one), s), gcode_of(slice_field(p.tape, p.f.info, s, two), s));
}

TEST(Slicer, RefusesWhatCannotBePrinted) {
  PrintSettings s;
  {
    Graph g;
    const Field f = sphere(g, {0, 0, 0}, 120);  // 240 mm: wider than the bed, not too tall
    try {
      slice_field(Tape::compile(g, f.id()), f.info, s);
      FAIL() << "a part bigger than the bed was sliced";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("bigger than the 220.0 x 220.0 mm bed"), std::string::npos) << e.what();
    }
  }
  {
    Graph g;
    const Field f = plane(g, {0, 0, 1}, 0);  // a half-space: unbounded
    EXPECT_THROW(slice_field(Tape::compile(g, f.id()), f.info, s), InputError);
  }
  {
    Graph g;
    const Field f = sphere(g, {0, 0, 0}, 0.05);  // thinner than half a layer
    EXPECT_THROW(slice_field(Tape::compile(g, f.id()), f.info, s), InputError);
  }
  {
    Graph g;
    const Field f = sphere(g, {0, 0, 0}, 5);
    PrintSettings keep = s;
    keep.keep_position = true;  // around (0, 0): off the bed
    EXPECT_THROW(slice_field(Tape::compile(g, f.id()), f.info, keep), InputError);
  }
}

// The shared CAD part, scaled to 40 mm: outer wall vertices against the mesh's exact sections
// (triangles cut by each layer's plane, computed here), and the extruded volume at 100%.
TEST(Slicer, MeshPartWallsAtHalfALineFromItsExactSections) {
  FREP_REQUIRE_SHARED_MESHES();
  test::ScratchDir scratch;
  TriMesh mesh = read_mesh(test::shared_mesh_dir() + "/fandisk.obj");
  Box3 b;
  for (const Vec3& v : mesh.vertices) b.add(v);
  const double k = 40 / std::max({b.size().x, b.size().y, b.size().z});
  for (Vec3& v : mesh.vertices) v = (v - b.lo) * k;
  const std::string path = scratch.path("part.stl");
  write_mesh(path, mesh);
  mesh = read_mesh(path);  // as stored (single precision)
  const Model m = load_field(path);
  const Tape tape = Tape::compile(*m.graph, m.root);
  PrintSettings s;
  s.infill = 100;
  const SlicedPart part = slice_field(tape, m.info, s);
  const test::GcodeFacts facts = test::read_gcode(gcode_of(part, s));
  ASSERT_TRUE(facts.problems.empty()) << facts.problems.front();

  // Each layer's section: segments where triangles cross the plane.
  std::vector<std::vector<std::array<double, 4>>> sections(facts.layer_z.size());
  for (std::size_t l = 0; l < sections.size(); ++l) {
    const double z = facts.layer_z[l] - s.layer_height / 2 - facts.shift[2];
    for (const Triangle& t : mesh.triangles) {
      const Vec3 p[3] = {mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]};
      double cut[2][2];
      int n = 0;
      for (int e = 0; e < 3 && n < 2; ++e) {
        const Vec3 a = p[e], c = p[(e + 1) % 3];
        if ((a.z < z) == (c.z < z)) continue;
        const double u = (z - a.z) / (c.z - a.z);
        cut[n][0] = a.x + u * (c.x - a.x), cut[n][1] = a.y + u * (c.y - a.y);
        ++n;
      }
      if (n == 2) sections[l].push_back({cut[0][0], cut[0][1], cut[1][0], cut[1][1]});
    }
  }
  std::size_t points = 0, within = 0;
  for (const test::GcodeMove& mv : facts.extrusions) {
    if (mv.type != "WALL-OUTER") continue;
    const double x = mv.x1 - facts.shift[0], y = mv.y1 - facts.shift[1];
    double best = 1e9;
    for (const auto& sg : sections[static_cast<std::size_t>(mv.layer)]) {
      const double dx = sg[2] - sg[0], dy = sg[3] - sg[1], l2 = dx * dx + dy * dy;
      const double t = l2 > 0 ? std::clamp(((x - sg[0]) * dx + (y - sg[1]) * dy) / l2, 0.0, 1.0) : 0;
      best = std::min(best, std::hypot(x - sg[0] - t * dx, y - sg[1] - t * dy));
    }
    ++points;
    if (std::fabs(best - s.line_width / 2) <= 0.01 * s.line_width) ++within;
  }
  ASSERT_GT(points, 10000u);
  EXPECT_GT(static_cast<double>(within) / static_cast<double>(points), 0.99);

  double volume = 0;  // the mesh's, by the divergence theorem
  for (const Triangle& t : mesh.triangles) {
    const Vec3 a = mesh.vertices[t[0]], c = mesh.vertices[t[1]], d = mesh.vertices[t[2]];
    volume += dot(a, cross(c, d)) / 6;
  }
  const double extruded = facts.filament * M_PI * s.filament_diameter * s.filament_diameter / 4;
  EXPECT_NEAR(extruded / volume, 1, 0.03);
}

}  // namespace
}  // namespace frep::slice
