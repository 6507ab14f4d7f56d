// The converter beyond accuracy: what it refuses and how it says so, gradients (unit off the
// surface in face, edge and vertex regions, finite on it), the formats it writes (.vm, .rhai and
// .frep read back to identical values), the tree's depth, size on flat CAD parts, TetGen's
// failures, and the command line.
#include <gtest/gtest.h>
#include <csignal>
#include <chrono>
#include <thread>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

#include "convert_test_util.hpp"
#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/eval/subdivision.hpp"
#include "frep/script/load.hpp"
#include "frep/script/save.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/validate.hpp"
#include "mesh_test_util.hpp"
#include "test_util.hpp"

namespace frep {
namespace {

std::string message_of(const TriMesh& m, const ConvertOptions& o = {}) {
  try {
    convert_mesh(m, o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Convert, RefusesMeshesCheckRejects) {
  // Open: a box without one triangle.
  TriMesh open = test::make_box();
  open.triangles.pop_back(), open.origins.pop_back();
  EXPECT_NE(message_of(open).find("open"), std::string::npos) << message_of(open);
  // Inward: every triangle flipped.
  TriMesh inward = test::make_box();
  for (Triangle& t : inward.triangles) std::swap(t[1], t[2]);
  EXPECT_NE(message_of(inward).find("inward"), std::string::npos) << message_of(inward);
}

// Zero-area triangles are valid for `frep check` (a warning), but the sign next to them is
// undefined, so the converter refuses them (docs/convert.md, "What it refuses"), naming the file
// and the first such triangle with its line. The mesh: a box whose face triangle (0, 2, 1) is
// split at the midpoint m of its edge 1-0 into (0, 2, m) and (m, 2, 1), with the sliver
// (0, m, 1) closing the crack along that edge: closed, manifold, outward, one zero-area triangle.
TEST(Convert, RefusesZeroAreaTrianglesNamingTheFirst) {
  for (int at : {0, 5, 13}) {  // where the sliver sits among the triangles (and so its line)
    TriMesh box = test::make_box();
    ASSERT_EQ(box.triangles[0], (Triangle{0, 2, 1}));
    TriMesh flat;
    flat.name = "sliver_box.obj";
    flat.vertices = box.vertices;
    flat.vertices.push_back((box.vertices[0] + box.vertices[1]) * 0.5);  // 8, on the edge 0-1
    std::vector<Triangle> tris(box.triangles.begin() + 1, box.triangles.end());
    tris.push_back({0, 2, 8});
    tris.push_back({8, 2, 1});
    tris.insert(tris.begin() + at, Triangle{0, 8, 1});
    for (std::uint32_t t = 0; t < tris.size(); ++t) flat.add_triangle(tris[t][0], tris[t][1], tris[t][2], t, 100 + t);
    // What frep check sees: a solid, with exactly this one zero-area triangle.
    const ValidationReport check = validate_mesh(flat);
    ASSERT_TRUE(check.is_solid()) << check.to_text();
    ASSERT_EQ(check.defect(DefectKind::ZeroAreaTriangles).count, 1u) << check.to_text();
    const std::string msg = message_of(flat);
    EXPECT_NE(msg.find("sliver_box.obj"), std::string::npos) << msg;
    EXPECT_NE(msg.find("1 zero-area triangles"), std::string::npos) << msg;
    EXPECT_NE(msg.find("the first is triangle " + std::to_string(at) + ", line " + std::to_string(100 + at)),
              std::string::npos)
        << msg;
    // The same box without the split converts.
    EXPECT_EQ(message_of(box), "");
  }
}

TEST(Convert, RefusesSelfIntersectingBenchyInBothSignModes) {
  FREP_REQUIRE_SHARED_MESHES();
  const TriMesh benchy = read_mesh(test::shared_mesh_dir() + "/benchy.stl");
  for (SignMode s : {SignMode::Pseudonormal, SignMode::Tetrahedra}) {
    ConvertOptions o;
    o.sign = s;
    const std::string msg = message_of(benchy, o);
    EXPECT_NE(msg.find("crossing triangle pairs"), std::string::npos) << msg;
    EXPECT_NE(msg.find("benchy.stl"), std::string::npos) << msg;
  }
}

TEST(Convert, WeldToleranceClosesCracks) {
  // A box whose corners are repeated per face with offsets of 1e-9: open until welded.
  const TriMesh box = test::make_box();
  TriMesh cracked;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-1e-9, 1e-9);
  for (std::uint32_t t = 0; t < box.num_triangles(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = box.corner(t, k);
      cracked.vertices.push_back({p.x + jitter(rng), p.y + jitter(rng), p.z + jitter(rng)});
    }
    cracked.add_triangle(3 * t, 3 * t + 1, 3 * t + 2, t, 0);
  }
  EXPECT_NE(message_of(cracked), "");
  ConvertOptions o;
  o.weld_tolerance = 1e-6;
  EXPECT_EQ(message_of(cracked, o), "");
}

// A cube with its corner (1, 1, 1) cut off by a triangle 1e-9 across: its three corners are
// distinct in double but one point in f32, and so are the ends of the crease edges between
// them (repair makes such vertices where it cuts near an existing one). The converter takes
// each such edge as that point, and the result is as exact as for the plain cube.
TEST(Convert, CreaseEdgesShorterThanFloatsResolveAreTheirPoint) {
  const double e = 1e-9;
  TriMesh m;
  // Corners 0-6 of the unit cube except (1, 1, 1); 7-9 cut it: (1-e,1,1), (1,1-e,1), (1,1,1-e).
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1},
                {1 - e, 1, 1}, {1, 1 - e, 1}, {1, 1, 1 - e}};
  const std::uint32_t faces[][3] = {
      {0, 2, 3}, {0, 3, 1},                         // z = 0
      {0, 1, 5}, {0, 5, 4},                         // y = 0
      {0, 4, 6}, {0, 6, 2},                         // x = 0
      {4, 5, 8}, {4, 8, 7}, {4, 7, 6},              // z = 1 without the corner
      {2, 6, 7}, {2, 7, 9}, {2, 9, 3},              // y = 1
      {1, 3, 9}, {1, 9, 8}, {1, 8, 5},              // x = 1
      {7, 8, 9}};                                   // the cut
  for (std::uint32_t t = 0; t < std::size(faces); ++t) m.add_triangle(faces[t][0], faces[t][1], faces[t][2], t, 0);
  ASSERT_TRUE(validate_mesh(m).is_solid());
  const ConvertResult r = convert_mesh(m);
  const test::Samples s = test::sample_around(m, 500, 500, 200);
  const test::Accuracy a = test::measure(r.model, m, s);
  EXPECT_EQ(a.nonfinite, 0u);
  EXPECT_LE(a.max_error, 1e-6) << a.worst;
  EXPECT_EQ(a.sign_errors, 0u);
}

// |grad| = 1 within 1e-3 off the surface (both sides; face, edge and vertex regions), finite on it.
TEST(Convert, GradientsAreUnitOffTheSurfaceAndFiniteOnIt) {
  const TriMesh box = test::make_box({-1, -1, -1}, {1, 1, 1});
  const TriMesh sphere = test::make_sphere(2);
  for (const TriMesh* m : {&box, &sphere}) {
    const ConvertResult r = convert_mesh(*m);
    const Tape t = Tape::compile(*r.model.graph, r.model.root);
    GradEvaluator ge;
    std::vector<Vec3> off, on;
    for (std::size_t tri = 0; tri < m->num_triangles(); ++tri) {
      const Vec3 a = m->corner(tri, 0), b = m->corner(tri, 1), c = m->corner(tri, 2);
      const Vec3 n = cross(b - a, c - a) / length(cross(b - a, c - a));
      const Vec3 centroid = (a + b + c) / 3.0;
      for (double d : {0.3, 0.01, -0.01, -0.05}) off.push_back(centroid + n * d);  // face regions
      const Vec3 mid = (a + b) * 0.5, out = (mid - Vec3{0, 0, 0}) / length(mid);
      off.push_back(mid + out * 0.2);  // edge (or face) region, outside
      off.push_back(a + (a / length(a)) * 0.3);  // vertex region, outside
      on.push_back(centroid), on.push_back(mid), on.push_back(a), on.push_back(a + (b - a) * 0.25);
    }
    for (const Vec3& p : off) {
      const Grad g = ge.eval(t, static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z));
      const double len = std::sqrt(double(g.dx) * g.dx + double(g.dy) * g.dy + double(g.dz) * g.dz);
      ASSERT_NEAR(len, 1.0, 1e-3) << "at (" << p.x << ", " << p.y << ", " << p.z << ") value " << g.v;
    }
    for (const Vec3& p : on) {
      const Grad g = ge.eval(t, static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z));
      ASSERT_TRUE(std::isfinite(g.v) && std::isfinite(g.dx) && std::isfinite(g.dy) && std::isfinite(g.dz))
          << "at (" << p.x << ", " << p.y << ", " << p.z << ")";
    }
  }
}

