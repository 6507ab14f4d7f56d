// Repair: constructed broken solids come back as valid solids bounding exactly the region their
// surface winds around; real broken meshes are repaired or refused with a reason.
#include "frep/mesh/repair.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <set>

#include "frep/convert/make_solid.hpp"
#include "frep/error.hpp"
#include "frep/mesh/mesh_distance.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/validate.hpp"
#include "mesh_test_util.hpp"

namespace frep {
namespace {

using test::make_box;

TriMesh join(std::initializer_list<TriMesh> parts) {
  TriMesh out;
  out.name = "joined";
  for (const TriMesh& p : parts) {
    const auto base = static_cast<std::uint32_t>(out.vertices.size());
    out.vertices.insert(out.vertices.end(), p.vertices.begin(), p.vertices.end());
    for (const Triangle& t : p.triangles) out.add_triangle(t[0] + base, t[1] + base, t[2] + base);
  }
  return out;
}

TriMesh moved(TriMesh m, Vec3 d) {
  for (Vec3& v : m.vertices) v = v + d;
  return m;
}

// Volume of a union of axis-aligned boxes, exactly (coordinate compression).
double union_volume(const std::vector<Box3>& boxes) {
  std::vector<double> xs, ys, zs;
  for (const Box3& b : boxes) {
    xs.insert(xs.end(), {b.lo.x, b.hi.x});
    ys.insert(ys.end(), {b.lo.y, b.hi.y});
    zs.insert(zs.end(), {b.lo.z, b.hi.z});
  }
  for (auto* v : {&xs, &ys, &zs}) {
    std::sort(v->begin(), v->end());
    v->erase(std::unique(v->begin(), v->end()), v->end());
  }
  double vol = 0;
  for (std::size_t i = 0; i + 1 < xs.size(); ++i)
    for (std::size_t j = 0; j + 1 < ys.size(); ++j)
      for (std::size_t k = 0; k + 1 < zs.size(); ++k) {
        const Vec3 c{(xs[i] + xs[i + 1]) / 2, (ys[j] + ys[j + 1]) / 2, (zs[k] + zs[k + 1]) / 2};
        for (const Box3& b : boxes)
          if (b.contains(c)) {
            vol += (xs[i + 1] - xs[i]) * (ys[j + 1] - ys[j]) * (zs[k + 1] - zs[k]);
            break;
          }
      }
  return vol;
}

// The properties every exact repair has: a valid solid (checked independently of the report),
// every vertex on the input's surface.
void expect_exact_solid(const TriMesh& input, const RepairResult& r) {
  const ValidationReport v = validate_mesh(r.mesh);
  EXPECT_TRUE(v.is_solid()) << v.summary();
  EXPECT_TRUE(r.report.after.is_solid());
  EXPECT_TRUE(r.report.exact);
  const MeshDistance md(input);
  const Box3 box = bounding_box(input);
  const double diag = length(box.size());
  double worst = 0;
  for (const Vec3& p : r.mesh.vertices) worst = std::max(worst, md.unsigned_distance(p));
  EXPECT_LE(worst, 1e-9 * diag);
}

TEST(Repair, TwoOverlappingBoxesGiveTheirUnion) {
  const TriMesh in = join({make_box({0, 0, 0}, {2, 2, 2}), make_box({1, 1, 1}, {3, 3.5, 2.5})});
  const RepairResult r = repair_mesh(in);
  expect_exact_solid(in, r);
  EXPECT_NEAR(r.report.after.volume, union_volume({{{0, 0, 0}, {2, 2, 2}}, {{1, 1, 1}, {3, 3.5, 2.5}}}), 1e-12);
  EXPECT_GT(r.report.crossing_pairs, 0u);
  EXPECT_GT(r.report.patches_removed, 0u);
}

TEST(Repair, BoxesSharingAFaceRegionMerge) {
  // Coplanar overlap: the second box stands on the first's top face.
  const TriMesh in = join({make_box({0, 0, 0}, {4, 4, 1}), make_box({1, 1, 1}, {2, 2, 2})});
  const RepairResult r = repair_mesh(in);
  expect_exact_solid(in, r);
  EXPECT_NEAR(r.report.after.volume, 17, 1e-12);
  EXPECT_EQ(validate_mesh(r.mesh).components, 1u);
}

TEST(Repair, PlateWithEmbossedTextShells) {
  // Letters as separate shells: some standing on the plate, some sunk into it, one crossing its edge.
  std::vector<Box3> boxes = {{{0, 0, 0}, {10, 4, 1}}};
  std::vector<TriMesh> parts = {make_box(boxes[0].lo, boxes[0].hi)};
  for (int i = 0; i < 5; ++i) {
    const Box3 b{{1.0 + 1.7 * i, 1, i % 2 ? 1.0 : 0.5}, {2.2 + 1.7 * i, 3 + 0.25 * i, 1.6}};
    boxes.push_back(b);
    parts.push_back(make_box(b.lo, b.hi));
  }
  TriMesh in;
  for (const TriMesh& p : parts) in = join({in, p});
  const RepairResult r = repair_mesh(in);
  expect_exact_solid(in, r);
  EXPECT_NEAR(r.report.after.volume, union_volume(boxes), 1e-9);
}

TEST(Repair, BoxMissingAFaceIsFilled) {
  TriMesh in = make_box({0, 0, 0}, {1, 1, 1});
  in.triangles.erase(in.triangles.begin(), in.triangles.begin() + 2);  // the z = 0 face
  in.origins.clear();
  const RepairResult r = repair_mesh(in);
  EXPECT_TRUE(validate_mesh(r.mesh).is_solid());
  EXPECT_FALSE(r.report.exact);
  ASSERT_EQ(r.report.holes.size(), 1u);
  EXPECT_NEAR(r.report.holes[0].area, 1, 1e-9);
  EXPECT_NEAR(r.report.after.volume, 1, 1e-9);
}

// A crack: one corner stored twice, 1e-9 apart (a CAD export's rounding). The weld closes it at
// the default tolerance (1e-7 of the diagonal).
TEST(Repair, CracksCloseByARelativeWeld) {
  TriMesh in = make_box({0, 0, 0}, {1, 1, 1});
  in.origins.clear();
  in.vertices.push_back(in.vertices[7] + Vec3{1e-9, 0, 0});
  const auto copy = static_cast<std::uint32_t>(in.vertices.size() - 1);
  int replaced = 0;
  for (Triangle& t : in.triangles)
    for (std::uint32_t& v : t)
      if (v == 7 && replaced < 2) v = copy, ++replaced;
  ASSERT_FALSE(validate_mesh(in).is_solid());
  const RepairResult r = repair_mesh(in);
  EXPECT_TRUE(validate_mesh(r.mesh).is_solid());
  EXPECT_EQ(r.report.vertices_merged, 1u);
  EXPECT_TRUE(r.report.holes.empty());
  EXPECT_NEAR(r.report.after.volume, 1, 1e-8);
  // With the relative weld off, nothing is merged (the cut closes the crack exactly instead).
  RepairOptions exact_only;
  exact_only.weld_relative = 0;
  const RepairResult e = repair_mesh(in, exact_only);
  EXPECT_EQ(e.report.vertices_merged, 0u);
  EXPECT_TRUE(validate_mesh(e.mesh).is_solid());
}

TEST(Repair, HoleFillingCanBeRefused) {
  TriMesh in = make_box({0, 0, 0}, {1, 1, 1});
  in.triangles.pop_back();
  in.origins.clear();
  RepairOptions o;
  o.fill_holes = false;
  EXPECT_THROW(repair_mesh(in, o), InputError);
}

TEST(Repair, CubeWithOneFlippedTriangle) {
  TriMesh in = make_box({0, 0, 0}, {1, 1, 1});
  std::swap(in.triangles[5][1], in.triangles[5][2]);
  const RepairResult r = repair_mesh(in);
  expect_exact_solid(in, r);
  EXPECT_NEAR(r.report.after.volume, 1, 1e-12);
  EXPECT_EQ(r.report.triangles_turned, 1u);
}

TEST(Repair, InsideOutCubeIsTurnedButACavityIsKept) {
  TriMesh out = make_box({0, 0, 0}, {1, 1, 1});
  for (Triangle& t : out.triangles) std::swap(t[1], t[2]);
  RepairResult r = repair_mesh(out);
  expect_exact_solid(out, r);
  EXPECT_NEAR(r.report.after.volume, 1, 1e-12);
  EXPECT_EQ(r.report.shells_turned, 1u);
  // A hollow box: the inner shell faces inward by right.
  TriMesh cavity = make_box({1, 1, 1}, {2, 2, 2});
  for (Triangle& t : cavity.triangles) std::swap(t[1], t[2]);
  const TriMesh hollow = join({make_box({0, 0, 0}, {3, 3, 3}), cavity});
  // A valid solid already: nothing changes.
  r = repair_mesh(hollow);
  EXPECT_FALSE(r.report.changed);
  EXPECT_NEAR(r.report.after.volume, 26, 1e-12);
}

TEST(Repair, TwoCubesSharingAnEdgeAreSeparated) {
  const TriMesh in = join({make_box({0, 0, 0}, {1, 1, 1}), make_box({1, 1, 0}, {2, 2, 1})});
  ASSERT_FALSE(validate_mesh(in).is_solid());
  const RepairResult r = repair_mesh(in);
  expect_exact_solid(in, r);
  EXPECT_NEAR(r.report.after.volume, 2, 1e-8);
  EXPECT_EQ(r.report.vertices_separated, 2u);
}

TEST(Repair, TwoCubesSharingACorner) {
  const TriMesh in = join({make_box({0, 0, 0}, {1, 1, 1}), make_box({1, 1, 1}, {2, 2, 2})});
  const RepairResult r = repair_mesh(in);
  expect_exact_solid(in, r);
  EXPECT_NEAR(r.report.after.volume, 2, 1e-8);
}

TEST(Repair, DuplicatedShellIsOneSolid) {
  const TriMesh box = make_box({0, 0, 0}, {1, 2, 3});
  const TriMesh in = join({box, box});
  const RepairResult r = repair_mesh(in);
  expect_exact_solid(in, r);
  EXPECT_NEAR(r.report.after.volume, 6, 1e-12);
  EXPECT_EQ(r.mesh.triangles.size(), 12u);
}

TEST(Repair, CrossingTetrahedra) {
  TriMesh a;
  a.vertices = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 2}};
  a.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const TriMesh b = moved(a, {0.5, 0.4, 0.3});
  const TriMesh in = join({a, b});
  const RepairResult r = repair_mesh(in);
  expect_exact_solid(in, r);
  // The union's volume, from the winding number of the input at random points (an oracle that
  // does not share the repair's code), against the output's.
  const MeshDistance md(in);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 2.5);
  int inside = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) inside += md.winding_number_exact({u(rng), u(rng), u(rng)}) >= 0.5;
  const double mc = 2.5 * 2.5 * 2.5 * inside / n;
  EXPECT_NEAR(r.report.after.volume, mc, 0.02 * mc);
  EXPECT_LT(r.report.after.volume, 8.0 / 6 * 2);
  EXPECT_GT(r.report.after.volume, 8.0 / 6);
}

