// Command-line options that change a result, each shown to have the effect `--help` and the docs
// give it, by running `frep` as a user would on small inputs written here (and the shipped
// bracket): `clearance --tolerance / --max-boxes / --bounds` (the "touching" answer included),
// `sample --sign / --weld-tolerance / --threads`, `convert --weld-tolerance / --threads`,
// `mesh --snap-iterations` and `export --line-width`. Each option's bad values are refused with
// exit 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "cli_test_util.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/expr/expr.hpp"
#include "frep/script/load.hpp"
#include "frep/io/npy.hpp"
#include "frep/io/vm.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/sample/grid.hpp"
#include "mesh_test_util.hpp"

namespace frep {
namespace {

using test::CliRun;

const std::string kBracket = FREP_SOURCE_DIR "/examples/bracket.obj";

class OptionEffects : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return dir_.path(name); }
  CliRun run(const std::string& args) { return test::run_frep(dir_, args); }
  std::string q(const std::string& name) const { return test::shell_quote(path(name)); }

  // A ball of radius r at (cx, 0, 0), as a .vm file.
  std::string ball(const std::string& name, float cx, float r) {
    Graph g;
    save_vm(path(name), g, (sqrt(square(g.x() - cx) + square(g.y()) + square(g.z())) - r).id());
    return q(name);
  }
  // The box [-1, 1]^3 with every triangle's corners its own, each moved by up to 1e-9: open
  // (36 boundary edges) until welded within a tolerance above 2e-9.
  std::string cracked_box(const std::string& name) {
    const TriMesh box = test::make_box();
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> jitter(-1e-9, 1e-9);
    std::string obj;
    char line[128];
    for (std::size_t t = 0; t < box.num_triangles(); ++t)
      for (int k = 0; k < 3; ++k) {
        const Vec3 p = box.corner(t, k);
        std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", p.x + jitter(rng), p.y + jitter(rng), p.z + jitter(rng));
        obj += line;
      }
    for (std::size_t t = 0; t < box.num_triangles(); ++t) obj += "f " + std::to_string(3 * t + 1) + " " +
                                                                std::to_string(3 * t + 2) + " " + std::to_string(3 * t + 3) + "\n";
    test::write_text(path(name), obj);
    return q(name);
  }

  test::ScratchDir dir_;
};

// The exact signed distance of the box [-1, 1]^3.
double box_distance(const Vec3& p) {
  const double qx = std::fabs(p.x) - 1, qy = std::fabs(p.y) - 1, qz = std::fabs(p.z) - 1;
  const double ox = std::max(qx, 0.0), oy = std::max(qy, 0.0), oz = std::max(qz, 0.0);
  return std::sqrt(ox * ox + oy * oy + oz * oz) + std::min(std::max({qx, qy, qz}), 0.0);
}

// ---------------------------------------------------------------------------------------------
// frep clearance

// What `frep clearance` printed: the value (the gap, or minus the depth), and the bound line.
struct Clearance {
  bool parsed = false;
  double value = NAN, lower_bound = NAN;
  std::size_t boxes = 0;
  bool touching = false, out_of_boxes = false;
};

Clearance parse_clearance(const std::string& out) {
  Clearance c;
  double v = NAN;
  const std::size_t gap = out.find("gap: "), depth = out.find("interference: depth ");
  if (gap != std::string::npos && std::sscanf(out.c_str() + gap, "gap: %lf", &v) == 1) c.value = v;
  else if (depth != std::string::npos && std::sscanf(out.c_str() + depth, "interference: depth %lf", &v) == 1) c.value = -v;
  const std::size_t at = out.find("proven lower bound of A + B: ");
  if (at != std::string::npos &&
      std::sscanf(out.c_str() + at, "proven lower bound of A + B: %lf (%zu boxes", &c.lower_bound, &c.boxes) == 2)
    c.parsed = std::isfinite(c.value);
  c.touching = out.find("(within --tolerance: touching)") != std::string::npos;
  c.out_of_boxes = out.find("(--max-boxes narrows it)") != std::string::npos;
  return c;
}