// Every format reads back to the same values, bit for bit.
TEST(Convert, VmRhaiAndFrepReadBackIdentically) {
  const std::string dir = ::testing::TempDir();
  std::vector<TriMesh> meshes{test::make_box(), test::make_sphere(1), test::make_fine_box(2)};
  if (test::have_shared_meshes()) meshes.push_back(read_mesh(test::shared_mesh_dir() + "/spot.obj"));
  for (const TriMesh& m : meshes) {
    const ConvertResult r = convert_mesh(m);
    const test::Samples s = test::sample_around(m, 500, 500, 100);
    std::vector<float> x, y, z;
    for (const Vec3& p : s.points) x.push_back(float(p.x)), y.push_back(float(p.y)), z.push_back(float(p.z));
    std::vector<float> ref(x.size()), got(x.size());
    eval_points(Tape::compile(*r.model.graph, r.model.root), x.data(), y.data(), z.data(), ref.data(), x.size());
    for (const char* ext : {".vm", ".rhai", ".frep"}) {
      const std::string path = dir + "/convert_roundtrip" + ext;
      save_expression(path, *r.model.graph, r.model.root);
      const Model back = load_expression(path);
      EXPECT_LE(reachable_nodes(*back.graph, back.root).size(), r.stats.nodes) << ext;
      eval_points(Tape::compile(*back.graph, back.root), x.data(), y.data(), z.data(), got.data(), x.size());
      for (std::size_t i = 0; i < x.size(); ++i) ASSERT_TRUE(test::same_value(ref[i], got[i])) << ext << " point " << i;
      std::filesystem::remove(path);
    }
  }
}

