// The Rhai functions of the UGF library (src/io/rhai_ugf.cpp): each script call builds the same
// field as the C++ call (bit for bit at sampled points, in a fresh graph), on curved inputs so
// that c = dot(grad A, grad B) varies; tracked fields, the edge frame and find_clearance return
// maps; a part built from several of them evaluates to the C++ part; bad arguments are errors.
#include <gtest/gtest.h>

#include <functional>

#include "frep/ugf.hpp"
#include "rhai_test_util.hpp"

namespace frep {
namespace {

using test::fails_at;
using test::run_rhai;
using test::script_matches;

// A sphere and a tilted plane crossing it, in script and in C++.
const char* kInputs =
    "let a = sqrt(x * x + y * y + z * z) - 1.0;\n"
    "let b = (x + y) * 0.70710678 - 0.2;\n";
Expr in_a(Graph& g) { return sqrt(g.x() * g.x() + g.y() * g.y() + g.z() * g.z()) - 1.0f; }
Expr in_b(Graph& g) { return (g.x() + g.y()) * 0.70710678f - 0.2f; }

struct Case {
  const char* call;
  std::function<Expr(Graph&, Expr, Expr)> cpp;
};

TEST(RhaiUgf, EveryOperationBuildsTheLibrarysField) {
  using namespace ugf;
  const ugf::EdgeOptions five{5.0f};
  const std::vector<Case> cases = {
      {"offset(a, 0.25)", [](Graph&, Expr A, Expr) { return offset(A, 0.25f); }},
      {"a.offset(-0.1)", [](Graph&, Expr A, Expr) { return offset(A, -0.1f); }},
      {"shell(a, 0.2)", [](Graph&, Expr A, Expr) { return shell(A, 0.2f); }},
      {"shell_biased(a, 0.2, 0.5)", [](Graph&, Expr A, Expr) { return shell_biased(A, 0.2f, 0.5f); }},
      {"shell_inward(a, 0.2)", [](Graph&, Expr A, Expr) { return shell_inward(A, 0.2f); }},
      {"shell_outward(a, 0.2)", [](Graph&, Expr A, Expr) { return shell_outward(A, 0.2f); }},
      {"shell_variable(a, two_body_parameter(a, b) * 0.3)",
       [](Graph&, Expr A, Expr B) { return shell_variable(A, two_body_parameter(A, B) * 0.3f); }},
      {"intersect(a, b)", [](Graph&, Expr A, Expr B) { return intersect(A, B); }},
      {"unite(a, b)", [](Graph&, Expr A, Expr B) { return unite(A, B); }},
      {"subtract(a, b)", [](Graph&, Expr A, Expr B) { return subtract(A, B); }},
      {"intersect_exact(a, b)", [](Graph&, Expr A, Expr B) { return intersect_exact(A, B); }},
      {"intersect_exact(a, b, #{ min_angle: 5 })", [five](Graph&, Expr A, Expr B) { return intersect_exact(A, B, five); }},
      {"unite_exact(a, b)", [](Graph&, Expr A, Expr B) { return unite_exact(A, B); }},
      {"subtract_exact(a, b)", [](Graph&, Expr A, Expr B) { return subtract_exact(A, B); }},
      {"intersect_right_angle(a, b)", [](Graph&, Expr A, Expr B) { return intersect_right_angle(A, B); }},
      {"unite_right_angle(a, b)", [](Graph&, Expr A, Expr B) { return unite_right_angle(A, B); }},
      {"subtract_right_angle(a, b)", [](Graph&, Expr A, Expr B) { return subtract_right_angle(A, B); }},
      {"smooth_union(a, b, 0.3)", [](Graph&, Expr A, Expr B) { return smooth_union(A, B, 0.3f); }},
      {"smooth_union(a, b, 0.3, \"cubic\")", [](Graph&, Expr A, Expr B) { return smooth_union(A, B, 0.3f, Blend::Cubic); }},
      {"smooth_intersection(a, b, 0.3, \"exponential\")",
       [](Graph&, Expr A, Expr B) { return smooth_intersection(A, B, 0.3f, Blend::Exponential); }},
      {"smooth_difference(a, b, 0.3, \"root\")", [](Graph&, Expr A, Expr B) { return smooth_difference(A, B, 0.3f, Blend::Root); }},
      {"edge_frame(a, b).Sn", [](Graph&, Expr A, Expr B) { return edge_frame(A, B).Sn; }},
      {"edge_frame(a, b).Dn", [](Graph&, Expr A, Expr B) { return edge_frame(A, B).Dn; }},
      {"edge_frame(a, b, #{ min_angle: 5 }).valid", [five](Graph&, Expr A, Expr B) { return edge_frame(A, B, five).valid; }},
      {"edge_frame(a, b).c + edge_frame(a, b).cos_half * edge_frame(a, b).sin_half",
       [](Graph&, Expr A, Expr B) { const EdgeFrame f = edge_frame(A, B); return f.c + f.cos_half * f.sin_half; }},
      {"edge_frame(a, b).S - edge_frame(a, b).D", [](Graph&, Expr A, Expr B) { const EdgeFrame f = edge_frame(A, B); return f.S - f.D; }},
      {"chamfer_intersection(a, b, #{ inset: 0.1 })",
       [](Graph&, Expr A, Expr B) { return chamfer_intersection(A, B, Chamfer::inset(0.1f)); }},
      {"chamfer_intersection(a, b, #{ setback: 0.2, min_angle: 5 })",
       [five](Graph&, Expr A, Expr B) { return chamfer_intersection(A, B, Chamfer::setback(0.2f), five); }},
      {"chamfer_intersection(a, b, #{ width: 0.3, exact: true })",
       [](Graph&, Expr A, Expr B) { return chamfer_intersection(A, B, Chamfer::width(0.3f).distance_preserving()); }},
      {"chamfer_union(a, b, #{ setbacks: [0.1, 0.25] })",
       [](Graph&, Expr A, Expr B) { return chamfer_union(A, B, Chamfer::setbacks(0.1f, 0.25f)); }},
      {"chamfer_intersection_right_angle(a, b, 0.2)",
       [](Graph&, Expr A, Expr B) { return chamfer_intersection_right_angle(A, B, 0.2f); }},
      {"chamfer_union_right_angle(a, b, 0.2)", [](Graph&, Expr A, Expr B) { return chamfer_union_right_angle(A, B, 0.2f); }},
      {"round_intersection(a, b, 0.3)", [](Graph&, Expr A, Expr B) { return round_intersection(A, B, 0.3f); }},
      {"round_union(a, b, 0.3, #{ min_angle: 5 })", [five](Graph&, Expr A, Expr B) { return round_union(A, B, 0.3f, five); }},
      {"pencil(a, b, 0.4)", [](Graph&, Expr A, Expr B) { return pencil(edge_frame(A, B), 0.4f); }},
      {"pencil_face(a, b, -0.3, 0.1)", [](Graph&, Expr A, Expr B) { return pencil_face(edge_frame(A, B), -0.3f, 0.1f); }},
      {"pencil_chamfer(a, b, 0.2, -0.15)", [](Graph&, Expr A, Expr B) { return pencil_chamfer(edge_frame(A, B), 0.2f, -0.15f); }},
      {"two_body(a, b)", [](Graph&, Expr A, Expr B) { return two_body(A, B); }},
      {"two_body_parameter(a, b)", [](Graph&, Expr A, Expr B) { return two_body_parameter(A, B); }},
      {"between(a, b, 0.5)", [](Graph&, Expr A, Expr B) { return between(A, B, 0.5f); }},
      {"midsurface(a, b)", [](Graph&, Expr A, Expr B) { return midsurface(A, B); }},
      {"clearance_field(a, b)", [](Graph&, Expr A, Expr B) { return clearance_field(A, B); }},
      {"normalize(a * a * a)", [](Graph&, Expr A, Expr) { return normalize(A * A * A); }},
      {"normalize(a * a * a, 0.01)", [](Graph&, Expr A, Expr) { return normalize(A * A * A, 0.01f); }},
      {"gyroid(0.7)", [](Graph& g, Expr, Expr) { return gyroid(g, 0.7f); }},
      {"gyroid_normalized(0.7)", [](Graph& g, Expr, Expr) { return gyroid_normalized(g, 0.7f); }},
      {"gyroid_normalized(0.7, \"bound\")", [](Graph& g, Expr, Expr) { return gyroid_normalized(g, 0.7f, GyroidScale::Bound); }},
      {"gyroid_network(0.7, 0.05)", [](Graph& g, Expr, Expr) { return gyroid_network(g, 0.7f, 0.05f); }},
      {"gyroid_sheet(0.7, 0.1, \"bound\")", [](Graph& g, Expr, Expr) { return gyroid_sheet(g, 0.7f, 0.1f, GyroidScale::Bound); }},
      {"negate(a)", [](Graph&, Expr A, Expr) { return -A; }},
      // Medial-axis tracking: maps #{ f, m }.
      {"track_plane(b).m + track_plane(b).f", [](Graph&, Expr, Expr B) { const Tracked t = track_plane(B); return t.m + t.f; }},
      {"offset(track_sphere([0.1, 0, 0], 0.8), 0.2).m",
       [](Graph& g, Expr, Expr) { return offset(track_sphere(g, 0.1f, 0, 0, 0.8f), 0.2f).m; }},
      {"shell(track(a, a + 1.0), 0.1).m", [](Graph&, Expr A, Expr) { return shell(track(A, A + 1.0f), 0.1f).m; }},
      {"negate(track_sphere([0, 0, 0], 1)).f", [](Graph& g, Expr, Expr) { return negate(track_sphere(g, 0, 0, 0, 1)).f; }},
      {"intersect(track_sphere([0, 0, 0], 1), track_plane(b)).m",
       [](Graph& g, Expr, Expr B) { return intersect(track_sphere(g, 0, 0, 0, 1), track_plane(B)).m; }},
      {"unite(track_sphere([0, 0, 0], 1), track_plane(b)).f",
       [](Graph& g, Expr, Expr B) { return unite(track_sphere(g, 0, 0, 0, 1), track_plane(B)).f; }},
      {"subtract(track_sphere([0, 0, 0], 1), track_plane(b)).m",
       [](Graph& g, Expr, Expr B) { return subtract(track_sphere(g, 0, 0, 0, 1), track_plane(B)).m; }},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.call);
    EXPECT_TRUE(script_matches(std::string(kInputs) + c.call, [&](Graph& g) { return c.cpp(g, in_a(g), in_b(g)); }));
  }
  // Same nodes, not only the same values: built in the script's own graph, the C++ call finds
  // the script's node (hash-consing), for a few operations of each kind.
  for (const char* call : {"round_intersection(a, b, 0.3)", "chamfer_intersection(a, b, #{ width: 0.3 })", "shell_inward(a, 0.2)"}) {
    const Model m = run_rhai(std::string(kInputs) + call);
    Graph& g = *m.graph;
    const std::size_t before = g.size();
    const Expr A = in_a(g), B = in_b(g);
    const Expr e = std::string(call).rfind("round", 0) == 0   ? ugf::round_intersection(A, B, 0.3f)
                   : std::string(call).rfind("chamfer", 0) == 0 ? ugf::chamfer_intersection(A, B, ugf::Chamfer::width(0.3f))
                                                                : ugf::shell_inward(A, 0.2f);
    EXPECT_EQ(e.id(), m.root) << call;
    EXPECT_EQ(g.size(), before) << call << ": the C++ call built new nodes";
  }
}

TEST(RhaiUgf, FindClearanceReturnsTheGapAndWhere) {
  const Model m = run_rhai(
      "let a = sqrt(x * x + y * y + z * z) - 1.0;\n"
      "let b = sqrt((x - 3.0) * (x - 3.0) + y * y + z * z) - 0.5;\n"
      "let r = find_clearance(a, b, [-2, -2, -2], [4, 2, 2]);\n"
      "if r.point[0] < 1.0 || r.point[0] > 2.5 || r.lower_bound > r.value { throw \"bad\"; }\n"
      "r.value");
  // The gap is 3 - 1 - 0.5: the script's value is a constant field.
  EXPECT_NEAR(test::eval_graph<float>(*m.graph, m.root, 0.f, 0.f, 0.f), 1.5f, 1e-5f);
}

// A part as a user would write it: a block with rounded vertical edges and a chamfered top,
// hollowed, with a gyroid inside, cut by a smooth hole; the same in C++.
TEST(RhaiUgf, APartBuiltFromSeveralOperations) {
  const char* script = R"(
    let sx = max(x - 1.0, -x - 1.0);
    let sy = max(y - 0.6, -y - 0.6);
    let plate = round_intersection(x - 1.0, y - 0.6, 0.2);
    let block = intersect_exact(intersect_exact(sx, sy), -z - 0.4);
    let top = chamfer_intersection(block, z - 0.4, #{ width: 0.15 });
    let body = intersect(top, plate);
    let hole = sqrt(x * x + y * y) - 0.25;
    let part = smooth_difference(body, hole, 0.05);
    let infill = intersect(gyroid_sheet(0.4, 0.05), offset(part, -0.1));
    unite(shell_inward(part, 0.08), infill)
  )";
  auto build = [](Graph& g) {
    using namespace ugf;
    const Expr x = g.x(), y = g.y(), z = g.z();
    const Expr sx = max(x - 1.0f, -x - 1.0f), sy = max(y - 0.6f, -y - 0.6f);
    const Expr plate = round_intersection(x - 1.0f, y - 0.6f, 0.2f);
    const Expr block = intersect_exact(intersect_exact(sx, sy), -z - 0.4f);
    const Expr top = chamfer_intersection(block, z - 0.4f, Chamfer::width(0.15f));
    const Expr part = smooth_difference(intersect(top, plate), sqrt(x * x + y * y) - 0.25f, 0.05f);
    return unite(shell_inward(part, 0.08f), intersect(gyroid_sheet(g, 0.4f, 0.05f), offset(part, -0.1f)));
  };
  EXPECT_TRUE(script_matches(script, build, 1.5f));
  const Model m = run_rhai(script);
  // Inside the wall, outside the part, in the hole.
  EXPECT_LT(test::eval_graph<float>(*m.graph, m.root, 0.96f, 0.f, 0.f), 0.f);
  EXPECT_GT(test::eval_graph<float>(*m.graph, m.root, 1.2f, 0.f, 0.f), 0.f);
  EXPECT_GT(test::eval_graph<float>(*m.graph, m.root, 0.f, 0.1f, 0.f), 0.f);
}

TEST(RhaiUgf, BadArgumentsAreErrorsThatSaySo) {
  EXPECT_TRUE(fails_at("offset(x)", 1, 1, "`offset` takes (shape, distance)"));
  EXPECT_TRUE(fails_at("offset(x, y)", 1, 1, "the distance must be a number"));
  EXPECT_TRUE(fails_at("chamfer_intersection(x, y, 0.2)", 1, 1, "the size is a map"));
  EXPECT_TRUE(fails_at("chamfer_intersection(x, y, #{ width: 0.2, setback: 0.1 })", 1, 1, "exactly one"));
  EXPECT_TRUE(fails_at("chamfer_union(x, y, #{ widht: 0.2 })", 1, 1, "unknown option `widht`"));
  EXPECT_TRUE(fails_at("smooth_union(x, y, 0.2, \"quartic\")", 1, 1, "the blend kind is"));
  EXPECT_TRUE(fails_at("smooth_union(x, y, 0)", 1, 1, "must be > 0"));
  EXPECT_TRUE(fails_at("round_intersection(x, y, 0.1, #{ min_angle: 120 })", 1, 1, "min_angle"));
  EXPECT_TRUE(fails_at("between(x, y, 2)", 1, 1, "t must be in [-1, 1]"));
  EXPECT_TRUE(fails_at("gyroid(-1)", 1, 1, "the period must be > 0"));
  EXPECT_TRUE(fails_at("gyroid_sheet(1, 0.1, \"exact\")", 1, 1, "\"sampson\" or \"bound\""));
  EXPECT_TRUE(fails_at("intersect(track_plane(x), y)", 1, 1, "needs two tracked fields"));
  EXPECT_TRUE(fails_at("find_clearance(x, y, [1, 0, 0], [0, 1, 1])", 1, 1, "the region is empty"));
  // Nested in a loop, operations that differentiate their arguments grow the graph geometrically:
  // the node and step limits stop the script with an error instead of running out of memory.
  RhaiOptions limited;
  limited.max_nodes = 100000;
  EXPECT_TRUE(fails_at("let a = x * x + y - 1.0; for i in 0..40 { a = normalize(a); } a", 1, 57, "expression nodes", limited));
  // A script's own function of the same name still wins (Rhai's lookup order).
  const Model m = run_rhai("fn offset(a, b) { a + b } offset(x, 2)");
  EXPECT_EQ(test::eval_graph<float>(*m.graph, m.root, 1.f, 0.f, 0.f), 3.f);
}

}  // namespace
}  // namespace frep
