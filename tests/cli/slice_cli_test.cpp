// frep slice as a user runs it: G-code that passes the independent checker, the SVG and PNG
// pictures, settings from a file and the command line, and clear refusals that leave no file.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>

#include "cli_test_util.hpp"
#include "mesh_test_util.hpp"
#include "slice/gcode_checker.hpp"

namespace frep::test {
namespace {

const char* kPocket =
    "difference(box([-10, -8, 0], [10, 8, 10]), sphere(#{center: [0, 0, 10], radius: 6}))\n";

TEST(SliceCli, WritesGcodeThatPassesTheChecker) {
  ScratchDir d;
  write_text(d.path("part.rhai"), kPocket);
  const CliRun s = run_frep(d, "slice " + shell_quote(d.path("part.rhai")) + " -o " + shell_quote(d.path("part.gcode")));
  ASSERT_EQ(s.code, 0) << s.err;
  EXPECT_NE(s.out.find("layers: 50 of 0.2 mm"), std::string::npos) << s.out;
  const GcodeFacts f = read_gcode(read_text(d.path("part.gcode")));
  EXPECT_TRUE(f.problems.empty()) << f.problems.front();
  EXPECT_EQ(f.layer_z.size(), 50u);
  EXPECT_TRUE(f.has_shift);
}

TEST(SliceCli, SettingsFromFileSetAndOptionsInThatOrder) {
  ScratchDir d;
  write_text(d.path("part.rhai"), kPocket);
  write_text(d.path("printer.ini"), "# a printer\nlayer_height = 0.25\nline-width = 0.5\n; comment\nbed_x = 250\n");
  const std::string in = shell_quote(d.path("part.rhai")), out = shell_quote(d.path("p.gcode"));
  CliRun r = run_frep(d, "slice " + in + " -o " + out + " --config " + shell_quote(d.path("printer.ini")));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("layers: 40 of 0.25 mm"), std::string::npos) << r.out;
  GcodeLimits lim;
  lim.layer_height = 0.25;
  lim.bed_x = 250;
  GcodeFacts f = read_gcode(read_text(d.path("p.gcode")), lim);
  EXPECT_TRUE(f.problems.empty()) << f.problems.front();
  EXPECT_NEAR(f.shift[0], 125, 1e-6);  // centred on the 250 mm bed
  // --set after the file, options after --set.
  r = run_frep(d, "slice " + in + " -o " + out + " --config " + shell_quote(d.path("printer.ini")) +
                      " --set layer_height=0.1 --layer-height 0.2");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("layers: 50 of 0.2 mm"), std::string::npos) << r.out;
  r = run_frep(d, "slice --list-settings");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("layer_height = 0.2\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("infill_pattern = lines\n"), std::string::npos) << r.out;
}

TEST(SliceCli, BadSettingsNameTheFileAndLine) {
  ScratchDir d;
  write_text(d.path("part.rhai"), kPocket);
  write_text(d.path("bad.ini"), "layer_height = 0.2\nnozzle = 0.4\n");
  const std::string in = shell_quote(d.path("part.rhai")), out = shell_quote(d.path("p.gcode"));
  CliRun r = run_frep(d, "slice " + in + " -o " + out + " --config " + shell_quote(d.path("bad.ini")));
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("bad.ini:2: unknown setting 'nozzle'"), std::string::npos) << r.err;
  write_text(d.path("bad.ini"), "infill = 150\n");
  r = run_frep(d, "slice " + in + " -o " + out + " --config " + shell_quote(d.path("bad.ini")));
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("bad.ini:1: infill must be a number from 0 to 100"), std::string::npos) << r.err;
  r = run_frep(d, "slice " + in + " -o " + out + " --line-width 0.1");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("line width"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d.path("p.gcode")));
}

TEST(SliceCli, SvgOfTheLayersAndAPngPreview) {
  ScratchDir d;
  write_text(d.path("part.rhai"), kPocket);
  const CliRun r = run_frep(d, "slice " + shell_quote(d.path("part.rhai")) + " -o " + shell_quote(d.path("layers.svg")) +
                                   " --preview " + shell_quote(d.path("layer.png")) + " --preview-layer 7");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string svg = read_text(d.path("layers.svg"));
  const std::regex group("<g id=\"layer-[0-9]+\"");
  EXPECT_EQ(std::distance(std::sregex_iterator(svg.begin(), svg.end(), group), std::sregex_iterator()), 50);
  EXPECT_NE(svg.find("<g id=\"layer-7\" inkscape:groupmode=\"layer\" inkscape:label=\"layer 7 z=1.6000\" transform=\"scale(1,-1)\">"),
            std::string::npos);
  EXPECT_EQ(read_text(d.path("layer.png")).substr(1, 3), "PNG");
  const CliRun bad = run_frep(d, "slice " + shell_quote(d.path("part.rhai")) + " -o " + shell_quote(d.path("x.gcode")) +
                                     " --preview " + shell_quote(d.path("l.png")) + " --preview-layer 50");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("the part has 50 layers (0 to 49)"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(d.path("x.gcode")));
}