// Terms are combined in balanced trees: the depth grows with log2 of the size, not linearly.
TEST(Convert, ExpressionDepthIsLogarithmic) {
  const TriMesh m = test::make_sphere(4);  // 5120 triangles
  const ConvertResult r = convert_mesh(m);
  const Graph& g = *r.model.graph;
  std::vector<int> depth(g.size(), 0);
  int deepest = 0;
  for (NodeId id : reachable_nodes(g, r.model.root)) {
    const Node& n = g.node(id);
    int d = 0;
    if (n.a != kNoNode) d = std::max(d, depth[n.a]);
    if (n.b != kNoNode) d = std::max(d, depth[n.b]);
    depth[id] = d + 1;
    deepest = std::max(deepest, depth[id]);
  }
  // log2(5120 triangles) is 12.3; a term is about 15 deep and each tree level adds about 4.
  EXPECT_LT(deepest, 15 + 4 * 16) << "depth " << deepest;
}

// The vertex bound (min(P, 4 B)) lets pruning drop the far terms of a box on the surface, where
// the terms near it cannot settle their signs: a box 1/20 of the diameter keeps a few percent.
TEST(Convert, ABoxOnTheSurfaceKeepsOnlyNearbyTerms) {
  const TriMesh m = test::make_sphere(3, 1.0);
  const ConvertResult r = convert_mesh(m);
  const Tape tape = Tape::compile(*r.model.graph, r.model.root);
  IntervalEvaluator ie;
  Tape s;
  ie.simplify(tape, {-0.05f, 0.05f}, {-0.05f, 0.05f}, {0.95f, 1.05f}, s);
  EXPECT_LT(s.size() * 20, tape.size()) << s.size() << " of " << tape.size();
}

