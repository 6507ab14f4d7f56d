// frep repair and --repair end to end: two overlapping boxes in one OBJ come back as their union,
// which frep check accepts; every command that reads a mesh repairs it on request; failures
// exit 1 naming the file and write nothing.
#include <gtest/gtest.h>

#include <filesystem>

#include "cli_test_util.hpp"
#include "mesh_test_util.hpp"

namespace frep {
namespace {

namespace fs = std::filesystem;
using test::run_frep;
using test::ScratchDir;

// Two unit cubes, the second moved by (0.5, 0.5, 0.5): union volume 2 - 1/8.
const char* const kOverlapping =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n"
    "v .5 .5 .5\nv 1.5 .5 .5\nv .5 1.5 .5\nv 1.5 1.5 .5\nv .5 .5 1.5\nv 1.5 .5 1.5\nv .5 1.5 1.5\nv 1.5 1.5 1.5\n"
    "f 1 3 2\nf 2 3 4\nf 5 6 7\nf 6 8 7\nf 1 2 5\nf 2 6 5\nf 3 7 4\nf 4 7 8\nf 1 5 3\nf 3 5 7\nf 2 4 6\nf 4 8 6\n"
    "f 9 11 10\nf 10 11 12\nf 13 14 15\nf 14 16 15\nf 9 10 13\nf 10 14 13\nf 11 15 12\nf 12 15 16\nf 9 13 11\n"
    "f 11 13 15\nf 10 12 14\nf 12 16 14\n";

TEST(RepairCli, UnionOfOverlappingBoxesPassesCheck) {
  ScratchDir s;
  test::write_text(s.path("two.obj"), kOverlapping);
  EXPECT_EQ(run_frep(s, "check " + s.path("two.obj")).code, 4);
  const auto r = run_frep(s, "repair " + s.path("two.obj") + " -o " + s.path("one.stl") + " -q");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("exact"), std::string::npos) << r.out;
  const auto c = run_frep(s, "check " + s.path("one.stl"));
  EXPECT_EQ(c.code, 0) << c.out;
  EXPECT_NE(c.out.find("volume: 1.875"), std::string::npos) << c.out;
  const auto j = run_frep(s, "repair " + s.path("two.obj") + " -o " + s.path("one.obj") + " --json");
  ASSERT_EQ(j.code, 0) << j.err;
  EXPECT_NE(j.out.find("\"volume_after\": 1.875"), std::string::npos) << j.out;
}

TEST(RepairCli, CommandsRepairOnRequest) {
  ScratchDir s;
  const std::string in = s.path("two.obj");
  test::write_text(in, kOverlapping);
  // Refused without --repair, naming the file.
  auto r = run_frep(s, "mesh " + in + " -r 16 -o " + s.path("m.stl") + " -q");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find(in), std::string::npos) << r.err;
  r = run_frep(s, "mesh " + in + " -r 16 -o " + s.path("m.stl") + " -q --repair");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(run_frep(s, "check " + s.path("m.stl")).code, 0);
  r = run_frep(s, "convert " + in + " -o " + s.path("c.frep") + " -q --repair");
  EXPECT_EQ(r.code, 0) << r.err;
  r = run_frep(s, "offset " + in + " 0.1 -o " + s.path("o.stl") + " -r 16 -q --repair");
  EXPECT_EQ(r.code, 0) << r.err;
  r = run_frep(s, "render " + in + " --3d --size 64 -o " + s.path("r.png") + " -q --repair");
  EXPECT_EQ(r.code, 0) << r.err;
  r = run_frep(s, "sample " + in + " --points 100 -o " + s.path("s.npy") + " -q --repair");
  EXPECT_EQ(r.code, 0) << r.err;
  test::write_text(s.path("p.txt"), "0.25 0.25 0.25\n");
  r = run_frep(s, "sdf " + in + " -p " + s.path("p.txt") + " --repair");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("-0.25"), std::string::npos) << r.out;
}

TEST(RepairCli, WhatBoundsNothingIsRefusedAndNothingWritten) {
  ScratchDir s;
  test::write_text(s.path("sheet.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 2\n");
  const auto r = run_frep(s, "repair " + s.path("sheet.obj") + " -o " + s.path("out.stl"));
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("sheet.obj"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("no volume"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(s.path("out.stl")));
}

}  // namespace
}  // namespace frep