// Random unions of boxes and spheres: the output's volume equals the union's, and so does its
// inside, tested at random points against the input's winding number.
TEST(Repair, RandomUnionsOfBoxesAndSpheres) {
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> pos(-1, 1), size(0.3, 1.2);
  for (int trial = 0; trial < 6; ++trial) {
    std::vector<Box3> boxes;
    TriMesh in;
    for (int k = 0; k < 4; ++k) {
      const Vec3 lo{pos(rng), pos(rng), pos(rng)};
      const Box3 b{lo, lo + Vec3{size(rng), size(rng), size(rng)}};
      boxes.push_back(b);
      in = join({in, make_box(b.lo, b.hi)});
    }
    const bool with_spheres = trial % 2 == 1;
    if (with_spheres)
      for (int k = 0; k < 2; ++k) in = join({in, moved(test::make_sphere(2, size(rng) * 0.7), {pos(rng), pos(rng), pos(rng)})});
    SCOPED_TRACE("trial " + std::to_string(trial));
    const RepairResult r = repair_mesh(in);
    expect_exact_solid(in, r);
    if (!with_spheres) {
      EXPECT_NEAR(r.report.after.volume, union_volume(boxes), 1e-9 * union_volume(boxes));
    } else {
      const MeshDistance before(in), after(r.mesh);
      std::uniform_real_distribution<double> p(-1.5, 2.5);
      int differ = 0;
      for (int i = 0; i < 4000; ++i) {
        const Vec3 q{p(rng), p(rng), p(rng)};
        differ += (before.winding_number_exact(q) >= 0.5) != (after.winding_number_exact(q) >= 0.5);
      }
      EXPECT_EQ(differ, 0);
    }
  }
}