// Two balls of radius 0.5 overlapping by 0.01: the depth is reported as such until --tolerance
// exceeds it, then as touching; the search stops as soon as the value found is within the
// tolerance of the proven bound, so a wider tolerance examines fewer boxes. A gap is a gap
// whatever the tolerance. Two meshes: a shallow crossing is an interference "shallower than
// --tolerance", and faces lying on each other touch.
TEST_F(OptionEffects, ClearanceToleranceSaysTouchingAndStopsTheSearch) {
  const std::string a = ball("a.vm", 0, 0.5f), c = ball("c.vm", 0.99f, 0.5f), b = ball("b.vm", 1.01f, 0.5f);
  CliRun r = run("clearance -q " + a + " " + c);
  ASSERT_EQ(r.code, 0) << r.err;
  Clearance d = parse_clearance(r.out);
  ASSERT_TRUE(d.parsed) << r.out;
  EXPECT_NEAR(d.value, -0.01, 1e-6) << r.out;
  EXPECT_FALSE(d.touching) << r.out;
  // Below the depth: still the depth (the search runs out of boxes before proving it to 0.005).
  r = run("clearance -q " + a + " " + c + " --tolerance 0.005");
  ASSERT_EQ(r.code, 0) << r.err;
  d = parse_clearance(r.out);
  EXPECT_NEAR(d.value, -0.01, 1e-6) << r.out;
  EXPECT_FALSE(d.touching) << r.out;
  std::size_t previous_boxes = SIZE_MAX;
  for (double tolerance : {0.02, 0.05, 0.1}) {
    r = run("clearance -q " + a + " " + c + " --tolerance " + std::to_string(tolerance));
    ASSERT_EQ(r.code, 0) << r.err;
    d = parse_clearance(r.out);
    ASSERT_TRUE(d.parsed) << r.out;
    EXPECT_NEAR(d.value, -0.01, 1e-6) << r.out;
    EXPECT_TRUE(d.touching) << tolerance << ": " << r.out;
    // Stopped by the tolerance, not by running out of boxes: the bound is within it.
    EXPECT_FALSE(d.out_of_boxes) << tolerance << ": " << r.out;
    EXPECT_LE(d.lower_bound, d.value) << r.out;
    EXPECT_LE(d.value - d.lower_bound, tolerance * (1 + 1e-5)) << tolerance << ": " << r.out;
    EXPECT_LT(d.boxes, previous_boxes) << tolerance << ": " << r.out;
    previous_boxes = d.boxes;
  }
  r = run("clearance -q " + a + " " + b + " --tolerance 0.05");
  ASSERT_EQ(r.code, 0) << r.err;
  d = parse_clearance(r.out);
  EXPECT_NEAR(d.value, 0.01, 1e-6) << r.out;
  EXPECT_EQ(r.out.find("touching"), std::string::npos) << r.out;
  // Two meshes: a box crossing the cube [-1, 1]^3 by 0.002 is an interference, said to be
  // shallower than a tolerance above that; one on its face touches (a gap of 0) at any tolerance.
  write_mesh(path("cube.obj"), test::make_box());
  write_mesh(path("crossing.obj"), test::make_box({0.998, -0.5, -0.5}, {3, 0.5, 0.5}));
  write_mesh(path("touching.obj"), test::make_box({1, -0.5, -0.5}, {3, 0.5, 0.5}));
  for (const char* tolerance : {"", " --tolerance 0.001", " --tolerance 0.01"}) {
    r = run("clearance -q " + q("cube.obj") + " " + q("crossing.obj") + tolerance);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("surfaces cross: "), std::string::npos) << r.out;
    EXPECT_NEAR(parse_clearance(r.out).value, -0.002, 1e-6) << r.out;
    EXPECT_EQ(r.out.find("(shallower than --tolerance)") != std::string::npos, std::string(tolerance).find("0.01") != std::string::npos)
        << tolerance << ": " << r.out;
    r = run("clearance -q " + q("cube.obj") + " " + q("touching.obj") + tolerance);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("gap: 0 (the surfaces touch; no interference deeper than --tolerance found)"), std::string::npos)
        << tolerance << ": " << r.out;
  }
  for (const char* bad : {"0", "-1", "nan", "x"}) EXPECT_EQ(run("clearance " + a + " " + c + " --tolerance " + bad).code, 2) << bad;
}