// Away from the surface, a box's sign is settled: by intervals outside the mesh's bounding box
// (the root is bounded by the distance to that box), and everywhere by the value at the box's
// centre and the Lipschitz bound the conversion reports (intervals alone cannot settle it near
// the surface: the vertex bound that makes pruning work caps both signs' terms).
TEST(Convert, BoxesAwayFromTheSurfaceSettleTheirSign) {
  const TriMesh m = test::make_sphere(3, 1.0);  // 1280 triangles, inradius about 0.99
  const ConvertResult r = convert_mesh(m);
  ASSERT_EQ(r.model.info.lipschitz, 1.0);
  const Tape tape = Tape::compile(*r.model.graph, r.model.root);
  IntervalEvaluator ie;
  const Interval far = ie.eval(tape, {1.5f, 1.7f}, {-0.1f, 0.1f}, {-0.1f, 0.1f});
  EXPECT_GT(far.lo, 0.3f) << far.lo << " " << far.hi;
  EXPECT_LE(far.lo, 0.51f);
  PointEvaluator pe;
  auto settle = [&](Interval x, Interval y, Interval z) {
    const float c[3] = {0.5f * (x.lo + x.hi), 0.5f * (y.lo + y.hi), 0.5f * (z.lo + z.hi)};
    const double r = 0.5 * std::sqrt(double(x.hi - x.lo) * (x.hi - x.lo) + double(y.hi - y.lo) * (y.hi - y.lo) +
                                     double(z.hi - z.lo) * (z.hi - z.lo));
    return lipschitz_bound(ie.eval(tape, x, y, z), Interval::point(pe.eval(tape, c[0], c[1], c[2])), 1.0, r, 2.0);
  };
  const Interval inside = settle({-0.1f, 0.1f}, {-0.1f, 0.1f}, {0.2f, 0.3f});
  EXPECT_LT(inside.hi, -0.5f) << inside.lo << " " << inside.hi;
  EXPECT_GE(inside.hi, -0.81f);  // the distance at (0.1, 0.1, 0.3) is above -0.8
  const Interval near = settle({1.1f, 1.2f}, {-0.05f, 0.05f}, {-0.05f, 0.05f});
  EXPECT_GT(near.lo, 0.0f) << near.lo << " " << near.hi;
}

// Flat CAD parts shrink: coplanar neighbours share a plane, edges inside flat regions vanish.
TEST(Convert, FlatFacesShrinkTheExpression) {
  const ConvertResult coarse = convert_mesh(test::make_fine_box(1));
  for (int n : {2, 3, 8}) {
    const ConvertResult fine = convert_mesh(test::make_fine_box(n));  // 12 n^2 triangles, the same solid
    EXPECT_EQ(fine.stats.flat_regions, 6u);
    EXPECT_EQ(fine.stats.polygons, 6u) << "each face merges back into one convex polygon";
    EXPECT_EQ(fine.stats.edge_terms, 12u) << "collinear pieces of a box edge are one segment";
    EXPECT_EQ(fine.stats.nodes, coarse.stats.nodes) << "the tessellation of flat faces costs nothing";
  }
}

TEST(Convert, TetGenFailuresAreClearErrors) {
  const TriMesh box = test::make_box();
  ConvertOptions o;
  o.sign = SignMode::Tetrahedra;
  o.tetgen = "/nonexistent/tetgen";
  EXPECT_NE(message_of(box, o).find("was not found"), std::string::npos) << message_of(box, o);
  o.tetgen = "false";  // exits 1 at once
  EXPECT_NE(message_of(box, o).find("TetGen failed"), std::string::npos) << message_of(box, o);
  o.tetgen = "sleep";  // never writes its output within the limit ("sleep -pYQ in.smesh" fails or sleeps)
  o.tetgen_timeout = 0.2;
  EXPECT_NE(message_of(box, o).find("TetGen"), std::string::npos) << message_of(box, o);
}