// Every coordinate, whatever the count (a vectorizing compiler once rounded only z of the last few).
TEST(Repair, RoundVerticesToFloatRoundsEveryCoordinate) {
  for (std::size_t n = 1; n <= 9; ++n) {
    TriMesh m;
    for (std::size_t i = 0; i < n; ++i) m.vertices.push_back({0.1 + i, 0.2 + i, 0.3 + i});
    round_vertices_to_float(m);
    for (const Vec3& v : m.vertices)
      for (double c : {v.x, v.y, v.z}) EXPECT_EQ(c, double(static_cast<float>(c))) << n;
  }
}

// STL stores floats: with float_coordinates every output coordinate is a float and the solid is
// valid as such (spheres crossing at arbitrary angles make cut points no float can hold).
TEST(Repair, FloatCoordinatesForStl) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> pos(-0.6, 0.6), radius(0.5, 1.0);
  for (int trial = 0; trial < 4; ++trial) {
    TriMesh in;
    for (int k = 0; k < 3; ++k) in = join({in, moved(test::make_sphere(2, radius(rng)), {pos(rng), pos(rng), pos(rng)})});
    RepairOptions o;
    o.float_coordinates = true;
    const RepairResult r = repair_mesh(in, o);
    for (const Vec3& v : r.mesh.vertices) {
      EXPECT_EQ(v.x, double(static_cast<float>(v.x)));
      EXPECT_EQ(v.y, double(static_cast<float>(v.y)));
      EXPECT_EQ(v.z, double(static_cast<float>(v.z)));
    }
    EXPECT_TRUE(validate_mesh(r.mesh).is_solid()) << validate_mesh(r.mesh).summary();
    // Written as STL and read back, still the same valid solid.
    const TriMesh back = read_mesh_from_memory(write_mesh_to_string(r.mesh, MeshFormat::Stl), "back.stl");
    EXPECT_TRUE(validate_mesh(back).is_solid());
  }
}