// --max-boxes N: the search examines at most N boxes (and says the bound is where it stopped);
// more boxes prove a bound at least as high, never above the value found.
TEST_F(OptionEffects, ClearanceMaxBoxesLimitsTheSearch) {
  const std::string a = ball("a.vm", 0, 0.5f), c = ball("c.vm", 0.99f, 0.5f);
  double previous_bound = -INFINITY;
  for (std::size_t n : {10, 100, 1000, 5000}) {
    const CliRun r = run("clearance -q " + a + " " + c + " --max-boxes " + std::to_string(n));
    ASSERT_EQ(r.code, 0) << r.err;
    const Clearance d = parse_clearance(r.out);
    ASSERT_TRUE(d.parsed) << r.out;
    EXPECT_GE(d.boxes, n) << r.out;
    EXPECT_LE(d.boxes, n + 1) << r.out;
    EXPECT_TRUE(d.out_of_boxes) << r.out;
    EXPECT_NEAR(d.value, -0.01, 1e-6) << r.out;
    EXPECT_LE(d.lower_bound, d.value) << r.out;
    EXPECT_GE(d.lower_bound, previous_bound) << r.out;
    previous_bound = d.lower_bound;
  }
  EXPECT_GT(previous_bound, -0.1);  // 5000 boxes bound the depth well
  for (const char* bad : {"0", "-5", "1.5", "x"}) EXPECT_EQ(run("clearance " + a + " " + c + " --max-boxes " + bad).code, 2) << bad;
}

// --bounds is the region searched: needed for an unbounded input (a half-space), and the answer
// is the minimum of A + B over it (a region away from where the balls meet gives a gap).
TEST_F(OptionEffects, ClearanceBoundsAreTheRegionSearched) {
  const std::string a = ball("a.vm", 0, 0.5f), c = ball("c.vm", 0.99f, 0.5f);
  {
    Graph g;
    save_vm(path("half.vm"), g, (2.0f - g.x()).id());  // inside where x > 2
  }
  CliRun r = run("clearance -q " + a + " " + q("half.vm"));
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.err.find("--bounds"), std::string::npos) << r.err;
  r = run("clearance -q " + a + " " + q("half.vm") + " --bounds -1,-1,-1,3,1,1");
  ASSERT_EQ(r.code, 0) << r.err;
  Clearance d = parse_clearance(r.out);
  ASSERT_TRUE(d.parsed) << r.out;
  EXPECT_NEAR(d.value, 1.5, 1e-5) << r.out;
  EXPECT_NE(r.out.find(", 2, 0, 0 on "), std::string::npos) << r.out;  // the half-space's nearest point
  // Around the contact: the depth, as without bounds.
  r = run("clearance -q " + a + " " + c + " --bounds 0.3,-0.3,-0.3,0.7,0.3,0.3");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NEAR(parse_clearance(r.out).value, -0.01, 1e-6) << r.out;
  // Only x in [-0.6, -0.4] (behind the first ball's centre): A + B = |p| + |p - (0.99, 0, 0)| - 1
  // is smallest on the axis at x = -0.4, where it is 0.4 + 1.39 - 1 = 0.79.
  r = run("clearance -q " + a + " " + c + " --bounds -0.6,-0.1,-0.1,-0.4,0.1,0.1");
  ASSERT_EQ(r.code, 0) << r.err;
  d = parse_clearance(r.out);
  ASSERT_TRUE(d.parsed) << r.out;
  EXPECT_NEAR(d.value, 0.79, 1e-5) << r.out;
  EXPECT_GE(d.lower_bound, 0.79 - 1e-4 - 1e-6) << r.out;  // proven within the default tolerance
  for (const char* bad : {"0,0,0,1,1", "0,0,0,1,1,nan", "0,0,0,-1,1,1"})
    EXPECT_EQ(run("clearance " + a + " " + c + " --bounds " + bad).code, 2) << bad;
}

// ---------------------------------------------------------------------------------------------
// frep sample

// The .npy a run wrote.
NpyArray npy(const std::string& file) { return read_npy(file); }

