// Tests of the LaTeX exporter. The mathematics is read back by an independent reader
// (latex_reader.hpp) and evaluated in double against the graph; the structure is checked
// (definitions, cases, wrapping, constants); documents compile with pdflatex where installed.
#include <gtest/gtest.h>

#include <regex>
#include <set>
#include <sstream>

#include "export_test_util.hpp"
#include "frep/error.hpp"
#include "frep/export/latex.hpp"
#include "frep/expr/expr.hpp"
#include "frep/script/load.hpp"
#include "latex_reader.hpp"
#include "test_util.hpp"

namespace frep::test {
namespace {

std::string latex(const Graph& g, NodeId root, LatexOptions opt = {}) {
  std::ostringstream out;
  write_latex(out, g, root, opt);
  return out.str();
}

std::string fragment(const Graph& g, NodeId root) {
  LatexOptions opt;
  opt.standalone = false;
  return latex(g, root, opt);
}

// Fraction of points where the mathematics disagrees with the graph (double evaluation of both;
// the text regroups sums and products, so values agree to rounding, not bit for bit). Points
// where the graph's value is not finite are skipped: mathematics says nothing about NaN.
double disagreement(const Graph& g, NodeId root, const LatexMath& m, std::mt19937_64& rng, int points,
                    std::string* example) {
  int bad = 0, counted = 0;
  for (int i = 0; i < points; ++i) {
    std::uniform_real_distribution<double> u(-3, 3);
    const double x = static_cast<float>(u(rng)), y = static_cast<float>(u(rng)), z = static_cast<float>(u(rng));
    const double want = eval_graph<double>(g, root, x, y, z);
    if (!std::isfinite(want)) continue;
    ++counted;
    const double got = m.eval(x, y, z);
    if (!(std::fabs(got - want) <= 1e-7 * (1 + std::fabs(want)))) {
      if (++bad == 1 && example)
        *example = "at (" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z) +
                   "): latex " + std::to_string(got) + ", graph " + std::to_string(want);
    }
  }
  return counted ? static_cast<double>(bad) / counted : 0.0;
}

// Continuous ops only: the mathematics must agree everywhere (up to rounding).
TEST(LatexExport, ContinuousRandomExpressionsMeanTheSame) {
  Graph g;
  const std::vector<Op> ops = {Op::Add, Op::Sub, Op::Mul, Op::Div, Op::Neg, Op::Square, Op::Sqrt, Op::Abs,
                               Op::Min, Op::Max, Op::Sin, Op::Cos, Op::Exp, Op::Recip, Op::Atan};
  std::mt19937_64 rng(7);
  GenOptions opt;
  opt.ops = ops;
  opt.special_const_prob = 0;
  for (int i = 0; i < 200; ++i) {
    ExprGen gen(g, rng, opt);
    const NodeId root = gen.gen();
    const std::string text = fragment(g, root);
    SCOPED_TRACE(text.substr(0, 3000));
    try {
      const LatexMath m(text);
      std::string ex;
      EXPECT_EQ(disagreement(g, root, m, rng, 40, &ex), 0.0) << ex;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "cannot read back: " << e.what();
    }
  }
}

// Every op, with selects: discontinuous ops (floor, compare, mod, conditions) may flip on
// rounding differences at a few points, nothing more.
TEST(LatexExport, RandomExpressionsOverEveryOpcodeMeanTheSame) {
  Graph g;
  std::mt19937_64 rng(8);
  GenOptions opt;
  opt.special_const_prob = 0;
  double worst = 0;
  std::vector<bool> used(kOpCount, false);
  for (int i = 0; i < 300; ++i) {
    ExprGen gen(g, rng, opt);
    NodeId root = gen.gen();
    if (i % 3 == 0) {  // a select on top, with a condition made of logic, so that cases are exercised
      GenOptions logic = opt;
      logic.ops = {Op::And, Op::Or, Op::Not, Op::Compare, Op::Compare, Op::Sub};
      ExprGen cond(g, rng, logic), more(g, rng, opt);
      root = if_nonzero_else(g.expr(cond.gen(4)), g.expr(more.gen(3)), g.expr(root)).id();
    }
    for (NodeId id : reachable_nodes(g, root)) used[static_cast<int>(g.node(id).op)] = true;
    const std::string text = fragment(g, root);
    SCOPED_TRACE(text.substr(0, 3000));
    try {
      const LatexMath m(text);
      std::string ex;
      const double d = disagreement(g, root, m, rng, 40, &ex);
      worst = std::max(worst, d);
      EXPECT_LE(d, 0.1) << ex;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "cannot read back: " << e.what();
    }
  }
  for (int op = 0; op < kOpCount; ++op) EXPECT_TRUE(used[op]) << "not covered: " << op_name(static_cast<Op>(op));
  std::printf("worst disagreement on one expression: %.1f%% of points\n", 100 * worst);
}

TEST(LatexExport, SharedModelsReadBackAndMeanTheSame) {
  for (const char* name : {"bear.vm", "prospero.vm", "hi.vm", "quarter.vm", "tanglecube.vm"}) {
    SCOPED_TRACE(name);
    if (!have_data(name)) {
      std::printf("[ SKIPPED  ] shared data not found: %s\n", data_file(name).c_str());
      continue;
    }
    const Model m = load_expression(data_file(name));
    const std::string text = latex(*m.graph, m.root);
    try {
      const LatexMath math(text);
      std::mt19937_64 rng(3);
      std::string ex;
      EXPECT_EQ(disagreement(*m.graph, m.root, math, rng, 300, &ex), 0.0) << ex;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "cannot read back: " << e.what();
    }
  }
}

TEST(LatexExport, ReaderRejectsWrongMathematics) {  // the checks above can fail
  Graph g;
  auto x = g.x(), y = g.y();
  const NodeId root = (x - (y - 1.0f)).id();
  std::string text = fragment(g, root);
  const LatexMath good(text);
  std::mt19937_64 rng(1);
  EXPECT_EQ(disagreement(g, root, good, rng, 20, nullptr), 0.0);
  const std::size_t at = text.find("+ 1");
  ASSERT_NE(at, std::string::npos) << text;
  text[at] = '-';
  const LatexMath wrong(text);
  EXPECT_GT(disagreement(g, root, wrong, rng, 20, nullptr), 0.5);
  EXPECT_THROW(LatexMath("\\begin{align*}\nf(x) &= \\foo(x)\n\\end{align*}\n"), std::runtime_error);
  EXPECT_THROW(LatexMath("\\begin{align*}\nf(x) &= d_{1}\n\\end{align*}\n"), std::runtime_error);
}

TEST(LatexExport, SelectsBecomeCasesTriedInOrder) {
  Graph g;
  auto x = g.x(), y = g.y();
  auto inner = if_nonzero_else(compare(y, 0.0f), x - y, x + y);
  auto f = if_nonzero_else(compare(x, 1.0f), sqrt(x), inner);
  const std::string text = fragment(g, f.id());
  EXPECT_NE(text.find("\\begin{cases} \\sqrt{x} & \\text{if } x \\neq 1 \\\\ x - y & \\text{else if } y \\neq 0 \\\\ "
                      "x + y & \\text{otherwise} \\end{cases}"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("d_{"), std::string::npos) << "the condition's two uses are one in the mathematics: " << text;
  // Conditions built from not/and/or read as logic.
  auto c = logical_and(compare(x, y), logical_not(compare(y, 2.0f)));
  const std::string t2 = fragment(g, if_nonzero_else(c, x, y).id());
  EXPECT_NE(t2.find("\\text{if } x \\neq y \\land y = 2"), std::string::npos) << t2;
  const std::string t3 = fragment(g, logical_not(logical_or(x, compare(x, y))).id());
  EXPECT_NE(t3.find("[x = 0 \\land x = y]"), std::string::npos) << t3;
}

TEST(LatexExport, LongSelectChainsSplitIntoSeveralCases) {
  Graph g;
  auto x = g.x();
  Expr e = x;
  for (int i = 0; i < 100; ++i) e = if_nonzero_else(compare(x, static_cast<float>(i)), e + 1.0f, x * static_cast<float>(i));
  const std::string text = fragment(g, e.id());
  const LatexMath m(text);
  std::mt19937_64 rng(2);
  EXPECT_EQ(disagreement(g, e.id(), m, rng, 50, nullptr), 0.0);
  std::size_t envs = 0;
  for (std::size_t at = text.find("\\begin{cases}"); at != std::string::npos; at = text.find("\\begin{cases}", at + 1)) {
    ++envs;
    const std::size_t end = text.find("\\end{cases}", at);
    std::size_t rows = 1;
    for (std::size_t r = text.find("\\\\", at); r < end; r = text.find("\\\\", r + 2)) ++rows;
    EXPECT_LE(rows, 16u);
  }
  EXPECT_GE(envs, 7u);
}

TEST(LatexExport, SharedSubexpressionsAreNamedOnceAndShortOnesRepeated) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  auto r = sqrt(square(x) + square(y) + square(z));  // shared, long: a definition
  auto f = max(r - 1.0f, min(r * 2.0f, square(x) - r));  // x^2 is shared but short
  const std::string text = fragment(g, f.id());
  EXPECT_NE(text.find("d_{1} &= \\sqrt{"), std::string::npos) << text;
  EXPECT_EQ(text.find("d_{2}"), std::string::npos) << text;
  EXPECT_NE(text.find("f(x, y, z) &= \\max(d_{1} - 1, \\min(2 d_{1}, x^{2} - d_{1}))"), std::string::npos) << text;
}

TEST(LatexExport, LongSumsAndMinimaWrapAndStayReadable) {
  Graph g;
  auto x = g.x(), y = g.y();
  Expr sum = g.c(0.5f), mn = x;
  for (int i = 1; i <= 200; ++i) {
    sum = sum + static_cast<float>(i) * square(x - static_cast<float>(i) * 0.01f);
    mn = min(mn, sqrt(square(x - static_cast<float>(i)) + square(y)) - 0.25f);
  }
  for (const Expr& e : {sum, mn, max(sum, mn)}) {
    const std::string text = fragment(g, e.id());
    const LatexMath m(text);
    EXPECT_GT(m.rows(), 20);
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) EXPECT_LT(line.size(), 200u) << line;
    std::mt19937_64 rng(4);
    EXPECT_EQ(disagreement(g, e.id(), m, rng, 30, nullptr), 0.0);
  }
}