TEST(SliceCli, RefusesClearlyAndLeavesNoFile) {
  ScratchDir d;
  const std::string out = shell_quote(d.path("out.gcode"));
  struct Case {
    const char* script;
    const char* message;
    const char* extra;
  } cases[] = {
      {"sphere(#{center: [0, 0, 0], radius: 120})\n", "bigger than the 220.0 x 220.0 mm bed", ""},
      {"sphere(#{center: [0, 0, 0], radius: 140})\n", "more than the printer's 250.0 mm", ""},
      {"z\n", "looks unbounded", ""},
      {"sphere(#{center: [0, 0, 0], radius: 1}) + 5\n", "not negative anywhere", ""},
      {"sphere(#{center: [0, 0, 0], radius: 0.05})\n", "thinner than half a layer", ""},
      {"sphere(#{center: [0, 0, 0], radius: 5})\n", "off the 220.0 x 220.0 mm bed", " --keep-position"},
  };
  for (const Case& c : cases) {
    write_text(d.path("in.rhai"), c.script);
    const CliRun r = run_frep(d, "slice " + shell_quote(d.path("in.rhai")) + " -o " + out + c.extra);
    EXPECT_EQ(r.code, 1) << c.script << r.err;
    EXPECT_NE(r.err.find("in.rhai"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.script << r.err;
    EXPECT_FALSE(fs::exists(d.path("out.gcode"))) << c.script;
  }
  write_text(d.path("in.rhai"), kPocket);
  CliRun r = run_frep(d, "slice " + shell_quote(d.path("in.rhai")) + " -o " + shell_quote(d.path("out.stl")));
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("unknown output format"), std::string::npos) << r.err;
  r = run_frep(d, "slice " + shell_quote(d.path("in.rhai")) + " -o " + shell_quote(d.path("no/such/dir/out.gcode")));
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("does not exist"), std::string::npos) << r.err;
}

// A lattice is unbounded: --bounds gives the part, cut there, with gyroid infill in the skin.
TEST(SliceCli, LatticeCutByBounds) {
  ScratchDir d;
  write_text(d.path("lattice.rhai"), "gyroid_sheet(6, 1.2)\n");
  const CliRun r = run_frep(d, "slice " + shell_quote(d.path("lattice.rhai")) + " -o " + shell_quote(d.path("l.gcode")) +
                                   " --bounds -8,-8,0,8,8,3 --infill-pattern gyroid");
  ASSERT_EQ(r.code, 0) << r.err;
  const GcodeFacts f = read_gcode(read_text(d.path("l.gcode")));
  EXPECT_TRUE(f.problems.empty()) << f.problems.front();
  EXPECT_EQ(f.layer_z.size(), 15u);
  // Cut at the bounds: the part spans 16 mm, centred.
  EXPECT_NE(r.out.find("part: 16.00 x 16.00 x 3.00 mm"), std::string::npos) << r.out;
}

TEST(SliceCli, SharedMeshesSliceOrAreRefusedWithTheReason) {
  FREP_REQUIRE_SHARED_MESHES();
  ScratchDir d;
  CliRun r = run_frep(d, "slice " + shell_quote(shared_mesh_dir() + "/cube_unit_bin.stl") + " -o " + shell_quote(d.path("c.gcode")) +
                         " --line-width 0.42 --layer-height 0.1");
  ASSERT_EQ(r.code, 0) << r.err;
  GcodeLimits lim;
  lim.layer_height = 0.1;
  const GcodeFacts f = read_gcode(read_text(d.path("c.gcode")), lim);
  EXPECT_TRUE(f.problems.empty()) << f.problems.front();
  EXPECT_EQ(f.layer_z.size(), 10u);
  r = run_frep(d, "slice " + shell_quote(shared_mesh_dir() + "/self_intersect_A.obj") + " -o " + shell_quote(d.path("s.gcode")));
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("self-intersections"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d.path("s.gcode")));
}

}  // namespace
}  // namespace frep::test

namespace frep::test {
namespace {

// --scale below 1 makes the field change faster than the input's own Lipschitz bound: the bound
// used must follow (it once did not, and tiles crossed by the surface were settled).
TEST(SliceCli, ScaleAndAWrongLipschitzBound) {
  ScratchDir d;
  write_text(d.path("part.rhai"), kPocket);
  const std::string in = shell_quote(d.path("part.rhai")), out = shell_quote(d.path("p.gcode"));
  CliRun r = run_frep(d, "slice " + in + " -o " + out + " --scale 0.5");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("part: 10.00 x 8.00 x 5.00 mm"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("layers: 25 of 0.2 mm"), std::string::npos) << r.out;
  EXPECT_TRUE(read_gcode(read_text(d.path("p.gcode"))).problems.empty());
  // A bound far too small is the user's mistake, said as such (not an internal error).
  r = run_frep(d, "slice " + in + " -o " + out + " --lipschitz 0.05");
  EXPECT_NE(r.code, 3) << r.err;
  if (r.code != 0) {
    EXPECT_NE(r.err.find("--lipschitz"), std::string::npos) << r.err;
  }
  r = run_frep(d, "slice " + in + " -o " + shell_quote(d.path("l.svg")) + " --svg-layers 5abc");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("expected N or FIRST-LAST"), std::string::npos) << r.err;
  r = run_frep(d, "slice " + in + " -o " + out + " --set retract_length=0");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(read_text(d.path("p.gcode")).find("E-0.00000"), std::string::npos);
}

}  // namespace
}  // namespace frep::test