// A TetGen that outlives its time limit through a child of its own (a wrapper script): the
// whole process group is killed, and the scratch directory removed; so is an interrupted one
// (SIGTERM to frep), which used to leave both behind.
TEST(Convert, TetGenTimeoutsAndSignalsLeaveNothingBehind) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(::testing::TempDir()) / ("frep_tetgen_group_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "tmp");
  const fs::path script = dir / "slow_tetgen.sh", pidfile = dir / "child.pid";
  {
    std::ofstream(script) << "#!/bin/sh\nsleep 60 &\necho $! > '" << pidfile.string() << "'\nwait\n";
  }
  fs::permissions(script, fs::perms::owner_all);
  const auto child_alive = [&] {
    std::ifstream in(pidfile);
    long pid = 0;
    if (!(in >> pid) || pid <= 0) return false;
    // Running or sleeping; a zombie (killed, not yet reaped: containers may have no init that
    // reaps) is dead.
    const auto running = [&] {
      std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
      std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
      const std::size_t paren = text.rfind(')');
      return paren != std::string::npos && paren + 2 < text.size() && text[paren + 2] != 'Z' && text[paren + 2] != 'X';
    };
    for (int i = 0; i < 100 && running(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    return running();
  };
  ConvertOptions o;
  o.sign = SignMode::Tetrahedra;
  o.tetgen = script.string();
  o.tetgen_timeout = 0.5;
  EXPECT_NE(message_of(test::make_box(), o).find("did not finish"), std::string::npos);
  EXPECT_FALSE(child_alive()) << "the script's child survived the timeout";
  fs::remove(pidfile);

  // The command line, stopped by SIGTERM while TetGen runs: no scratch directory, no child.
  const std::string mesh = (dir / "box.stl").string();
  write_mesh(mesh, test::make_box());
  const std::string cmd = "TMPDIR='" + (dir / "tmp").string() + "' " + FREP_CLI_PATH + " convert '" + mesh +
                          "' --sign tets --tetgen '" + script.string() + "' -o '" + (dir / "box.frep").string() +
                          "' > /dev/null 2>&1 & echo $!";
  std::FILE* p = ::popen(cmd.c_str(), "r");
  long frep_pid = 0;
  ASSERT_EQ(std::fscanf(p, "%ld", &frep_pid), 1);
  ::pclose(p);
  for (int i = 0; i < 500 && !fs::exists(pidfile); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_TRUE(fs::exists(pidfile)) << "the fake TetGen did not start";
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ::kill(static_cast<pid_t>(frep_pid), SIGTERM);
  for (int i = 0; i < 200 && ::kill(static_cast<pid_t>(frep_pid), 0) == 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_FALSE(child_alive()) << "TetGen's child survived frep";
  EXPECT_TRUE(fs::is_empty(dir / "tmp")) << "a scratch directory was left in " << (dir / "tmp");
  EXPECT_FALSE(fs::exists(dir / "box.frep"));
  fs::remove_all(dir);
}

// A relative program path with a slash names a file from the current directory, though TetGen
// runs in its scratch directory (it was reported as not found).
TEST(Convert, TetGenByARelativePath) {
  if (std::system("command -v tetgen > /dev/null 2>&1") != 0) GTEST_SKIP() << "the tetgen program is not installed";
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(::testing::TempDir()) / ("frep_tetgen_rel_" + std::to_string(::getpid()));
  fs::create_directories(dir / "bin");
  { std::ofstream(dir / "bin" / "tg.sh") << "#!/bin/sh\nexec tetgen \"$@\"\n"; }
  fs::permissions(dir / "bin" / "tg.sh", fs::perms::owner_all);
  const fs::path cwd = fs::current_path();
  fs::current_path(dir);
  ConvertOptions o;
  o.sign = SignMode::Tetrahedra;
  o.tetgen = "bin/tg.sh";
  const std::string message = message_of(test::make_box(), o);
  fs::current_path(cwd);
  EXPECT_EQ(message, "") << message;
  fs::remove_all(dir);
}

int run(const std::string& cmd, std::string* out = nullptr) {
  std::string full = cmd + " 2>&1";
  std::FILE* p = ::popen(full.c_str(), "r");
  std::string text;
  char buf[4096];
  while (std::size_t k = std::fread(buf, 1, sizeof buf, p)) text.append(buf, k);
  const int status = ::pclose(p);
  if (out) *out = text;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(ConvertCli, ConvertsRefusesAndWritesAtomically) {
  const std::string dir = ::testing::TempDir();
  const std::string mesh = dir + "/cli_box.stl", out = dir + "/cli_box.frep";
  write_mesh(mesh, test::make_box());
  std::string text;
  ASSERT_EQ(run(std::string(FREP_CLI_PATH) + " convert " + mesh + " -o " + out, &text), 0) << text;
  EXPECT_NE(text.find("12 triangles"), std::string::npos) << text;
  EXPECT_NE(text.find("per triangle"), std::string::npos) << text;
  EXPECT_EQ(run(std::string(FREP_CLI_PATH) + " info " + out, &text), 0) << text;
  EXPECT_NE(text.find("lipschitz: 1"), std::string::npos) << "the file says it is a distance: " << text;
  // --lipschitz: used by the commands that subdivide space; a negative bound is a usage error.
  const std::string png = dir + "/cli_box.png";
  EXPECT_EQ(run(std::string(FREP_CLI_PATH) + " render " + out + " --3d --size 24 --lipschitz 0 -o " + png, &text), 0) << text;
  EXPECT_EQ(run(std::string(FREP_CLI_PATH) + " render " + out + " --3d --size 24 --lipschitz -1 -o " + png, &text), 2) << text;
  EXPECT_NE(text.find("Lipschitz"), std::string::npos) << text;
  // The file's box frames pictures and meshes: a part in millimetres far from [-1,1]^3.
  const std::string part = dir + "/cli_part.stl", part_frep = dir + "/cli_part.frep";
  write_mesh(part, test::make_box({100, 200, 300}, {300, 300, 400}));
  ASSERT_EQ(run(std::string(FREP_CLI_PATH) + " convert " + part + " -o " + part_frep, &text), 0) << text;
  EXPECT_EQ(run(std::string(FREP_CLI_PATH) + " info " + part_frep, &text), 0) << text;
  EXPECT_NE(text.find("bounds: 100, 200, 300 .. 300, 300, 400"), std::string::npos) << text;
  EXPECT_EQ(run(std::string(FREP_CLI_PATH) + " render " + part_frep + " --3d --view front --size 64 -o " + png, &text), 0) << text;
  int w = 0, h = 0;
  ASSERT_EQ(std::sscanf(text.c_str() + text.find('('), "(%dx%d", &w, &h), 2) << text;
  EXPECT_EQ(w, 64);  // the front view shows x (200 + 2 * 10) across and y (100 + 2 * 10) up
  EXPECT_NEAR(h, 64 * 120 / 220, 2) << text;
  const std::string part_stl = dir + "/cli_part_remeshed.stl";
  EXPECT_EQ(run(std::string(FREP_CLI_PATH) + " mesh " + part_frep + " -r 16 -o " + part_stl, &text), 0) << text;
  EXPECT_NE(text.find("known from the input"), std::string::npos) << text;
  // A refused mesh: exit 1, a message naming the file, and no output file.
  TriMesh open = test::make_box();
  open.triangles.pop_back(), open.origins.pop_back();
  const std::string bad = dir + "/cli_open.stl", bad_out = dir + "/cli_open.vm";
  write_mesh(bad, open);
  std::filesystem::remove(bad_out);
  EXPECT_EQ(run(std::string(FREP_CLI_PATH) + " convert " + bad + " -o " + bad_out, &text), 1);
  EXPECT_NE(text.find("cli_open.stl"), std::string::npos) << text;
  EXPECT_FALSE(std::filesystem::exists(bad_out));
  // Usage errors exit 2.
  EXPECT_EQ(run(std::string(FREP_CLI_PATH) + " convert " + mesh + " -o " + dir + "/x.vm --sign nope"), 2);
  EXPECT_EQ(run(std::string(FREP_CLI_PATH) + " convert " + mesh + " -o " + dir + "/x.stl", &text), 1) << text;
}

}  // namespace
}  // namespace frep
