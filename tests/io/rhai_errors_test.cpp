// Malformed and runaway Rhai scripts: every error is an InputError naming the line and column
// and saying what was expected; limits (steps, nesting, recursion, value depth) stop scripts with
// a clear message; long straight-line scripts and long chains run without deep recursion.
#include <gtest/gtest.h>

#include <string>

#include "rhai_test_util.hpp"

namespace frep {
namespace {

using test::fails_at;

TEST(RhaiErrors, SyntaxErrorsNameLineAndColumn) {
  EXPECT_TRUE(fails_at("let a = 1;\nlet b = ;", 2, 9, "expected an expression, found `;`"));
  EXPECT_TRUE(fails_at("let a = 1 let b = 2", 1, 11, "expected `;` to end the statement, found `let`"));
  EXPECT_TRUE(fails_at("let = 3;", 1, 5, "expected a variable name after `let`"));
  EXPECT_TRUE(fails_at("min(x, y", 1, 9, "expected `)` to close the argument list, found the end of the script"));
  EXPECT_TRUE(fails_at("let a = [1, 2;", 1, 14, "expected `]` to close the array"));
  EXPECT_TRUE(fails_at("if x > 1 x", 1, 10, "expected `{` after the `if` condition"));
  EXPECT_TRUE(fails_at("fn f(a, a) { a }", 1, 9, "duplicate parameter name"));
  EXPECT_TRUE(fails_at("{ fn g() { 1 } }", 1, 3, "functions can only be defined at the top level"));
  EXPECT_TRUE(fails_at("let s = \"abc\nx", 1, 9, "unterminated string"));
  EXPECT_TRUE(fails_at("x /* never closed", 1, 3, "unterminated block comment"));
  EXPECT_TRUE(fails_at("let a = 1;\n  { let b = 2;\n", 2, 3, "unterminated block"));
  EXPECT_TRUE(fails_at("x @ y", 1, 3, "unexpected character `@`"));
  EXPECT_TRUE(fails_at("1.5.5", 1, 5, "a property or method name after `.`"));
  EXPECT_TRUE(fails_at("0x", 1, 1, "malformed number"));
  EXPECT_TRUE(fails_at("12abc", 1, 3, "malformed number"));
  EXPECT_TRUE(fails_at("\"\\q\"", 1, 2, "malformed escape sequence"));
  EXPECT_TRUE(fails_at("x + 1 = 2", 1, 7, "cannot assign to this"));
  EXPECT_TRUE(fails_at("let a = 1; a++;", 1, 13, "`++` is not an operator in Rhai"));
  EXPECT_TRUE(fails_at("#{ 1: 2 }", 1, 4, "expected a property name"));
  // Column counts characters, not bytes.
  EXPECT_TRUE(fails_at("let s = \"éé\"; let = 1;", 1, 19, "expected a variable name"));
}

TEST(RhaiErrors, UnsupportedFeaturesSaySo) {
  EXPECT_TRUE(fails_at("let n = rand(x);", 1, 9, "`rand` (one of Fidget's newest noise opcodes) is unsupported"));
  EXPECT_TRUE(fails_at("x + 1;\nmix(x, y, 0.5)", 2, 1, "`mix` (one of Fidget's newest noise opcodes) is unsupported"));
  EXPECT_TRUE(fails_at("let f = |a| a + 1;", 1, 9, "closures"));
  EXPECT_TRUE(fails_at("switch x { 1 => x }", 1, 1, "`switch` is not supported"));
  EXPECT_TRUE(fails_at("import \"m\" as m;", 1, 1, "`import` is not supported"));
  EXPECT_TRUE(fails_at("let s = `a${x}`;", 1, 11, "string interpolation"));
  EXPECT_TRUE(fails_at("a?.b", 1, 2, "not supported"));
}

TEST(RhaiErrors, RuntimeErrorsNameLineAndColumn) {
  // Fidget refuses comparisons of trees; frep says why.
  EXPECT_TRUE(fails_at("let a = x;\nif a < 0 { 1 } else { 2 }", 2, 6, "cannot compare expressions with `<`"));
  EXPECT_TRUE(fails_at("x == y", 1, 3, "cannot compare expressions"));
  EXPECT_TRUE(fails_at("if x { 1 }", 1, 4, "a condition cannot depend on an expression"));
  EXPECT_TRUE(fails_at("if 1 { x }", 1, 4, "a condition must be a boolean, not i64"));
  EXPECT_TRUE(fails_at("let a = 1;\nfoo(a)", 2, 1, "unknown function `foo`"));
  EXPECT_TRUE(fails_at("fn f(a) { a }\nf(1, 2)", 2, 1, "function `f` takes 1 argument(s), not 2"));
  EXPECT_TRUE(fails_at("y + q", 1, 5, "variable `q` is not defined"));
  EXPECT_TRUE(fails_at("x.remap_xyz(y, x)", 1, 2, "remap_xyz"));
  EXPECT_TRUE(fails_at("let a = sqrt; a", 1, 9, "`sqrt` is a function, not a variable"));
  EXPECT_TRUE(fails_at("let a = [1, 2];\na[5]", 2, 2, "array index 5 out of bounds (length 2)"));
  EXPECT_TRUE(fails_at("let a = 7 / 0;", 1, 11, "integer division by zero"));
  EXPECT_TRUE(fails_at("9223372036854775807 + 1", 1, 21, "arithmetic overflow"));
  EXPECT_TRUE(fails_at("x ** 2", 1, 3, "`**` is not defined for expressions"));
  EXPECT_TRUE(fails_at("x + \"a\"", 1, 3, "expected an expression (a number, x, y, z or a shape) for the right side of `+`"));
  EXPECT_TRUE(fails_at("x.foo", 1, 2, "Tree has no property `foo`"));
  EXPECT_TRUE(fails_at("let a = 1; a.push(2)", 1, 13, "`push` takes (array, item), not (i64, i64)"));
  EXPECT_TRUE(fails_at("sqrt(\"4\")", 1, 1, "`sqrt` takes a number or an expression"));
  EXPECT_TRUE(fails_at("break;", 1, 1, "`break` or `continue` outside of a loop"));
  EXPECT_TRUE(fails_at("fn f() { g = 1; }\nlet g = 0; f()", 1, 10, "cannot change `g` inside a function"));
  EXPECT_TRUE(fails_at("let a = 1;\nthrow \"bad \" + a;", 2, 1, "the script threw: bad 1"));
  EXPECT_TRUE(fails_at("let a = 1;", 1, 11, "the script produced no shape"));
  EXPECT_TRUE(fails_at("\"text\"", 1, 7, "expected an expression (a number, x, y, z or a shape) for the script's value, got string"));
  EXPECT_TRUE(fails_at("for i in 5 { }", 1, 10, "cannot iterate over i64"));
  EXPECT_TRUE(fails_at("parse_float(\"1.5x\")", 1, 1, "is not a number"));
  EXPECT_TRUE(fails_at("fn f(a) { a }\nfn f(b) { b }\nx", 2, 1, "is defined twice"));
}

TEST(RhaiErrors, RunawayScriptsStopAtTheStepLimit) {
  RhaiOptions o;
  o.max_steps = 100000;
  EXPECT_TRUE(fails_at("let i = 0;\nloop { i += 1; }", 2, 6, "more than 100000 steps", o));
  EXPECT_TRUE(fails_at("let e = x;\nwhile true { e = e + 1; }", 2, 18, "steps", o));
  // The default is far above what straight-line models need: see RhaiErrors.LongScripts.
  o.max_nodes = 5000;
  o.max_steps = 0;
  EXPECT_TRUE(fails_at("let e = x;\nfor i in 0..100000 { e = e * 2 + i; }", 2, 1, "expression nodes", o));
  // A remap that doubles the expression stops before it copies past the limit (by default a
  // share of the machine's memory: this script used to take all of it).
  EXPECT_TRUE(fails_at("let a = sin(x) + cos(y);\nfor i in 0..60 { a = remap(a, sin(a), cos(a), a); }\na", 2, 47,
                       "expression nodes", o));
  // Bulk work costs steps too, so the limit bounds time and memory: doubling arrays and strings,
  // and traversing arrays whose parts are shared (2^100 elements in a few hundred bytes).
  o = RhaiOptions{};
  o.max_steps = 200000;
  EXPECT_TRUE(fails_at("let a = [1];\nloop { a += a; }", 2, 13, "steps", o));
  EXPECT_TRUE(fails_at("let s = \"ab\";\nloop { s += s; }", 2, 13, "steps", o));
  EXPECT_TRUE(fails_at("let a = [1];\nfor i in 0..100 { a = [a, a]; }\nlet b = a;\nb == a", 4, 6, "steps", o));
  EXPECT_TRUE(fails_at("let a = [1];\nfor i in 0..100 { a = [a, a]; }\nto_string(a)", 3, 11, "steps", o));
  EXPECT_TRUE(fails_at("let a = [x];\nfor i in 0..100 { a = [a, a]; }\na + x", 3, 5, "steps", o));
  EXPECT_TRUE(fails_at("let e = x + 1;\nfor i in 0..100 { e = e.remap(x * 2 + e, y, z); }\ne", 2, 45, "steps", o));
}

// The limits docs/rhai.md states, at their boundary: 199 parentheses, 99 calls, blocks or arrays.
TEST(RhaiErrors, NestingLimitsAreWhereTheDocsSay) {
  const auto nest = [](const std::string& open, int n, const std::string& inner, const std::string& close) {
    std::string s;
    for (int i = 0; i < n; ++i) s += open;
    s += inner;
    for (int i = 0; i < n; ++i) s += close;
    return s;
  };
  EXPECT_NO_THROW(test::run_rhai(nest("(", 199, "x", ")")));
  EXPECT_TRUE(fails_at(nest("(", 200, "x", ")"), 1, 201, "nested more than 200 levels"));
  EXPECT_NO_THROW(test::run_rhai(nest("abs(", 99, "x", ")")));
  EXPECT_TRUE(fails_at(nest("abs(", 100, "x", ")"), 1, 401, "nested more than 200 levels"));
  EXPECT_NO_THROW(test::run_rhai(nest("{", 99, "x", "}")));
  EXPECT_TRUE(fails_at(nest("{", 100, "x", "}"), 1, 101, "nested more than 200 levels"));
}

TEST(RhaiErrors, NestingLimitsGiveErrorsNotCrashes) {
  const int n = 100000;
  // Deep parentheses, unary operators, blocks, arrays, calls and `**` chains: a clear error.
  EXPECT_TRUE(fails_at(std::string(n, '(') + "x" + std::string(n, ')'), 1, 201, "nested more than 200 levels"));
  {
    std::string s;
    for (int i = 0; i < n; ++i) s += "- ";
    EXPECT_TRUE(fails_at(s + "x", 1, 399, "nested more than 200 levels"));
  }
  EXPECT_TRUE(fails_at(std::string(n, '{') + std::string(n, '}'), 1, 101, "nested more than 200 levels"));
  EXPECT_TRUE(fails_at(std::string(n, '[') + std::string(n, ']'), 1, 101, "nested more than 200 levels"));
  {
    std::string s;
    for (int i = 0; i < n; ++i) s += "abs(";
    s += "x" + std::string(n, ')');
    EXPECT_TRUE(fails_at(s, 1, 401, "nested more than 200 levels"));
  }
  {
    std::string s = "2";
    for (int i = 0; i < n; ++i) s += " ** 2";
    EXPECT_TRUE(fails_at(s, 1, 1001, "nested more than 200 levels"));
  }
  // Runaway recursion: a clear error at the call depth limit.
  EXPECT_TRUE(fails_at("fn f(n) { f(n + 1) }\nf(0)", 1, 11, "more than 200 levels deep"));
  // Values nested too deeply.
  EXPECT_TRUE(fails_at("let a = [];\nfor i in 0..1000 { a = [a]; }", 2, 24, "nested more than 128 levels"));
  EXPECT_TRUE(fails_at("let a = [];\nfor i in 0..1000 { a.push(a); }", 2, 21, "nested more than 128 levels"));
}

TEST(RhaiErrors, LongScriptsAndChainsRun) {
  // A chain of 50,000 additions (left-nested: evaluated with a loop, not recursion).
  std::string chain = "x";
  for (int i = 0; i < 50000; ++i) chain += " + y";
  Model m = test::run_rhai(chain);
  EXPECT_EQ(test::eval_graph<float>(*m.graph, m.root, 1, 1, 0), 50001.0f);
  // Method and index chains.
  std::string methods = "x";
  for (int i = 0; i < 50000; ++i) methods += ".abs()";
  m = test::run_rhai(methods);
  EXPECT_EQ(test::eval_graph<float>(*m.graph, m.root, -2, 0, 0), 2.0f);
  std::string logic = "let t = true";
  for (int i = 0; i < 50000; ++i) logic += " && true";
  m = test::run_rhai(logic + "; if t { x } else { y }");
  EXPECT_EQ(test::eval_graph<float>(*m.graph, m.root, 3, 4, 0), 3.0f);
  // A converter-like script: many statements, one variable each.
  std::string lines = "let v0 = x;\n";
  for (int i = 1; i < 30000; ++i)
    lines += "let v" + std::to_string(i) + " = min(v" + std::to_string(i - 1) + ", x + " + std::to_string(i) + ");\n";
  lines += "v29999\n";
  m = test::run_rhai(lines);
  EXPECT_EQ(test::eval_graph<float>(*m.graph, m.root, 1, 0, 0), 1.0f);
  // An else-if chain of 10,000 arms (a loop in the parser, not recursion).
  std::string arms = "let k = 9999;\nif k == 0 { 0 }";
  for (int i = 1; i < 10000; ++i) arms += " else if k == " + std::to_string(i) + " { x * " + std::to_string(i) + " }";
  m = test::run_rhai(arms);
  EXPECT_EQ(test::eval_graph<float>(*m.graph, m.root, 1, 0, 0), 9999.0f);
}

}  // namespace
}  // namespace frep
