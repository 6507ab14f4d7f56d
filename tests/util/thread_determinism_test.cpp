// Results do not depend on the number of worker threads, as every threaded API promises: mesh
// grids (both methods, truncated or not) and expression grids, point samples (uniform and near
// the surface, from meshes and expressions), the clearance of two meshes (the check of each, the
// mesh-to-mesh query and the interval search for the depth, as `frep clearance` runs them), and
// the mesher (dual contouring and snap), each on several models, compared bit for bit between
// 1, 2 and 3 threads.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "frep/contour/mesher.hpp"
#include "frep/convert/convert.hpp"
#include "frep/convert/mesh_oracle.hpp"
#include "frep/eval/tape.hpp"
#include "frep/expr/expr.hpp"
#include "frep/mesh/mesh_field.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/mesh_pair.hpp"
#include "frep/sample/grid.hpp"
#include "frep/sample/points.hpp"
#include "frep/ugf/clearance.hpp"
#include "mesh_test_util.hpp"

namespace frep {
namespace {

const std::string kBracket = FREP_SOURCE_DIR "/examples/bracket.obj";
constexpr int kThreadCounts[] = {2, 3};

// Bit for bit (so that -0 and 0, and NaN payloads, count as different).
bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
}

bool same_mesh(const TriMesh& a, const TriMesh& b) {
  if (a.triangles != b.triangles || a.vertices.size() != b.vertices.size()) return false;
  for (std::size_t i = 0; i < a.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k)
      if (std::bit_cast<std::uint64_t>(a.vertices[i][k]) != std::bit_cast<std::uint64_t>(b.vertices[i][k])) return false;
  return true;
}

// The meshes: the bracket (a CAD part), a sphere (smooth), and a shared scan when present.
std::vector<std::pair<std::string, TriMesh>> meshes() {
  std::vector<std::pair<std::string, TriMesh>> r;
  r.emplace_back("bracket", read_mesh(kBracket));
  r.emplace_back("sphere", test::make_sphere(3, 0.7));
  if (test::have_shared_meshes()) r.emplace_back("spot", read_mesh(test::shared_mesh_dir() + "/spot.obj"));
  return r;
}

// Expressions: a ball, a rotated box (sharp edges), an under-sampled gyroid in a ball (many
// components; at 24 cells the mesher meshes it again on shifted grids), and the converted bracket.
struct Shape {
  std::string name;
  Model model;
};

std::vector<Shape> shapes() {
  std::vector<Shape> r;
  {
    Shape s{"ball", {}};
    Graph& g = *s.model.graph;
    s.model.root = (sqrt(square(g.x() - 0.1f) + square(g.y()) + square(g.z() + 0.05f)) - 0.6f).id();
    r.push_back(std::move(s));
  }
  {
    Shape s{"rotated box", {}};
    Graph& g = *s.model.graph;
    const Expr x = g.x(), y = g.y(), z = g.z();
    const Expr u = x * 0.8660254f + y * 0.5f, v0 = y * 0.8660254f - x * 0.5f;
    const Expr v = v0 * 0.9396926f + z * 0.3420201f, w = z * 0.9396926f - v0 * 0.3420201f;
    s.model.root = max(max(abs(u) - 0.5f, abs(v) - 0.35f), abs(w) - 0.25f).id();
    r.push_back(std::move(s));
  }
  {
    Shape s{"gyroid", {}};
    Graph& g = *s.model.graph;
    const Expr x = g.x() * 150.0f, y = g.y() * 150.0f, z = g.z() * 150.0f;
    const Expr gy = sin(x) * cos(y) + sin(y) * cos(z) + sin(z) * cos(x);
    s.model.root = max(sqrt(square(g.x()) + square(g.y()) + square(g.z())) - 1.0f, abs(gy) - 0.2f).id();
    r.push_back(std::move(s));
  }
  r.push_back({"converted bracket", convert_mesh(read_mesh(kBracket)).model});
  return r;
}

TEST(ThreadDeterminism, MeshGrids) {
  for (const auto& [name, mesh] : meshes()) {
    const MeshField field(mesh);
    ASSERT_TRUE(field.solid()) << name;
    const Box3 b = default_mesh_bounds(field.box());
    const GridSpec grid{{b.lo, b.hi + Vec3{0.01, -0.02, 0.03}}, {21, 17, 19}};
    for (MeshGridMethod method : {MeshGridMethod::Cpt, MeshGridMethod::Queries})
      for (double truncate : {0.0, 0.05 * length(b.size())}) {
        const std::string what = name + (method == MeshGridMethod::Cpt ? ", cpt" : ", queries") +
                                 (truncate > 0 ? ", truncated" : "");
        MeshGridOptions o;
        o.method = method;
        o.truncate = truncate;
        o.threads = 1;
        const std::vector<float> one = sample_grid(field, grid, o);
        for (int threads : kThreadCounts) {
          o.threads = threads;
          EXPECT_TRUE(same_bits(sample_grid(field, grid, o), one)) << what << ", " << threads << " threads";
        }
      }
  }
}

TEST(ThreadDeterminism, ExpressionGrids) {
  for (const Shape& s : shapes()) {
    const Tape tape = Tape::compile(*s.model.graph, s.model.root);
    const GridSpec grid{{{-1.1, -0.9, -1.0}, {1.0, 1.05, 0.95}}, {23, 29, 19}};
    for (double truncate : {0.0, 0.1}) {
      ExprGridOptions o;
      o.tiles = {16, 4};
      o.truncate = truncate;
      o.lipschitz = s.model.info.lipschitz;
      o.threads = 1;
      const std::vector<float> one = sample_grid(tape, grid, o);
      for (int threads : kThreadCounts) {
        o.threads = threads;
        EXPECT_TRUE(same_bits(sample_grid(tape, grid, o), one)) << s.name << ", truncate " << truncate << ", "
                                                                 << threads << " threads";
      }
    }
  }
}

TEST(ThreadDeterminism, PointSamples) {
  for (const auto& [name, mesh] : meshes()) {
    const MeshField field(mesh);
    const Box3 b = default_mesh_bounds(field.box());
    const double sigma = 0.01 * length(b.size());
    PointSampleOptions o;
    o.seed = 11;
    o.threads = 1;
    const std::vector<float> uniform = sample_uniform(field, b, 4000, o), near = sample_near_surface(field, 4000, sigma, o);
    for (int threads : kThreadCounts) {
      o.threads = threads;
      EXPECT_TRUE(same_bits(sample_uniform(field, b, 4000, o), uniform)) << name << ", " << threads << " threads";
      EXPECT_TRUE(same_bits(sample_near_surface(field, 4000, sigma, o), near)) << name << ", " << threads << " threads";
    }
  }
  for (const Shape& s : shapes()) {
    if (s.name == "gyroid") continue;  // its surface points are found by Newton steps: slow to converge there
    const Tape tape = Tape::compile(*s.model.graph, s.model.root);
    const Box3 b{{-1.1, -1.1, -1.1}, {1.1, 1.1, 1.1}};
    PointSampleOptions o;
    o.seed = 5;
    o.threads = 1;
    const std::vector<float> uniform = sample_uniform(tape, b, 3000, o), near = sample_near_surface(tape, b, 1500, 0.01, o);
    for (int threads : kThreadCounts) {
      o.threads = threads;
      EXPECT_TRUE(same_bits(sample_uniform(tape, b, 3000, o), uniform)) << s.name << ", " << threads << " threads";
      EXPECT_TRUE(same_bits(sample_near_surface(tape, b, 1500, 0.01, o), near)) << s.name << ", " << threads << " threads";
    }
  }
}

// What `frep clearance` computes for two meshes: each checked (MeshFieldOptions::threads), the
// mesh-to-mesh query (MeshPairOptions::threads), and for interfering ones the interval search for
// the depth over the two mesh leaves, seeded at the first contacts.
struct ClearanceAnswer {
  MeshPairResult pair;
  ugf::ClearanceResult depth;
};

ClearanceAnswer clearance_of(const TriMesh& a, const TriMesh& b, int threads) {
  ConvertOptions co;
  co.threads = threads;
  const auto oa = std::make_shared<const MeshOracle>(a, co), ob = std::make_shared<const MeshOracle>(b, co);
  MeshPairOptions po;
  po.threads = threads;
  ClearanceAnswer r;
  r.pair = compare_meshes(oa->field(), ob->field(), po);
  if (r.pair.apart()) return r;
  Model m = mesh_model(oa);
  Graph& g = *m.graph;
  const NodeId broot = g.oracle(ob);
  Box3 box{max(oa->field().box().lo, ob->field().box().lo), min(oa->field().box().hi, ob->field().box().hi)};
  box = box.inflated(1e-3 * length(box.size()));
  ugf::ClearanceOptions o;
  o.lipschitz = 2;
  o.max_boxes = 3000;
  for (const MeshPairContactExample& e : r.pair.examples) o.seeds.push_back(Vec3f(e.point));
  r.depth = ugf::find_clearance(m.root_expr(), Expr(g, broot), {float(box.lo.x), float(box.hi.x)},
                                {float(box.lo.y), float(box.hi.y)}, {float(box.lo.z), float(box.hi.z)}, o);
  return r;
}

TriMesh moved(TriMesh m, const Vec3& t) {
  for (Vec3& v : m.vertices) v += t;
  return m;
}

TEST(ThreadDeterminism, ClearanceOfMeshes) {
  const TriMesh bracket = read_mesh(kBracket), ball = test::make_sphere(3, 0.3);
  const struct {
    const char* what;
    TriMesh a, b;
    bool crossing, nested;
  } pairs[] = {
      {"bracket and a ball apart", bracket, moved(ball, {0.2, 0.1, 0.6}), false, false},
      {"bracket and a ball crossing it", bracket, moved(ball, {0.5, -0.2, 0.1}), true, false},
      {"bracket and a copy moved along x", bracket, moved(bracket, {0.7, 0.05, 0}), true, false},
      {"a ball inside a box", test::make_fine_box(6), moved(ball, {0.1, 0, -0.2}), false, true},
  };
  for (const auto& p : pairs) {
    const ClearanceAnswer one = clearance_of(p.a, p.b, 1);
    for (int threads : kThreadCounts) {
      const ClearanceAnswer r = clearance_of(p.a, p.b, threads);
      const std::string what = std::string(p.what) + ", " + std::to_string(threads) + " threads";
      EXPECT_EQ(r.pair.crossing, one.pair.crossing) << what;
      EXPECT_EQ(r.pair.overlapping, one.pair.overlapping) << what;
      EXPECT_EQ(r.pair.touching, one.pair.touching) << what;
      EXPECT_EQ(r.pair.a_shells_inside_b, one.pair.a_shells_inside_b) << what;
      EXPECT_EQ(r.pair.b_shells_inside_a, one.pair.b_shells_inside_a) << what;
      EXPECT_EQ(std::bit_cast<std::uint64_t>(r.pair.distance), std::bit_cast<std::uint64_t>(one.pair.distance)) << what;
      EXPECT_EQ(r.pair.point_a, one.pair.point_a) << what;
      EXPECT_EQ(r.pair.point_b, one.pair.point_b) << what;
      ASSERT_EQ(r.pair.examples.size(), one.pair.examples.size()) << what;
      for (std::size_t i = 0; i < r.pair.examples.size(); ++i) {
        EXPECT_EQ(r.pair.examples[i].a, one.pair.examples[i].a) << what;
        EXPECT_EQ(r.pair.examples[i].b, one.pair.examples[i].b) << what;
        EXPECT_EQ(r.pair.examples[i].point, one.pair.examples[i].point) << what;
      }
      EXPECT_EQ(std::bit_cast<std::uint32_t>(r.depth.value), std::bit_cast<std::uint32_t>(one.depth.value)) << what;
      EXPECT_EQ(std::bit_cast<std::uint32_t>(r.depth.lower_bound), std::bit_cast<std::uint32_t>(one.depth.lower_bound))
          << what;
      EXPECT_EQ(r.depth.boxes, one.depth.boxes) << what;
      EXPECT_EQ(Vec3f(r.depth.x, r.depth.y, r.depth.z), Vec3f(one.depth.x, one.depth.y, one.depth.z)) << what;
    }
    // Each case is what it says, and the depth search ran where they share volume.
    EXPECT_EQ(one.pair.crossing > 0, p.crossing) << p.what;
    EXPECT_EQ(one.pair.b_shells_inside_a > 0, p.nested) << p.what;
    if (!one.pair.apart()) {
      EXPECT_LT(one.depth.value, 0) << p.what;
    }
  }
}

TEST(ThreadDeterminism, Mesher) {
  std::vector<Shape> all = shapes();
  {
    Shape leaf{"bracket mesh leaf", mesh_model(std::make_shared<const MeshOracle>(read_mesh(kBracket)))};
    all.push_back(std::move(leaf));
  }
  for (const Shape& s : all)
    for (MeshMethod method : {MeshMethod::DualContouring, MeshMethod::Snap}) {
      const std::string what = s.name + (method == MeshMethod::Snap ? ", snap" : ", dual contouring");
      MeshOptions o;
      o.method = method;
      o.resolution = s.name == "gyroid" ? 24 : 40;
      o.lipschitz = s.model.info.lipschitz;
      o.known_bounds = s.model.info.bounds;
      o.threads = 1;
      const Tape tape = Tape::compile(*s.model.graph, s.model.root);
      MeshStats first;
      const TriMesh one = mesh_expression(tape, o, &first);
      ASSERT_GT(one.triangles.size(), 0u) << what;
      if (s.name == "gyroid" && method == MeshMethod::DualContouring) {
        EXPECT_GT(first.unresolved_first, 0u) << "the reruns on shifted grids are not exercised";
      }
      for (int threads : kThreadCounts) {
        o.threads = threads;
        MeshStats st;
        const TriMesh m = mesh_expression(tape, o, &st);
        EXPECT_TRUE(same_mesh(m, one)) << what << ", " << threads << " threads: " << m.triangles.size() << " against "
                                       << one.triangles.size() << " triangles";
        EXPECT_EQ(st.unresolved, first.unresolved) << what;
        EXPECT_EQ(st.zero_corners, first.zero_corners) << what;
      }
    }
}

}  // namespace
}  // namespace frep
