// Scripts in the style of Fidget's examples: shapes, transforms and booleans through every call
// form of Fidget's shape library (maps, defaults, positional by type, ordered, transforms as
// methods, reductions), each checked against the same expression built in C++, plus Fidget's
// own documented results (transform order, reflect, move/scale defaults) and its errors.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "rhai_test_util.hpp"

namespace frep {
namespace {

using test::fails_at;
using test::script_matches;

float F(double v) { return static_cast<float>(v); }

Expr circle(Expr x, Expr y, float cx, float cy, float r) { return sqrt(square(x - cx) + square(y - cy)) - r; }
Expr sphere(Expr x, Expr y, Expr z, float cx, float cy, float cz, float r) {
  return sqrt(square(x - cx) + square(y - cy) + square(z - cz)) - r;
}

float at(const Model& m, float x, float y, float z) { return test::eval_graph<float>(*m.graph, m.root, x, y, z); }

TEST(RhaiShapes, CircleInEveryCallForm) {
  auto expected = [](Graph& g) { return circle(g.x(), g.y(), 1, 2, 3); };
  for (const char* s : {"circle(#{ center: [1, 2], radius: 3 })", "circle(#{ center: vec2(1.0, 2.0), radius: 3 })",
                        "circle([1, 2], 3)", "circle(3, [1, 2])", "circle(3, vec2([1, 2]))",
                        "let c = #{ radius: 3 }; c.center = [1, 2]; circle(c)"}) {
    EXPECT_TRUE(script_matches(s, expected)) << s;
  }
  // Defaults: center [0, 0], radius 1.
  EXPECT_TRUE(script_matches("circle()", [](Graph& g) { return circle(g.x(), g.y(), 0, 0, 1); }));
  EXPECT_TRUE(script_matches("circle([1, 2])", [](Graph& g) { return circle(g.x(), g.y(), 1, 2, 1); }));
  EXPECT_TRUE(script_matches("circle(#{ radius: 0.5 })", [](Graph& g) { return circle(g.x(), g.y(), 0, 0, 0.5f); }));
}

TEST(RhaiShapes, SphereRectangleBox) {
  EXPECT_TRUE(script_matches("sphere([1, 2, 3], 2)", [](Graph& g) { return sphere(g.x(), g.y(), g.z(), 1, 2, 3, 2); }));
  EXPECT_TRUE(script_matches("sphere(#{ radius: 3 })", [](Graph& g) { return sphere(g.x(), g.y(), g.z(), 0, 0, 0, 3); }));
  // A Vec2 fills a Vec3 field with a default (z from the default).
  EXPECT_TRUE(script_matches("sphere([1, 1], 4)", [](Graph& g) { return sphere(g.x(), g.y(), g.z(), 1, 1, 0, 4); }));
  EXPECT_TRUE(script_matches("rectangle([0, 0], [1, 2])", [](Graph& g) {
    const Expr x = g.x(), y = g.y();
    return max(max(0.0f - x, x - 1.0f), max(0.0f - y, y - 2.0f));
  }));
  EXPECT_TRUE(script_matches("box(#{ lower: [-1, -2, -3], upper: [1, 2, 3] })", [](Graph& g) {
    const Expr x = g.x(), y = g.y(), z = g.z();
    return max(max(max(-1.0f - x, x - 1.0f), max(-2.0f - y, y - 2.0f)), max(-3.0f - z, z - 3.0f));
  }));
  EXPECT_TRUE(script_matches("box([-1, -2, -3], [1, 2, 3])", [](Graph& g) {
    const Expr x = g.x(), y = g.y(), z = g.z();
    return max(max(max(-1.0f - x, x - 1.0f), max(-2.0f - y, y - 2.0f)), max(-3.0f - z, z - 3.0f));
  }));
}

TEST(RhaiShapes, Booleans) {
  const char* defs = "let a = circle([0, 0], 1); let b = circle([1, 0], 0.5); let c = circle([0, 1], 0.5);\n";
  auto abc = [](Graph& g) {
    return std::array<Expr, 3>{circle(g.x(), g.y(), 0, 0, 1), circle(g.x(), g.y(), 1, 0, 0.5f),
                               circle(g.x(), g.y(), 0, 1, 0.5f)};
  };
  auto with = [&](const char* tail) { return std::string(defs) + tail; };
  // Reductions are balanced trees: [a, b, c] -> min(a, min(b, c)).
  EXPECT_TRUE(script_matches(with("union(a, b, c)"), [&](Graph& g) {
    auto [a, b, c] = abc(g);
    return min(a, min(b, c));
  }));
  EXPECT_TRUE(script_matches(with("union([a, b, c])"), [&](Graph& g) {
    auto [a, b, c] = abc(g);
    return min(a, min(b, c));
  }));
  EXPECT_TRUE(script_matches(with("a.union(b)"), [&](Graph& g) {
    auto [a, b, c] = abc(g);
    return min(a, b);
  }));
  EXPECT_TRUE(script_matches(with("intersection(#{ input: [a, b, c] })"), [&](Graph& g) {
    auto [a, b, c] = abc(g);
    return max(a, max(b, c));
  }));
  EXPECT_TRUE(script_matches(with("difference(a, b)"), [&](Graph& g) {
    auto [a, b, c] = abc(g);
    return max(a, -b);
  }));
  EXPECT_TRUE(script_matches(with("difference(a, [b, c])"), [&](Graph& g) {
    auto [a, b, c] = abc(g);
    return max(a, -min(b, c));
  }));
  EXPECT_TRUE(script_matches(with("inverse(a)"), [&](Graph& g) { return -abc(g)[0]; }));
  EXPECT_TRUE(script_matches(with("blend(a, b, 0.5)"), [&](Graph& g) {
    auto [a, b, c] = abc(g);
    return min(a, b) - F(1.0 / (4.0 * 0.5)) * square(max(0.5f - abs(a - b), 0.0f));
  }));
  EXPECT_TRUE(script_matches(with("blend(#{ a: a, b: b, radius: 0 })"), [&](Graph& g) {
    auto [a, b, c] = abc(g);
    return min(a, b);
  }));
}

TEST(RhaiShapes, MoveAndScaleAreAffineRemaps) {
  // move(offset) evaluates the shape at p - offset; Fidget writes x + (-1).
  EXPECT_TRUE(script_matches("x.move([1, 1])", [](Graph& g) { return g.x() + -1.0f; }));
  EXPECT_TRUE(script_matches("z.move([1, 1])", [](Graph& g) { return g.z(); }));  // z offset defaults to 0
  EXPECT_TRUE(script_matches("z.scale([1, 1])", [](Graph& g) { return g.z(); }));  // z scale defaults to 1
  EXPECT_TRUE(script_matches("circle([0, 0], 1).move(#{ offset: [1, 2] })",
                             [](Graph& g) { return circle(g.x() + -1.0f, g.y() + -2.0f, 0, 0, 1); }));
  EXPECT_TRUE(script_matches("move(sphere(), [1, 2, 3])",
                             [](Graph& g) { return sphere(g.x() + -1.0f, g.y() + -2.0f, g.z() + -3.0f, 0, 0, 0, 1); }));
  EXPECT_TRUE(script_matches("sphere().scale([2, 4, 8])", [](Graph& g) {
    return sphere(0.5f * g.x(), 0.25f * g.y(), 0.125f * g.z(), 0, 0, 0, 1);
  }));
  EXPECT_TRUE(script_matches("scale_uniform(sphere(), 4)",
                             [](Graph& g) { return sphere(0.25f * g.x(), 0.25f * g.y(), 0.25f * g.z(), 0, 0, 0, 1); }));
  // Chains compose into one matrix, as in Fidget: move, then scale by 2 -> 0.5 x + (-1).
  EXPECT_TRUE(script_matches("sphere().move([1, 0, 0]).scale([2, 2, 2])", [](Graph& g) {
    return sphere(0.5f * g.x() + -1.0f, 0.5f * g.y(), 0.5f * g.z(), 0, 0, 0, 1);
  }));
  // An array of shapes where one is expected: their union (Fidget's automatic reduction).
  EXPECT_TRUE(script_matches("[circle([0, 0], 1), circle([2, 0], 1)].move(#{ offset: [1, 0] })", [](Graph& g) {
    const Expr x = g.x() + -1.0f, y = g.y();
    return min(circle(x, y, 0, 0, 1), circle(x, y, 2, 0, 1));
  }));
}

TEST(RhaiShapes, RotateFollowsFidgetsTransformOrder) {
  // Fidget's own test: x moved by -1, then rotated 90 degrees about z.
  const Model m = test::run_rhai("x.move([-1, 0, 0]).rotate_z(90)");
  EXPECT_NEAR(at(m, 0, 0, 0), 1.0f, 1e-6);
  EXPECT_NEAR(at(m, 0, -1, 0), 0.0f, 1e-6);
  EXPECT_NEAR(at(m, 0, 1, 0), 2.0f, 1e-6);
  // A sphere at (1, 0, 0) rotated 90 degrees about z sits at (0, 1, 0); about x, y goes to z.
  const Model s = test::run_rhai("sphere([1, 0, 0], 0.5).rotate(\"z\", 90)");
  EXPECT_NEAR(at(s, 0, 1, 0), -0.5f, 1e-6);
  EXPECT_NEAR(at(s, 1, 0, 0), std::sqrt(2.0f) - 0.5f, 1e-6);
  const Model sx = test::run_rhai("rotate_x(sphere([0, 1, 0], 0.5), 90)");
  EXPECT_NEAR(at(sx, 0, 0, 1), -0.5f, 1e-6);
  // About a center: 180 degrees about z through (1, 0, 0) takes (2, 0, 0) to the origin.
  const Model c = test::run_rhai("rotate(sphere([2, 0, 0], 0.5), #{ axis: [0, 0, 3], angle: 180, center: [1, 0, 0] })");
  EXPECT_NEAR(at(c, 0, 0, 0), -0.5f, 1e-6);
  // Every spelling of the axis gives the same field.
  const Model a = test::run_rhai("sphere([1, 2, 3], 0.5).rotate_y(30)");
  for (const char* s2 : {"sphere([1, 2, 3], 0.5).rotate(axis(\"y\"), 30)", "sphere([1, 2, 3], 0.5).rotate(30, \"Y\")",
                         "rotate(sphere([1, 2, 3], 0.5), #{ axis: y, angle: 30 })"}) {
    const Model b = test::run_rhai(s2);
    EXPECT_TRUE(test::same_field(*a.graph, a.root, *b.graph, b.root)) << s2;
  }
  // Rotations keep distances: the rotated sphere is still a unit-gradient field of radius 0.5.
  for (const test::Point3& p : test::sample_points(1.0f, 50, 3)) {
    const float d = at(a, p.x, p.y, p.z) + 0.5f;
    EXPECT_GE(d, -1e-5f);
  }
}

TEST(RhaiShapes, Reflect) {
  // Fidget's test: x.reflect("yz") and x.reflect("x") are x - x * 2.
  EXPECT_TRUE(script_matches("x.reflect(\"yz\")", [](Graph& g) { return g.x() - 2.0f * g.x(); }));
  EXPECT_TRUE(script_matches("x.reflect(\"x\")", [](Graph& g) { return g.x() - 2.0f * g.x(); }));
  EXPECT_TRUE(script_matches("reflect_x(x + y, 1)", [](Graph& g) { return (g.x() - 2.0f * (g.x() - 1.0f)) + g.y(); }));
  EXPECT_TRUE(script_matches("reflect_z(z, 0.5)", [](Graph& g) { return g.z() - 2.0f * (g.z() - 0.5f); }));
  EXPECT_TRUE(script_matches("reflect(y, plane([0, 2, 0], 1))", [](Graph& g) { return g.y() - 2.0f * (g.y() - 1.0f); }));
  // Fidget's constant for "xy" has the Y axis; reproduced as it is.
  EXPECT_TRUE(script_matches("y.reflect(\"xy\")", [](Graph& g) { return g.y() - 2.0f * g.y(); }));
  // A diagonal plane: p - 2 (dot(a, p)) a with a = (1, 1, 0) / sqrt(2).
  const Model m = test::run_rhai("sphere([1, 0, 0], 0.25).reflect(axis([1, 1, 0]))");
  EXPECT_NEAR(at(m, 0, -1, 0), -0.25f, 1e-6);
}

TEST(RhaiShapes, ExtrudeLoftRevolve) {
  EXPECT_TRUE(script_matches("extrude_z(circle(), -1, 2)", [](Graph& g) {
    const Expr z = g.z();
    return max(circle(g.x(), g.y(), 0, 0, 1), max(-1.0f - z, z - 2.0f));
  }));
  EXPECT_TRUE(script_matches("circle().extrude_z(#{ upper: 3 })", [](Graph& g) {
    const Expr z = g.z();
    return max(circle(g.x(), g.y(), 0, 0, 1), max(0.0f - z, z - 3.0f));
  }));
  // The shape is taken at z = 0.
  EXPECT_TRUE(script_matches("extrude_z(x + z, 0, 1)", [](Graph& g) {
    const Expr z = g.z();
    return max(g.x() + 0.0f, max(0.0f - z, z - 1.0f));
  }));
  EXPECT_TRUE(script_matches("loft_z(circle(), circle([0, 0], 2), 0, 2)", [](Graph& g) {
    const Expr z = g.z();
    const Expr a = circle(g.x(), g.y(), 0, 0, 1), b = circle(g.x(), g.y(), 0, 0, 2);
    return max(((z - 0.0f) * b + (2.0f - z) * a) / 2.0f, max(0.0f - z, z - 2.0f));
  }));
  EXPECT_TRUE(script_matches("revolve_y(circle([2, 0], 0.5))", [](Graph& g) {
    return circle(sqrt(square(g.x()) + square(g.y())), g.y(), 2, 0, 0.5f);
  }));
}

TEST(RhaiShapes, PlanesAxesAndVectors) {
  EXPECT_TRUE(script_matches("plane(\"x\")", [](Graph& g) { return g.x(); }));
  EXPECT_TRUE(script_matches("plane([0, 1, 0], 0.5)", [](Graph& g) { return g.y() - 0.5f; }));
  EXPECT_TRUE(script_matches("draw(plane(#{ axis: \"z\", offset: 2 }))", [](Graph& g) { return g.z() - 2.0f; }));
  EXPECT_TRUE(script_matches("plane([3, 4], 1)",
                             [](Graph& g) { return g.x() * F(0.6) + g.y() * F(0.8) - 1.0f; }));
  EXPECT_TRUE(script_matches("let v = vec2(1, 2) + vec2(1, 1); v.y *= 2; circle(v, v.x)",
                             [](Graph& g) { return circle(g.x(), g.y(), 2, 6, 2); }));
  EXPECT_TRUE(script_matches("let v = -vec3([1, 2]) * 2; sphere(v, 1)",
                             [](Graph& g) { return sphere(g.x(), g.y(), g.z(), -2, -4, -0.0f, 1); }));
}

TEST(RhaiShapes, FidgetsErrors) {
  EXPECT_TRUE(fails_at("circle(#{ radius: 4, xy: [1, 2] })", 1, 1, "field `xy` is not present in Circle"));
  EXPECT_TRUE(fails_at("circle(#{ center: 3.0, radius: 3 })", 1, 1, "field `center` must be Vec2"));
  EXPECT_TRUE(fails_at("rectangle([0, 0], [1, 1, 1])", 1, 1, "argument 2 must be Vec2"));
  EXPECT_TRUE(fails_at("box(#{ lower: [0, 0, 0] })", 1, 1, "field `upper` must be provided for Box"));
  EXPECT_TRUE(fails_at("let s = sphere();\nunion()", 2, 1, "needs at least one shape"));
  EXPECT_TRUE(fails_at("x.scale(2)", 1, 2, "has no argument of type f64"));
  EXPECT_TRUE(fails_at("axis([0, 0, 0])", 1, 1, "too short"));
  EXPECT_TRUE(fails_at("blend(1, x, 0.5)", 1, 1, "argument 1 must be Tree"));
  EXPECT_TRUE(fails_at("x.move(\"up\")", 1, 2, "cannot use string"));
}

}  // namespace
}  // namespace frep