TEST(LatexExport, ConstantsAreCompact) {
  Graph g;
  auto x = g.x();
  const std::string text = fragment(g, (x * 0.1f + x * 1e-5f + x * 2.5e20f - 3.0f + x / 30.555555f).id());
  for (const char* want : {"0.1 x", "10^{-5}", "2.5 \\cdot 10^{20}", "- 3", "30.555555"})
    EXPECT_NE(text.find(want), std::string::npos) << want << " in " << text;
  LatexOptions opt;
  opt.standalone = false;
  opt.digits = 3;
  const std::string rounded = latex(g, (x * 0.123456f).id(), opt);
  EXPECT_NE(rounded.find("0.123 x"), std::string::npos) << rounded;
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_NE(fragment(g, min(x, g.c(inf)).id()).find("\\infty"), std::string::npos);
}

TEST(LatexExport, DocumentAndOptions) {
  Graph g;
  auto x = g.x();
  LatexOptions opt;
  opt.source = "my_model#1.vm";
  const std::string doc = latex(g, (x - 1.0f).id(), opt);
  EXPECT_EQ(doc.find("\\documentclass"), doc.find('\n') + 1) << doc;
  EXPECT_NE(doc.find("\\texttt{my\\_model\\#1.vm}"), std::string::npos) << doc;
  EXPECT_NE(doc.find("\\end{document}"), std::string::npos);
  EXPECT_EQ(fragment(g, x.id()).find("\\documentclass"), std::string::npos);
  EXPECT_NE(fragment(g, g.constant(2)).find("f &= 2"), std::string::npos);
  for (int bad : {-1, 10}) {
    LatexOptions o;
    o.digits = bad;
    EXPECT_THROW(latex(g, x.id(), o), InputError);
  }
  LatexOptions o;
  o.line_width = 5;
  EXPECT_THROW(latex(g, x.id(), o), InputError);
}