// --sign picks the sign of valid solids: on one both are exact, so the values are the same,
// while the method differs (the closest point transform needs pseudonormals: with the winding
// number grids take one query per sample, and --method cpt is refused). A mesh that is not a
// valid solid always gets the winding number, whatever --sign says.
TEST_F(OptionEffects, SampleSignPicksTheSignMethodOfSolids) {
  const std::string bracket = test::shell_quote(kBracket);
  CliRun pseudo = run("sample " + bracket + " --grid 20 -o " + q("p.npy"));
  CliRun winding = run("sample " + bracket + " --grid 20 -o " + q("w.npy") + " --sign winding");
  ASSERT_EQ(pseudo.code, 0) << pseudo.err;
  ASSERT_EQ(winding.code, 0) << winding.err;
  EXPECT_NE(pseudo.out.find("closest point transform"), std::string::npos) << pseudo.out;
  EXPECT_NE(pseudo.out.find("pseudonormal signs"), std::string::npos) << pseudo.out;
  EXPECT_NE(winding.out.find("one oracle query per sample, winding-number signs"), std::string::npos) << winding.out;
  const NpyArray p = npy(path("p.npy")), w = npy(path("w.npy"));
  EXPECT_EQ(p.data, w.data);
  EXPECT_LT(*std::min_element(p.data.begin(), p.data.end()), 0);  // both signs occur
  EXPECT_GT(*std::max_element(p.data.begin(), p.data.end()), 0);
  CliRun r = run("sample " + bracket + " --grid 20 -o " + q("c.npy") + " --sign winding --method cpt");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("pseudonormal"), std::string::npos) << r.err;
  // Points: the same rows, the sign method named.
  pseudo = run("sample " + bracket + " --near-surface 2000 --sigma 0.01 -o " + q("pp.npy"));
  winding = run("sample " + bracket + " --near-surface 2000 --sigma 0.01 -o " + q("wp.npy") + " --sign winding");
  ASSERT_EQ(pseudo.code, 0) << pseudo.err;
  ASSERT_EQ(winding.code, 0) << winding.err;
  EXPECT_NE(pseudo.out.find("(pseudonormal signs)"), std::string::npos) << pseudo.out;
  EXPECT_NE(winding.out.find("(winding-number signs)"), std::string::npos) << winding.out;
  EXPECT_EQ(npy(path("pp.npy")).data, npy(path("wp.npy")).data);
  // Not a solid: the winding number either way.
  TriMesh open = test::make_box();
  open.triangles.pop_back(), open.origins.pop_back();
  write_mesh(path("open.obj"), open);
  for (const char* sign : {"pseudonormal", "winding"}) {
    r = run("sample " + q("open.obj") + " --grid 12 -o " + q(std::string(sign) + ".npy") + " --sign " + sign);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("winding-number signs"), std::string::npos) << sign << ": " << r.out;
  }
  EXPECT_EQ(npy(path("pseudonormal.npy")).data, npy(path("winding.npy")).data);
  EXPECT_EQ(run("sample " + bracket + " --grid 8 -o " + q("x.npy") + " --sign tets").code, 2);
}

// --weld-tolerance merges vertices closer than it first: a box whose triangles have their own
// corners 1e-9 apart is open (signs from the winding number, queries only) until welded within
// 1e-6, then a valid solid (pseudonormal signs, the closest point transform); a tolerance below
// the cracks leaves it open. Every grid is the box's distance.
TEST_F(OptionEffects, SampleWeldToleranceClosesCracks) {
  const std::string box = cracked_box("cracked.obj");
  const GridSpec grid = cube_grid(Box3{{-1.5, -1.5, -1.5}, {1.5, 1.5, 1.5}}, 9);
  const auto check_values = [&](const std::string& file, const char* what) {
    const NpyArray a = npy(path(file));
    ASSERT_EQ(a.data.size(), grid.size()) << what;
    for (int i = 0; i < 9; ++i)
      for (int j = 0; j < 9; ++j)
        for (int k = 0; k < 9; ++k) {
          const Vec3 p{grid.coord(0, i), grid.coord(1, j), grid.coord(2, k)};
          ASSERT_NEAR(a.data[grid.index(i, j, k)], box_distance(p), 1e-6) << what << " at " << i << " " << j << " " << k;
        }
  };
  const std::string bounds = " --bounds -1.5,-1.5,-1.5,1.5,1.5,1.5";
  CliRun r = run("sample " + box + " --grid 9 -o " + q("open.npy") + bounds);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("not a solid: 36 open"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("one oracle query per sample, winding-number signs"), std::string::npos) << r.out;
  check_values("open.npy", "unwelded");
  EXPECT_EQ(run("sample " + box + " --grid 9 -o " + q("x.npy") + " --method cpt" + bounds).code, 1);
  r = run("sample " + box + " --grid 9 -o " + q("tiny.npy") + " --weld-tolerance 1e-12" + bounds);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("not a solid"), std::string::npos) << r.err;
  r = run("sample " + box + " --grid 9 -o " + q("welded.npy") + " --weld-tolerance 1e-6 --method cpt" + bounds);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find("not a solid"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("closest point transform"), std::string::npos) << r.out;
  check_values("welded.npy", "welded");
  for (const char* bad : {"-1", "nan", "x"}) EXPECT_EQ(run("sample " + box + " --grid 4 -o " + q("x.npy") + " --weld-tolerance " + bad).code, 2) << bad;
}