TEST(Repair, RefusesWhatBoundsNothing) {
  TriMesh sheet;
  sheet.name = "sheet.stl";
  sheet.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  sheet.triangles = {{0, 1, 2}, {0, 2, 1}};
  try {
    (void)repair_mesh(sheet);
    ADD_FAILURE() << "a double-sided triangle was repaired";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "sheet.stl");
    EXPECT_NE(std::string(e.what()).find("no volume"), std::string::npos) << e.what();
  }
  EXPECT_THROW(repair_mesh(TriMesh{}), InputError);
}

TEST(Repair, ValidSolidIsLeftAlone) {
  const TriMesh in = test::make_sphere(2);
  const RepairResult r = repair_mesh(in);
  EXPECT_FALSE(r.report.changed);
  EXPECT_EQ(r.mesh.triangles.size(), in.triangles.size());
}

TEST(Repair, ReportsAsJson) {
  const TriMesh in = join({make_box({0, 0, 0}, {2, 2, 2}), make_box({1, 1, 1}, {3, 3, 3})});
  const RepairResult r = repair_mesh(in);
  const std::string j = repair_report_json(r.report);
  EXPECT_NE(j.find("\"crossing_pairs\": "), std::string::npos);
  EXPECT_NE(j.find("\"exact\": true"), std::string::npos);
  EXPECT_NE(format_repair_report(r.report).find("valid solid"), std::string::npos);
}