// Every command the exporter can write; pdflatex is the real check where it is installed.
void expect_known_syntax(const std::string& doc) {
  static const std::set<std::string> known = {
      "documentclass", "usepackage", "allowdisplaybreaks", "begin", "end", "section", "texttt", "noindent",
      "operatorname", "frac", "sqrt", "left", "right", "lfloor", "rfloor", "lceil", "rceil", "min", "max",
      "sin", "cos", "tan", "arcsin", "arccos", "arctan", "exp", "ln", "bmod", "cdot", "neq", "land", "lor",
      "text", "qquad", "bigl", "bigr", "infty", "mathrm", "_", "#", "textbackslash", "$", "&", "%", "{", "}", "^", "~"};
  int depth = 0;
  for (std::size_t i = 0; i < doc.size(); ++i) {
    if (doc[i] == '%' && (i == 0 || doc[i - 1] != '\\')) {
      i = doc.find('\n', i);
      if (i == std::string::npos) break;
      continue;
    }
    if (doc[i] == '{') ++depth;
    if (doc[i] == '}') --depth;
    ASSERT_GE(depth, 0) << "unbalanced } at " << i;
    if (doc[i] == '\\' && i + 1 < doc.size()) {
      std::size_t j = i + 1;
      while (j < doc.size() && std::isalpha(static_cast<unsigned char>(doc[j]))) ++j;
      const std::string name = j > i + 1 ? doc.substr(i + 1, j - i - 1) : doc.substr(i + 1, 1);
      if (name != "\\" && name != "|" && name != "(" && name != ")" && name != "[" && name != "]") {
        EXPECT_TRUE(known.count(name)) << "unknown command \\" << name;
      }
      i = j > i + 1 ? j - 1 : i + 1;
    }
  }
  EXPECT_EQ(depth, 0);
  std::size_t lefts = 0, rights = 0, begins = 0, ends = 0;
  for (std::size_t at = doc.find("\\left"); at != std::string::npos; at = doc.find("\\left", at + 1)) ++lefts;
  for (std::size_t at = doc.find("\\right"); at != std::string::npos; at = doc.find("\\right", at + 1)) ++rights;
  for (std::size_t at = doc.find("\\begin{"); at != std::string::npos; at = doc.find("\\begin{", at + 1)) ++begins;
  for (std::size_t at = doc.find("\\end{"); at != std::string::npos; at = doc.find("\\end{", at + 1)) ++ends;
  EXPECT_EQ(lefts, rights);
  EXPECT_EQ(begins, ends);
}