// --threads: the same bytes on 1 and 2 threads, for every kind of output.
TEST_F(OptionEffects, SampleThreadsLeaveTheResultAlone) {
  const std::string bracket = test::shell_quote(kBracket);
  ASSERT_EQ(run("convert " + bracket + " -q -o " + q("bracket.frep")).code, 0);
  const std::string runs[] = {
      bracket + " --grid 24",
      bracket + " --grid 24 --method queries",
      bracket + " --grid 24 --truncate 0.05",
      bracket + " --points 3000 --seed 4",
      bracket + " --near-surface 3000 --sigma 0.01",
      q("bracket.frep") + " --grid 24",
      q("bracket.frep") + " --near-surface 500 --sigma 0.01",
  };
  for (const std::string& args : runs) {
    ASSERT_EQ(run("sample " + args + " -q --threads 1 -o " + q("one.npy")).code, 0) << args;
    ASSERT_EQ(run("sample " + args + " -q --threads 2 -o " + q("two.npy")).code, 0) << args;
    EXPECT_EQ(test::read_text(path("one.npy")), test::read_text(path("two.npy"))) << args;
  }
  for (const char* bad : {"-1", "1025", "x"}) EXPECT_EQ(run("sample " + bracket + " --grid 4 -o " + q("x.npy") + " --threads " + bad).code, 2) << bad;
}

// ---------------------------------------------------------------------------------------------
// frep convert

// --weld-tolerance: the cracked box is refused (naming the file and the open edges) until welded
// within a tolerance above its cracks; then its expression is the box's distance.
TEST_F(OptionEffects, ConvertWeldToleranceClosesCracks) {
  const std::string box = cracked_box("cracked.obj");
  for (const char* tolerance : {"", " --weld-tolerance 1e-12"}) {
    const CliRun r = run("convert " + box + " -o " + q("box.vm") + tolerance);
    EXPECT_EQ(r.code, 1) << tolerance;
    EXPECT_NE(r.err.find("cracked.obj"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("open"), std::string::npos) << r.err;
  }
  const CliRun r = run("convert " + box + " -q -o " + q("box.vm") + " --weld-tolerance 1e-6");
  ASSERT_EQ(r.code, 0) << r.err;
  const Model m = load_expression(path("box.vm"));
  const Tape t = Tape::compile(*m.graph, m.root);
  PointEvaluator pe;
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u(-1.6f, 1.6f);
  for (int i = 0; i < 500; ++i) {
    const float x = u(rng), y = u(rng), z = u(rng);
    ASSERT_NEAR(pe.eval(t, x, y, z), box_distance({x, y, z}), 1e-6) << x << " " << y << " " << z;
  }
}

// --threads (the check's workers): the same files on 1 and 2 threads.
TEST_F(OptionEffects, ConvertThreadsLeaveTheResultAlone) {
  const std::string bracket = test::shell_quote(kBracket);
  for (const char* ext : {".vm", ".frep"}) {
    ASSERT_EQ(run("convert " + bracket + " -q --threads 1 -o " + q(std::string("one") + ext)).code, 0);
    ASSERT_EQ(run("convert " + bracket + " -q --threads 2 -o " + q(std::string("two") + ext)).code, 0);
    EXPECT_EQ(test::read_text(path(std::string("one") + ext)), test::read_text(path(std::string("two") + ext))) << ext;
  }
  for (const char* bad : {"-1", "1025", "x"}) EXPECT_EQ(run("convert " + bracket + " -o " + q("x.vm") + " --threads " + bad).code, 2) << bad;
}

// ---------------------------------------------------------------------------------------------
// frep mesh

// --max-error: by default (`flat`) flat regions merge and nothing else: a box comes out as about
// its 12 triangles, every vertex on it; 0 is the uniform mesh of the grid; a bound, in cells or model
// units, simplifies too. Every output a valid solid with its vertices on the box's surface.
TEST_F(OptionEffects, MeshMaxErrorSimplifiesOnlyWhenAsked) {
  const std::string box_vm = path("box.vm");
  test::write_text(box_vm, "0 var-x\n1 var-y\n2 var-z\n3 abs 0\n4 abs 1\n5 abs 2\n6 const 0.5\n7 sub 3 6\n8 sub 4 6\n"
                           "9 sub 5 6\n10 max 7 8\n11 max 10 9\n");
  std::vector<std::string> files;
  for (const std::string opt : {"", "--max-error flat", "--max-error 0", "--max-error 0.05c", "--max-error 0.002"}) {
    files.push_back(path("box" + std::to_string(files.size()) + ".stl"));
    const CliRun r = run("mesh " + box_vm + " -q -r 32 --bounds -1,-1,-1,1,1,1 " + opt + " -o " + test::shell_quote(files.back()));
    ASSERT_EQ(r.code, 0) << opt << ": " << r.err;
  }
  EXPECT_EQ(test::read_text(files[0]), test::read_text(files[1])) << "the default is flat";
  const TriMesh uniform = read_mesh(files[2]);
  EXPECT_EQ(uniform.triangles.size(), 6u * 16 * 16 * 2) << "0: the uniform mesh";
  // A box's faces, two triangles each, and a few more where the grid's corner vertices sit a
  // millionth off the corners (the box's faces lie on grid planes here).
  EXPECT_LE(read_mesh(files[0]).triangles.size(), 24u) << "flat";
  for (std::size_t i = 0; i < files.size(); ++i) {
    const TriMesh m = read_mesh(files[i]);
    EXPECT_TRUE(validate_mesh(m).is_solid()) << files[i];
    if (i != 2) {
      EXPECT_LT(m.triangles.size() * 10, uniform.triangles.size()) << files[i] << ": flat faces merge";
    }
    for (const Vec3& v : m.vertices)
      EXPECT_NEAR(std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}), 0.5, 1e-5) << files[i];
  }
  const CliRun bad = run("mesh " + box_vm + " -q -r 32 --max-error flat0 -o " + test::shell_quote(path("bad.stl")));
  EXPECT_NE(bad.code, 0);
  EXPECT_NE(bad.err.find("flat or a number"), std::string::npos) << bad.err;
}

