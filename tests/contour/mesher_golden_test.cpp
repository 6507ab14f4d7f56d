// The mesher's output, bit for bit, on a few shapes that take every path of the driver and the
// assembly: a smooth ball (both methods), a rotated box (sharp edges, found bounds), boxes on grid
// planes (the rerun on a grid shifted off exact zeros), an under-sampled gyroid (cells with several
// vertices, the repairs, the reruns while vertices stay tangled) and the shared bear when present.
//
// The golden hashes guard the split of the assembly and the driver into named steps: that split
// must not change a single bit. They hold for this code on x86-64 with the project's compilers;
// an intended change of the output (or another platform's libm) changes them. To regenerate, run
//   frep_tests --gtest_filter='MesherGolden.*'
// and copy the hashes printed by the failures, after checking that the change is meant.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <string>
#include <vector>

#include "contour_test_util.hpp"
#include "frep/expr/expr.hpp"
#include "frep/io/vm.hpp"
#include "test_util.hpp"

namespace frep {
namespace {

// FNV-1a over the mesh (vertex bits, triangle indices) and the figures the driver reports.
struct Fnv {
  std::uint64_t h = 0xcbf29ce484222325ull;
  void add(std::uint64_t v) {
    for (int i = 0; i < 8; ++i) {
      h ^= (v >> (8 * i)) & 0xff;
      h *= 0x100000001b3ull;
    }
  }
};

std::uint64_t mesh_hash(const TriMesh& m, const MeshStats& st) {
  Fnv f;
  f.add(m.vertices.size());
  for (const Vec3& v : m.vertices)
    for (int a = 0; a < 3; ++a) f.add(std::bit_cast<std::uint64_t>(v[a]));
  f.add(m.triangles.size());
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) f.add(t[k]);
  for (std::uint64_t x : {std::uint64_t(st.leaves), std::uint64_t(st.surface_cells), std::uint64_t(st.unresolved),
                          std::uint64_t(st.unresolved_first), std::uint64_t(st.zero_corners), std::uint64_t(st.shifted),
                          std::uint64_t(st.capped), std::uint64_t(st.cells[0]), std::uint64_t(st.cells[1]),
                          std::uint64_t(st.cells[2])})
    f.add(x);
  for (int a = 0; a < 3; ++a) f.add(std::bit_cast<std::uint64_t>(st.bounds.lo[a])), f.add(std::bit_cast<std::uint64_t>(st.bounds.hi[a]));
  return f.h;
}

struct Case {
  std::string name;
  Tape tape;
  MeshOptions options;
  std::uint64_t golden;
};

void expect_golden(const Case& c) {
  MeshStats st;
  const TriMesh m = mesh_expression(c.tape, c.options, &st);
  const std::uint64_t h = mesh_hash(m, st);
  EXPECT_EQ(h, c.golden) << c.name << ": 0x" << std::hex << h << " (" << std::dec << m.triangles.size()
                         << " triangles, unresolved " << st.unresolved << ", first " << st.unresolved_first
                         << ", zero corners " << st.zero_corners << ")";
}

MeshOptions with(int resolution, Box3 bounds = {}, MeshMethod method = MeshMethod::DualContouring) {
  MeshOptions o = test::options(resolution, bounds, method);
  o.threads = 2;
  o.merge_flat = false;  // the grid's own mesh
  return o;
}

Tape tape_of(const Expr& e) { return Tape::compile(e.graph(), e.id()); }

TEST(MesherGolden, AnalyticShapes) {
  Graph g;
  const Expr x = g.x(), y = g.y(), z = g.z();
  const Box3 cube{{-1, -1, -1}, {1, 1, 1}};
  const Expr ball = sqrt(square(x - 0.1f) + square(y) + square(z + 0.05f)) - 0.6f;
  const Expr u = x * 0.8660254f + y * 0.5f, v0 = y * 0.8660254f - x * 0.5f;
  const Expr v = v0 * 0.9396926f + z * 0.3420201f, w = z * 0.9396926f - v0 * 0.3420201f;
  const Expr rotated_box = max(max(abs(u) - 0.5f, abs(v) - 0.35f), abs(w) - 0.25f);
  // Faces at multiples of 1/8: on the corners of a 16-cell grid over [-1, 1].
  const Expr on_planes = min(max(max(abs(x + 0.25f) - 0.25f, abs(y) - 0.5f), abs(z) - 0.5f),
                             max(max(abs(x - 0.25f) - 0.25f, abs(y) - 0.5f), abs(z) - 0.25f));
  const Expr gyroid = max(sqrt(square(x) + square(y) + square(z)) - 1.0f,
                          abs(sin(x * 150.0f) * cos(y * 150.0f) + sin(y * 150.0f) * cos(z * 150.0f) +
                              sin(z * 150.0f) * cos(x * 150.0f)) -
                              0.2f);
  const std::vector<Case> cases = {
      {"ball 20", tape_of(ball), with(20, cube), 0x3cd10a098624d790},
      {"ball 44", tape_of(ball), with(44, cube), 0xc3435b506eb2976b},
      {"ball 20 snap", tape_of(ball), with(20, cube, MeshMethod::Snap), 0x50807d8c734e25c0},
      {"rotated box 20", tape_of(rotated_box), with(20), 0xb2f9ef00baf86880},
      {"rotated box 44", tape_of(rotated_box), with(44), 0xbab1cf6cfaf9c99c},
      {"boxes on grid planes 16", tape_of(on_planes), with(16, cube), 0x6bc4570c499d1a36},
      {"boxes on grid planes 32", tape_of(on_planes), with(32, cube), 0x126b38476cdbde13},
      {"gyroid 24", tape_of(gyroid), with(24), 0x4b8f8e4514207dfa},
      {"gyroid 40", tape_of(gyroid), with(40), 0x75dba45bed4fc1b0},
  };
  for (const Case& c : cases) expect_golden(c);
}

TEST(MesherGolden, SharedBear) {
  FREP_REQUIRE_DATA("bear.vm");
  const Model m = read_vm(test::data_file("bear.vm"));
  const Tape t = Tape::compile(*m.graph, m.root);
  for (const Case& c : std::vector<Case>{{"bear 32", t, with(32), 0xdbee398d6b9e466c},
                                         {"bear 64", t, with(64, Box3{{-1, -1, -1}, {1, 1, 1}}), 0x1b60ccc32e1a3be8},
                                         {"bear 32 snap", t, with(32, {}, MeshMethod::Snap), 0x2000bd1c0763d7c7}})
    expect_golden(c);
}

}  // namespace
}  // namespace frep
