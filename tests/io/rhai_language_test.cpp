// The Rhai language subset: every construct of the issue in a small script, each checked
// against the same expression built in C++ (bit for bit at sample points), plus Rhai's number
// rules (integers, floats, exponents) and the Fidget-specific rules (x, y, z inside functions,
// `%` on expressions, comparisons of expressions refused).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "rhai_test_util.hpp"

namespace frep {
namespace {

using test::script_matches;

float F(double v) { return static_cast<float>(v); }

TEST(RhaiLanguage, LetAndArithmetic) {
  EXPECT_TRUE(script_matches("let a = x * 2; let b = a + y; b", [](Graph& g) { return g.x() * 2.0f + g.y(); }));
  EXPECT_TRUE(script_matches("x - y * z / 2 + -x", [](Graph& g) { return g.x() - g.y() * g.z() / 2.0f + -g.x(); }));
  EXPECT_TRUE(script_matches("(x - y) * (z + 1)", [](Graph& g) { return (g.x() - g.y()) * (g.z() + 1.0f); }));
  EXPECT_TRUE(script_matches("2 - x - y", [](Graph& g) { return 2.0f - g.x() - g.y(); }));
  EXPECT_TRUE(script_matches("+x * 3", [](Graph& g) { return g.x() * 3.0f; }));
}

TEST(RhaiLanguage, AssignmentAndCompoundAssignment) {
  EXPECT_TRUE(script_matches("let a = x; a = a + 1; a -= y; a *= 2; a /= z; a",
                             [](Graph& g) { return (g.x() + 1.0f - g.y()) * 2.0f / g.z(); }));
  EXPECT_TRUE(script_matches("let a = x; a %= 3; a += 0.5; a",
                             [](Graph& g) { return mod(g.x(), 3.0f) + 0.5f; }));
  EXPECT_TRUE(script_matches("let n = 5; n += 2; n -= 1; n *= 3; n /= 4; n %= 3; x * n",
                             [](Graph& g) { return g.x() * 1.0f; }));  // ((5+2-1)*3)/4 = 4; 4 % 3 = 1
}

TEST(RhaiLanguage, BlocksAndScopes) {
  EXPECT_TRUE(script_matches("let a = { let t = x + 1; t * t }; a", [](Graph& g) { return square(g.x() + 1.0f); }));
  // An inner `let` shadows only inside its block; the outer variable is unchanged afterwards.
  EXPECT_TRUE(script_matches("let a = x; { let a = y; a = a * 2; } a + 1", [](Graph& g) { return g.x() + 1.0f; }));
  // Assignment in an inner block changes the outer variable.
  EXPECT_TRUE(script_matches("let a = x; { a = a * 2; } a", [](Graph& g) { return g.x() * 2.0f; }));
  // Shadowing in the same scope; the old value is used on the right.
  EXPECT_TRUE(script_matches("let a = x; let a = a + y; let a = a * a; a",
                             [](Graph& g) { return square(g.x() + g.y()); }));
}

TEST(RhaiLanguage, FunctionsRecursionAndGlobals) {
  EXPECT_TRUE(script_matches("fn double(e) { e * 2 } double(double(x))",
                             [](Graph& g) { return g.x() * 2.0f * 2.0f; }));
  EXPECT_TRUE(script_matches("fn f(n, e) { if n == 0 { e } else { f(n - 1, e * 2) } } f(3, y)",
                             [](Graph& g) { return g.y() * 2.0f * 2.0f * 2.0f; }));
  // Overloading by arity, and calls before the definition (Rhai hoists functions).
  EXPECT_TRUE(script_matches("let r = g(x) + g(x, y);\nfn g(a) { a }\nfn g(a, b) { a * b }\nr",
                             [](Graph& g) { return g.x() + g.x() * g.y(); }));
  // A function defined after the call, found while another function's body runs.
  EXPECT_TRUE(script_matches("fn a(e) { b(e) * 2 }\nlet r = a(x);\nfn b(e) { e + 1 }\nr",
                             [](Graph& g) { return (g.x() + 1.0f) * 2.0f; }));
  // Functions read global variables (frep extension) ...
  EXPECT_TRUE(script_matches("let k = 3; fn add_k(e) { e + k } add_k(z)", [](Graph& g) { return g.z() + 3.0f; }));
  // ... but x, y, z inside a function are the axes, as in Fidget, even if the script rebinds them.
  EXPECT_TRUE(script_matches("let x = x * 2; fn raw() { x } raw() + x", [](Graph& g) { return g.x() + g.x() * 2.0f; }));
  // Parameters are copies; a function's variables do not leak.
  EXPECT_TRUE(script_matches("fn bump(a) { a += 1; let t = 5; a } let a = x; let b = bump(a); a + b",
                             [](Graph& g) { return g.x() + (g.x() + 1.0f); }));
}

TEST(RhaiLanguage, Return) {
  EXPECT_TRUE(script_matches("fn f(e) { if true { return e * 2; } e } f(y)", [](Graph& g) { return g.y() * 2.0f; }));
  EXPECT_TRUE(script_matches("fn f(e) { for i in 0..10 { if i == 2 { return e + i; } } e } f(x)",
                             [](Graph& g) { return g.x() + 2.0f; }));
  // `return` at the top level ends the script with its value.
  EXPECT_TRUE(script_matches("let a = x; return a * 3; a", [](Graph& g) { return g.x() * 3.0f; }));
}

TEST(RhaiLanguage, IfElse) {
  EXPECT_TRUE(script_matches("let a = 5; if a < 3 { x } else if a < 6 { y } else { z }", [](Graph& g) { return g.y(); }));
  EXPECT_TRUE(script_matches("let a = 9; if a < 3 { x } else if a < 6 { y } else { z }", [](Graph& g) { return g.z(); }));
  EXPECT_TRUE(script_matches("let e = x; if 2 > 1 && !(1 > 2) || false { e = e + 1; } e",
                             [](Graph& g) { return g.x() + 1.0f; }));
  EXPECT_TRUE(script_matches("let v = if 1.5 >= 1 { x } else { y }; v * 2", [](Graph& g) { return g.x() * 2.0f; }));
}

TEST(RhaiLanguage, WhileLoopDoBreakContinue) {
  EXPECT_TRUE(script_matches(
      "let i = 0; let acc = x; while true { i += 1; if i > 5 { break; } if i % 2 == 0 { continue; } acc = acc + i; } acc",
      [](Graph& g) { return g.x() + 1.0f + 3.0f + 5.0f; }));
  EXPECT_TRUE(script_matches("let i = 0; loop { i += 1; if i == 3 { break; } } x * i", [](Graph& g) { return g.x() * 3.0f; }));
  EXPECT_TRUE(script_matches("let n = loop { break 4; }; x * n", [](Graph& g) { return g.x() * 4.0f; }));
  EXPECT_TRUE(script_matches("let i = 0; do { i += 2; } while i < 5; x * i", [](Graph& g) { return g.x() * 6.0f; }));
  EXPECT_TRUE(script_matches("let i = 10; do { i += 1; } until i > 3; x * i", [](Graph& g) { return g.x() * 11.0f; }));
}

TEST(RhaiLanguage, ForLoops) {
  EXPECT_TRUE(script_matches("let s = x; for i in 0..3 { s = s * 2 + i } s",
                             [](Graph& g) { return ((g.x() * 2.0f + 0.0f) * 2.0f + 1.0f) * 2.0f + 2.0f; }));
  EXPECT_TRUE(script_matches("let s = x; for i in 1..=3 { s = s + i } s",
                             [](Graph& g) { return g.x() + 1.0f + 2.0f + 3.0f; }));
  EXPECT_TRUE(script_matches("let s = 0; for v in [x, y, z] { s = s + v } s",
                             [](Graph& g) { return 0.0f + g.x() + g.y() + g.z(); }));
  EXPECT_TRUE(script_matches("let s = x; for (v, i) in [10, 20] { s = s + v * i } s",
                             [](Graph& g) { return g.x() + 0.0f + 20.0f; }));
  EXPECT_TRUE(script_matches("let s = x; for i in range(0, 10, 4) { s = s + i } s",
                             [](Graph& g) { return g.x() + 0.0f + 4.0f + 8.0f; }));
  EXPECT_TRUE(script_matches("let s = x; for i in 0..10 { if i == 1 { continue; } if i == 3 { break; } s = s + i } s",
                             [](Graph& g) { return g.x() + 0.0f + 2.0f; }));
  EXPECT_TRUE(script_matches("let n = 0; for c in \"abc\" { n += 1; } x * n", [](Graph& g) { return g.x() * 3.0f; }));
}

TEST(RhaiLanguage, ArraysIndexingLenPush) {
  EXPECT_TRUE(script_matches("let a = [x, y]; a.push(z); a[1] = a[1] * 2; a[0] + a[1] + a[2] + a.len()",
                             [](Graph& g) { return g.x() + g.y() * 2.0f + g.z() + 3.0f; }));
  EXPECT_TRUE(script_matches("let a = [1, 2, 3]; x * len(a) + a[-1]", [](Graph& g) { return g.x() * 3.0f + 3.0f; }));
  EXPECT_TRUE(script_matches("let a = [[x, 1], [y, 2]]; a[1][0] += a[0][1]; a[1][0]",
                             [](Graph& g) { return g.y() + 1.0f; }));
  EXPECT_TRUE(script_matches("let a = []; for i in 0..4 { a.push(i * i); } let b = a; b.pop(); x * (a.len() * 10 + b.len())",
                             [](Graph& g) { return g.x() * 43.0f; }));
  EXPECT_TRUE(script_matches("let a = [1, 2] + [3]; a += 4; a.insert(0, 9); a.remove(1); x * a[0] + a.len()",
                             [](Graph& g) { return g.x() * 9.0f + 4.0f; }));
  EXPECT_TRUE(script_matches("let a = [1, 2, 3]; if 2 in a && !(5 in a) { x } else { y }", [](Graph& g) { return g.x(); }));
  // An array of shapes, where a tree is expected, is their union (Fidget).
  EXPECT_TRUE(script_matches("min([x, y, z], z * 2)",
                             [](Graph& g) { return min(min(g.x(), min(g.y(), g.z())), g.z() * 2.0f); }));
}

TEST(RhaiLanguage, ObjectMaps) {
  EXPECT_TRUE(script_matches("let m = #{ a: x, \"b\": 2 }; m.b += 1; m.c = y; m.a * m.b + m[\"c\"] + m.len()",
                             [](Graph& g) { return g.x() * 3.0f + g.y() + 3.0f; }));
  EXPECT_TRUE(script_matches("let m = #{ p: #{ q: [x] } }; m.p.q.push(y); m.p.q[1]", [](Graph& g) { return g.y(); }));
  EXPECT_TRUE(script_matches("let m = #{ b: 1, a: 2 }; let k = m.keys(); if k[0] == \"a\" && \"b\" in m { x } else { y }",
                             [](Graph& g) { return g.x(); }));
  EXPECT_TRUE(script_matches("let m = #{ a: 1 }; let v = m.missing; if v == () { x } else { y }",
                             [](Graph& g) { return g.x(); }));
}

TEST(RhaiLanguage, StringsAndParseFloat) {
  EXPECT_TRUE(script_matches("let s = \"1.5e2\"; x * parse_float(s)", [](Graph& g) { return g.x() * 150.0f; }));
  EXPECT_TRUE(script_matches("let s = \"a\" + 1 + 'b'; if s == \"a1b\" && s.len() == 3 { x } else { y }",
                             [](Graph& g) { return g.x(); }));
  EXPECT_TRUE(script_matches("x * parse_int(\"ff\", 16) + parse_float(\" -0.25 \")",
                             [](Graph& g) { return g.x() * 255.0f + -0.25f; }));
  EXPECT_TRUE(script_matches("let s = `multi\nline`; if s.len() == 10 && \"tab\\t\\x41\\u00e9\".len() == 6 { x } else { y }",
                             [](Graph& g) { return g.x(); }));
}

TEST(RhaiLanguage, NumbersFollowRhai) {
  EXPECT_TRUE(script_matches("x * 1e3 + 2.5E-2 + 1_000 + 0x10 + 0b101 + 0o17 + 3.",
                             [](Graph& g) { return g.x() * 1000.0f + F(2.5e-2) + 1000.0f + 16.0f + 5.0f + 15.0f + 3.0f; }));
  EXPECT_TRUE(script_matches("x * (7 / 2) + (7.0 / 2) + 7 % -3 + (-7.5) % 2 + 2 ** 10 + 2.0 ** 0.5",
                             [](Graph& g) { return g.x() * 3.0f + 3.5f + 1.0f + -1.5f + 1024.0f + F(std::sqrt(2.0)); }));
  // Numbers are f64 until they meet an expression: 1/3. is rounded to f32 once.
  EXPECT_TRUE(script_matches("x * (1/3. + 1/3.)", [](Graph& g) { return g.x() * F(2.0 / 3.0); }));
  EXPECT_TRUE(script_matches("x * (1 << 4) + (-16 >> 2) + (6 & 3) + (6 | 1) + (6 ^ 3)",
                             [](Graph& g) { return g.x() * 16.0f + -4.0f + 2.0f + 7.0f + 5.0f; }));
  // `2.abs()` is a method call on an integer; `-2.abs()` is abs(-2) (Rhai's lexer).
  EXPECT_TRUE(script_matches("x * 2.abs() + -2.abs()", [](Graph& g) { return g.x() * 2.0f + 2.0f; }));
  // Too large for i64: a float.
  EXPECT_TRUE(script_matches("x * 99999999999999999999", [](Graph& g) { return g.x() * F(1e20); }));
  EXPECT_TRUE(script_matches("let a = 0.1 + 0.2; x * a", [](Graph& g) { return g.x() * F(0.1 + 0.2); }));
}

TEST(RhaiLanguage, Comments) {
  EXPECT_TRUE(script_matches("#!/usr/bin/env rhai\n// line\nlet a = x; /* block /* nested */ still */ a // end",
                             [](Graph& g) { return g.x(); }));
}

TEST(RhaiLanguage, MethodCallsOnExpressionsAndNumbers) {
  EXPECT_TRUE(script_matches("x.abs().sqrt() + (x + y).square() + y.min(z) + 2.max(x)",
                             [](Graph& g) { return sqrt(abs(g.x())) + square(g.x() + g.y()) + min(g.y(), g.z()) + max(2.0f, g.x()); }));
  EXPECT_TRUE(script_matches("fn twice(e, k) { e * k } x.twice(3)", [](Graph& g) { return g.x() * 3.0f; }));
  EXPECT_TRUE(script_matches("(x + y).remap(y, x) + z.remap(x, y, x + 1)",
                             [](Graph& g) { return g.y() + g.x() + (g.x() + 1.0f); }));
  // Older Fidget's name for the 3-axis form, as in its models/cabin.rhai.
  EXPECT_TRUE(script_matches("(x - y).remap_xyz(x, z, y) + remap_xyz(z, y, x, 2)",
                             [](Graph& g) { return (g.x() - g.z()) + 2.0f; }));
}

TEST(RhaiLanguage, ModOnExpressions) {
  EXPECT_TRUE(script_matches("x % 2 + 5 % y + mod(z, 3)",
                             [](Graph& g) { return mod(g.x(), 2.0f) + mod(5.0f, g.y()) + mod(g.z(), 3.0f); }));
}

TEST(RhaiLanguage, RebindingAxes) {
  EXPECT_TRUE(script_matches("let x = x * 30; let y = x + y; x - y", [](Graph& g) {
    const Expr x = g.x() * 30.0f;
    return x - (x + g.y());
  }));
  EXPECT_TRUE(script_matches("let a = axes(); a.x + a.z * 2", [](Graph& g) { return g.x() + g.z() * 2.0f; }));
}

TEST(RhaiLanguage, EveryOpcodeAsAFunction) {
  EXPECT_TRUE(script_matches(
      "let a = x; let b = y;\n"
      "[abs(a), sqrt(a), square(a), floor(a), ceil(a), round(a), sin(a), cos(a), tan(a), asin(a), acos(a), atan(a),\n"
      " exp(a), ln(a), not(a), neg(a), recip(a), min(a, b), max(a, b), compare(a, b), and(a, b), or(a, b),\n"
      " atan2(a, b), mod(a, b), -a, a + b, a - b, a * b, a / b, a % b]",
      [](Graph& g) {
        const Expr a = g.x(), b = g.y();
        std::vector<NodeId> v;
        for (Expr e : {abs(a), sqrt(a), square(a), floor(a), ceil(a), round(a), sin(a), cos(a), tan(a), asin(a), acos(a),
                       atan(a), exp(a), ln(a), logical_not(a), -a, recip(a), min(a, b), max(a, b), compare(a, b),
                       logical_and(a, b), logical_or(a, b), atan2(a, b), mod(a, b), -a, a + b, a - b, a * b, a / b,
                       mod(a, b)})
          v.push_back(e.id());
        // Fidget's union of an array: a balanced tree of min.
        std::function<NodeId(std::size_t, std::size_t)> u = [&](std::size_t lo, std::size_t hi) -> NodeId {
          if (hi - lo == 1) return v[lo];
          const std::size_t mid = lo + (hi - lo) / 2;
          const NodeId l = u(lo, mid);
          return g.binary(Op::Min, l, u(mid, hi));
        };
        return g.expr(u(0, v.size()));
      },
      1.0f));
  // On plain numbers the same functions compute (with the opcode's semantics).
  EXPECT_TRUE(script_matches("x * (compare(1, 2) + and(0, 5) + or(0, 5) + not(0) + min(3, 4) + mod(-1, 3) + atan2(0, 1))",
                             [](Graph& g) { return g.x() * (-1.0f + 0.0f + 5.0f + 1.0f + 3.0f + 2.0f + 0.0f); }));
}

TEST(RhaiLanguage, MathConstants) {
  EXPECT_TRUE(script_matches("x * PI + TAU - E + PHI * SQRT_2 + FRAC_PI_2", [](Graph& g) {
    return g.x() * F(M_PI) + F(2 * M_PI) - F(M_E) + F(1.61803398874989484820 * M_SQRT2) + F(M_PI / 2);
  }));
  // A script may shadow them.
  EXPECT_TRUE(script_matches("let PI = 3; x * PI", [](Graph& g) { return g.x() * 3.0f; }));
}

TEST(RhaiLanguage, DrawAndTheLastValue) {
  EXPECT_TRUE(script_matches("draw(x - 1); 42", [](Graph& g) { return g.x() - 1.0f; }));
  // Several draws: their union.
  EXPECT_TRUE(script_matches("draw(x); draw_rgb(y, 1, 0, 0);", [](Graph& g) { return min(g.x(), g.y()); }));
  // The last value, with or without a semicolon; a number is a constant field.
  EXPECT_TRUE(script_matches("let a = 1; x + a;", [](Graph& g) { return g.x() + 1.0f; }));
  EXPECT_TRUE(script_matches("2.5", [](Graph& g) { return g.c(2.5f); }));
}

TEST(RhaiLanguage, ConstantsCannotChange) {
  EXPECT_TRUE(script_matches("const K = 2; x * K", [](Graph& g) { return g.x() * 2.0f; }));
  EXPECT_TRUE(test::fails_at("const K = 2;\nK = 3;", 2, 1, "constant"));
}

}  // namespace
}  // namespace frep