// --snap-iterations: Newton steps moving the snap method's vertices onto the surface. With none
// they stay where the voxels put them; each step brings them closer (the worst and the mean
// distance to the ball's surface fall); the vertices and triangles are as many (each quad's
// diagonal follows the moved corners). Dual contouring ignores it. Unsimplified (--max-error 0),
// so that the vertices are the snap's own.
TEST_F(OptionEffects, MeshSnapIterationsMoveVerticesOntoTheSurface) {
  const std::string ball_vm = ball("ball.vm", 0.1f, 0.6f);
  std::vector<TriMesh> meshes;
  for (int steps : {0, 1, 4}) {
    const std::string out = path("snap" + std::to_string(steps) + ".obj");
    const CliRun r = run("mesh " + ball_vm + " -q -r 16 --max-error 0 --method snap --snap-iterations " + std::to_string(steps) + " -o " +
                         test::shell_quote(out));
    ASSERT_EQ(r.code, 0) << r.err;
    meshes.push_back(read_mesh(out));
  }
  const double h = 1.2 / 16;  // the cell: the found bounds are the ball's box
  double previous_worst = INFINITY, previous_mean = INFINITY;
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    double worst = 0, sum = 0;
    for (const Vec3& v : meshes[i].vertices) {
      const double e = std::fabs(length(v - Vec3{0.1, 0, 0}) - 0.6);
      worst = std::max(worst, e), sum += e;
    }
    const double mean = sum / meshes[i].vertices.size();
    EXPECT_EQ(meshes[i].vertices.size(), meshes[0].vertices.size()) << i;
    EXPECT_EQ(meshes[i].triangles.size(), meshes[0].triangles.size()) << i;
    EXPECT_LT(worst, previous_worst) << i;
    EXPECT_LT(mean, previous_mean / (i == 1 ? 10 : 1.5)) << i;
    if (i == 0) {
      EXPECT_GT(worst, 0.3 * h);  // unsnapped: voxel positions, well off the surface
    }
    previous_worst = worst, previous_mean = mean;
  }
  for (const char* steps : {"0", "4"})
    ASSERT_EQ(run("mesh " + ball_vm + " -q -r 16 --snap-iterations " + std::string(steps) + " -o " + q(std::string("dc") + steps + ".obj")).code, 0);
  EXPECT_EQ(test::read_text(path("dc0.obj")), test::read_text(path("dc4.obj")));
  for (const char* bad : {"-1", "101", "x"}) EXPECT_EQ(run("mesh " + ball_vm + " -r 8 --method snap -o " + q("x.obj") + " --snap-iterations " + bad).code, 2) << bad;
}