TEST(LatexExport, SyntaxIsBalancedAndKnown) {
  Graph g;
  const std::vector<NodeId> roots = random_expressions(g, 51, 100);
  for (NodeId r : roots) expect_known_syntax(latex(g, r));
  for (const char* name : {"bear.vm", "prospero.vm"})
    if (have_data(name)) {
      const Model m = load_expression(data_file(name));
      expect_known_syntax(latex(*m.graph, m.root));
    }
}

void expect_pdflatex(const ScratchDir& dir, const std::string& name, const std::string& doc) {
  write_text(dir.path(name + ".tex"), doc);
  const CommandResult r = run_command("cd " + shell_quote(dir.dir().string()) +
                                          " && pdflatex -interaction=nonstopmode -halt-on-error " + shell_quote(name + ".tex"),
                                      dir.path(name + ".out"));
  EXPECT_EQ(r.code, 0) << name << ":\n" << r.output.substr(r.output.size() > 3000 ? r.output.size() - 3000 : 0);
  EXPECT_NE(r.output.find("Output written on"), std::string::npos) << r.output.substr(0, 2000);
}

TEST(LatexExport, DocumentsCompileWithPdflatex) {
  FREP_REQUIRE_PROGRAM("pdflatex");
  ScratchDir dir;
  // Random expressions over every opcode, as fragments in one document.
  Graph g;
  const std::vector<NodeId> roots = random_expressions(g, 61, 40);
  std::string doc = "\\documentclass{article}\n\\usepackage[margin=2cm]{geometry}\n\\usepackage{amsmath}\n"
                    "\\allowdisplaybreaks\n\\begin{document}\n";
  for (NodeId r : roots) doc += fragment(g, r);
  expect_pdflatex(dir, "random", doc + "\\end{document}\n");
  for (const char* name : {"bear.vm", "prospero.vm"})
    if (have_data(name)) {
      const Model m = load_expression(data_file(name));
      LatexOptions opt;
      opt.source = name;
      expect_pdflatex(dir, std::string(name).substr(0, 4), latex(*m.graph, m.root, opt));
    }
}

}  // namespace
}  // namespace frep::test