// Random soups (crossing, touching, coplanar on a coarse lattice, open): a valid solid or an
// InputError, never anything else.
TEST(Repair, RandomSoupsGiveASolidOrAReason) {
  std::mt19937_64 rng(99);
  std::uniform_int_distribution<int> lattice(0, 4), count(4, 24);
  for (int trial = 0; trial < 40; ++trial) {
    TriMesh soup;
    soup.name = "soup" + std::to_string(trial);
    const int n = count(rng);
    for (int t = 0; t < n; ++t) {
      for (int k = 0; k < 3; ++k) soup.vertices.push_back({double(lattice(rng)), double(lattice(rng)), double(lattice(rng))});
      const auto b = static_cast<std::uint32_t>(soup.vertices.size() - 3);
      soup.add_triangle(b, b + 1, b + 2);
    }
    if (trial % 3 == 0) soup = join({soup, make_box({0.5, 0.5, 0.5}, {3, 2, 2.5})});
    SCOPED_TRACE(soup.name);
    RepairOptions o;
    o.remesh_resolution = 24;
    try {
      const RepairResult r = make_solid(soup, o);
      EXPECT_TRUE(validate_mesh(r.mesh).is_solid());
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), soup.name);
    }
  }
}

// An exact repair's output: every vertex on the input's surface (within 1e-9 of the diagonal),
// and inside where the input's winding number is at least 1/2, at random points of the box
// (the exact sum decides wherever the hierarchy's estimate is near 1/2).
void expect_same_solid(const TriMesh& input, const TriMesh& output) {
  const MeshDistance in(input), out(output);
  const Box3 box = bounding_box(input);
  const double diag = length(box.size());
  double worst = 0;
  for (const Vec3& p : output.vertices) worst = std::max(worst, in.unsigned_distance(p));
  EXPECT_LE(worst, 1e-9 * diag);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  int differ = 0;
  const auto inside = [](const MeshDistance& md, const Vec3& q) {
    double w = md.winding_number(q);
    if (std::fabs(w - 0.5) < 0.3) w = md.winding_number_exact(q);
    return w >= 0.5;
  };
  for (int i = 0; i < 20000; ++i) {
    const Vec3 q = box.lo + Vec3{u(rng) * box.size().x, u(rng) * box.size().y, u(rng) * box.size().z};
    differ += inside(in, q) != inside(out, q);
  }
  EXPECT_EQ(differ, 0);
}

// Every broken shared mesh: a valid solid, or a refusal that names the file and says why.
TEST(SharedMeshes, RepairEveryBrokenMesh) {
  FREP_REQUIRE_SHARED_MESHES();
  std::size_t broken = 0, repaired = 0;
  for (const auto& entry : std::filesystem::directory_iterator(test::shared_mesh_dir())) {
    const std::string path = entry.path().string();
    if (format_from_extension(path) == MeshFormat::Unknown) continue;
    TriMesh m;
    try {
      m = read_mesh(path);
    } catch (const InputError&) {
      continue;
    }
    if (validate_mesh(m).is_solid()) continue;
    ++broken;
    SCOPED_TRACE(path);
    RepairOptions o;
    o.remesh_resolution = 96;
    o.time_limit = 120;
    try {
      const RepairResult r = make_solid(m, o);
      EXPECT_TRUE(validate_mesh(r.mesh).is_solid());
      ++repaired;
      // Exact, and the winding number of the input as it was (no triangle or shell turned).
      if (r.report.exact && r.report.triangles_turned == 0 && r.report.shells_turned == 0) expect_same_solid(m, r.mesh);
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path);
      EXPECT_FALSE(e.detail().empty());
    }
  }
  EXPECT_GE(broken, 10u);
  EXPECT_GE(repaired * 10, broken * 8) << repaired << " of " << broken << " repaired";
}

}  // namespace
}  // namespace frep