// ---------------------------------------------------------------------------------------------
// frep export

// --line-width: a long sum wraps at the top level into lines no wider than the width (in
// characters of mathematics: a superscript counts as one), each full (the next term would not
// have fitted); narrower widths make more lines, and the mathematics is the same whatever the
// width. On the converted bracket too, narrower means more lines.
TEST_F(OptionEffects, ExportLineWidthWrapsLongSums) {
  std::string sum;
  for (int k = 1; k <= 40; ++k) sum += (k > 1 ? " + " : "") + std::string("square(x - ") + std::to_string(k) + ") * " + std::to_string(k + 1);
  test::write_text(path("sum.rhai"), "draw(" + sum + ");\n");
  const std::regex first(R"(^f\(x\) &= )"), continued(R"(^&\\qquad \{\} )"), end(R"( \\\\$)"), square(R"(\^\{2\})");
  const auto visible = [&](std::string line) {
    line = std::regex_replace(line, first, "");
    line = std::regex_replace(line, continued, "");
    line = std::regex_replace(line, end, "");
    return std::regex_replace(line, square, "2");
  };
  std::string previous_math;
  std::size_t previous_lines = SIZE_MAX, lines_at_20 = 0;
  for (int width : {20, 40, 80, 160}) {
    const std::string out = path("sum" + std::to_string(width) + ".tex");
    const CliRun r = run("export " + q("sum.rhai") + " -q -f latex --fragment --line-width " + std::to_string(width) + " -o " +
                         test::shell_quote(out));
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string tex = test::read_text(out);
    std::vector<std::string> lines;  // the display lines of the sum
    std::istringstream in(tex);
    for (std::string l; std::getline(in, l);)
      if (l.rfind("f(x) &=", 0) == 0 || l.rfind("&\\qquad", 0) == 0) lines.push_back(l);
    ASSERT_GE(lines.size(), 1u) << tex;
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const std::string v = visible(lines[i]);
      EXPECT_LE(v.size(), static_cast<std::size_t>(width)) << width << ": " << lines[i];
      if (i + 1 < lines.size()) {  // full: the next line's first term would not have fitted
        const std::string next = visible(lines[i + 1]);
        const std::size_t second = next.find(" + ", 1);
        const std::size_t term = second == std::string::npos ? next.size() : second;
        EXPECT_GT(v.size() + 1 + term, static_cast<std::size_t>(width)) << width << ": " << lines[i] << " / " << lines[i + 1];
      }
    }
    EXPECT_LE(lines.size(), previous_lines) << width;
    if (width == 20) lines_at_20 = lines.size();
    if (width == 160) {
      EXPECT_GT(lines_at_20, 4 * lines.size());
    }
    // The same mathematics, lines joined.
    const std::string math = std::regex_replace(tex.substr(tex.find("\\begin{align*}")), std::regex(R"( \\\\\n&\\qquad \{\} )"), " ");
    if (!previous_math.empty()) {
      EXPECT_EQ(math, previous_math) << width;
    }
    previous_math = math;
    previous_lines = lines.size();
  }
  const auto line_count = [&](int width) {
    const std::string out = path("bracket" + std::to_string(width) + ".tex");
    EXPECT_EQ(run("export " + test::shell_quote(kBracket) + " -q -f latex --fragment --line-width " + std::to_string(width) +
                  " -o " + test::shell_quote(out))
                  .code,
              0);
    const std::string tex = test::read_text(out);
    return std::count(tex.begin(), tex.end(), '\n');
  };
  EXPECT_GT(line_count(30), line_count(200));
  for (const char* bad : {"19", "10001", "x"})
    EXPECT_EQ(run("export " + q("sum.rhai") + " -f latex -o " + q("x.tex") + " --line-width " + bad).code, 2) << bad;
}

}  // namespace
}  // namespace frep
