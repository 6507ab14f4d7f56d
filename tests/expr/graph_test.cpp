// The expression graph: hash-consing, constant folding, and that every algebraic identity applied
// at construction is exact (the folded graph evaluates bit-identically to the unfolded
// semantics, NaN, signed zeros and infinities included). Also million-node chains from .vm text.
#include <gtest/gtest.h>

#include <bit>
#include <chrono>
#include <map>
#include <random>
#include <tuple>
#include <sstream>

#include "frep/expr/expr.hpp"
#include "frep/io/vm.hpp"
#include "test_util.hpp"

namespace frep {
namespace {

using test::fstr;
using test::same_value;

TEST(GraphHashConsing, SameSubexpressionIsTheSameNode) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  EXPECT_EQ(g.var_x(), x.id());
  EXPECT_EQ(g.constant(1.5f), g.constant(1.5f));
  EXPECT_NE(g.constant(0.0f), g.constant(-0.0f));  // distinct bit patterns are distinct constants
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(g.constant(nan), g.constant(nan));
  const NodeId a = (sqrt(square(x - 1) + square(y + 2) + square(z)) - 0.5f).id();
  const std::size_t before = g.size();
  const NodeId b = (sqrt(square(x - 1) + square(y + 2) + square(z)) - 0.5f).id();
  EXPECT_EQ(a, b);
  EXPECT_EQ(g.size(), before);
  EXPECT_EQ((x * y).id(), (y * x).id());
  // min and max keep their order: a (+0, -0) tie returns the second argument.
  EXPECT_NE(min(x, y).id(), min(y, x).id());
  EXPECT_NE(max(x, y).id(), max(y, x).id());
  EXPECT_NE((x - y).id(), (y - x).id());
  EXPECT_NE(atan2(x, y).id(), atan2(y, x).id());
}

// The index keeps a node near its newest argument's slot; a node that is the newest argument of
// many others overflows into the second index. Every use must still find the one node, also
// after the indexes are rebuilt (growth and reserve).
TEST(GraphHashConsing, NodesWithManyUsersShareEveryUse) {
  Graph g;
  std::vector<NodeId> cs;
  for (int i = 0; i < 200; ++i) cs.push_back(g.constant(static_cast<float>(i) + 0.5f));
  const NodeId x = g.var_x();  // newer than every constant: the newest argument of all 200 products
  std::vector<NodeId> products;
  for (NodeId c : cs) products.push_back(g.binary(Op::Mul, c, x));
  const std::size_t size = g.size();
  for (std::size_t i = 0; i < cs.size(); ++i) EXPECT_EQ(g.binary(Op::Mul, x, cs[i]), products[i]);
  g.reserve(100000);  // rebuilds both indexes
  for (std::size_t i = 0; i < cs.size(); ++i) EXPECT_EQ(g.binary(Op::Mul, cs[i], x), products[i]);
  EXPECT_EQ(g.size(), size);
}

// Random graphs, with a few hub nodes that many others use, against a reference table: a node is
// new exactly when the reference has not seen its (op, arguments, value), through several
// growths of the indexes.
TEST(GraphHashConsing, MatchesAReferenceTableOnRandomGraphs) {
  Graph g;
  std::map<std::tuple<int, NodeId, NodeId, std::uint32_t>, NodeId> seen;
  std::mt19937 rng(7);
  std::vector<NodeId> ids{g.var_x(), g.var_y(), g.var_z()};
  for (NodeId id : ids) seen[{static_cast<int>(g.node(id).op), kNoNode, kNoNode, 0u}] = id;
  const Op ops[] = {Op::Sub, Op::Min, Op::Max, Op::Div, Op::Atan2};
  for (int i = 0; i < 300000; ++i) {
    const auto pick = [&]() -> NodeId {
      const std::uint32_t r = rng() % 100;
      if (r < 10) return ids[rng() % 8];                                  // hubs: the oldest nodes
      if (r < 70) return ids[ids.size() - 1 - rng() % std::min<std::size_t>(ids.size(), 32)];  // recent
      return ids[rng() % ids.size()];                                     // anywhere
    };
    NodeId got;
    std::tuple<int, NodeId, NodeId, std::uint32_t> key;
    if (rng() % 4 == 0) {
      const float v = static_cast<float>(rng() % 5000);  // repeats often
      got = g.constant(v);
      key = {static_cast<int>(Op::Const), kNoNode, kNoNode, std::bit_cast<std::uint32_t>(v)};
    } else {
      const Op op = ops[rng() % 5];
      const NodeId a = pick(), b = pick();
      if (a == b || g.is_const(a) || g.is_const(b)) continue;  // no folding or identities here
      got = g.binary(op, a, b);
      key = {static_cast<int>(op), a, b, 0u};
    }
    const auto [it, fresh] = seen.emplace(key, got);
    if (fresh) {
      ASSERT_EQ(got, ids.size()) << "a new node must get the next id (step " << i << ")";
      ids.push_back(got);
    } else {
      ASSERT_EQ(got, it->second) << "a repeated node must be found (step " << i << ")";
    }
  }
  EXPECT_EQ(g.size(), ids.size());
}

// Distance from p to segment [a, b], the branch-free form used by the mesh converter.
Expr segment_distance(Expr px, Expr py, Expr pz, const float a[3], const float b[3]) {
  const float d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const float dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  Expr ax = px - a[0], ay = py - a[1], az = pz - a[2];
  Expr t = min(max((ax * d[0] + ay * d[1] + az * d[2]) / dd, 0.0f), 1.0f);
  return sqrt(square(ax - t * d[0]) + square(ay - t * d[1]) + square(az - t * d[2]));
}

TEST(GraphHashConsing, TriangleEdgeSharedByTwoTrianglesIsOneNode) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  const float v0[3] = {0, 0, 0}, v1[3] = {1, 0, 0}, v2[3] = {0, 1, 0}, v3[3] = {1, 1, 0.5f};
  // Triangle A = (v0, v1, v2), triangle B = (v1, v3, v2): they share edge v1-v2.
  const Expr a01 = segment_distance(x, y, z, v0, v1), a12 = segment_distance(x, y, z, v1, v2),
             a20 = segment_distance(x, y, z, v2, v0);
  const Expr triA = min(min(a01, a12), a20);
  const std::size_t size_after_a = g.size();
  const Expr b12 = segment_distance(x, y, z, v1, v2);
  EXPECT_EQ(b12.id(), a12.id());
  EXPECT_EQ(g.size(), size_after_a) << "rebuilding a shared edge must not add nodes";
  const Expr b23 = segment_distance(x, y, z, v3, v2), b31 = segment_distance(x, y, z, v1, v3);
  const Expr triB = min(min(b12, b23), b31);
  const Expr both = min(triA, triB);
  // The tape holds the shared edge once: count sqrt instructions (one per distinct edge).
  const Tape t = Tape::compile(g, both.id());
  int sqrts = 0;
  for (const SsaInstr& s : t.ssa()) sqrts += s.op == Op::Sqrt;
  EXPECT_EQ(sqrts, 5);
}

TEST(GraphFolding, EveryOpOnConstantsFoldsToTheReferenceValue) {
  std::mt19937_64 rng(21);
  std::vector<float> vals = test::special_floats();
  for (int i = 0; i < 20; ++i) vals.push_back(test::random_float(rng));
  for (Op op : test::ops_of_arity(1)) {
    Graph g;
    for (float a : vals) {
      const NodeId id = g.unary(op, g.constant(a));
      ASSERT_TRUE(g.is_const(id));
      EXPECT_TRUE(same_value(g.node(id).value, op_eval<float>(op, a, 0.0f))) << op_name(op) << "(" << fstr(a) << ")";
    }
  }
  for (Op op : test::ops_of_arity(2)) {
    Graph g;
    for (float a : vals)
      for (float b : vals) {
        const NodeId id = g.binary(op, g.constant(a), g.constant(b));
        ASSERT_TRUE(g.is_const(id));
        ASSERT_TRUE(same_value(g.node(id).value, op_eval<float>(op, a, b)))
            << op_name(op) << "(" << fstr(a) << ", " << fstr(b) << ") folded to " << fstr(g.node(id).value);
      }
  }
  Graph g;
  auto x = g.x();
  EXPECT_TRUE(g.is_const((sin(g.c(1)) * g.c(2) + exp(g.c(0))).id()));
  EXPECT_FALSE(g.is_const((x * 0.0f).id())) << "x * 0 is not 0 (NaN, inf, -0)";
  EXPECT_FALSE(g.is_const((x - x).id())) << "x - x is not 0 (NaN, inf)";
}

// Argument forms that trigger every identity in Graph::unary / Graph::binary.
struct Form {
  std::string name;
  std::function<NodeId(Graph&)> build;
  std::function<float(float, float)> eval;  // unfolded semantics at (x, y)
};

std::vector<Form> argument_forms() {
  std::vector<Form> f;
  f.push_back({"x", [](Graph& g) { return g.var_x(); }, [](float x, float) { return x; }});
  f.push_back({"y", [](Graph& g) { return g.var_y(); }, [](float, float y) { return y; }});
  f.push_back({"-x", [](Graph& g) { return g.unary(Op::Neg, g.var_x()); },
               [](float x, float) { return op_eval<float>(Op::Neg, x, 0); }});
  f.push_back({"-y", [](Graph& g) { return g.unary(Op::Neg, g.var_y()); },
               [](float, float y) { return op_eval<float>(Op::Neg, y, 0); }});
  f.push_back({"|x|", [](Graph& g) { return g.unary(Op::Abs, g.var_x()); },
               [](float x, float) { return op_eval<float>(Op::Abs, x, 0); }});
  f.push_back({"-|y|", [](Graph& g) { return g.unary(Op::Neg, g.unary(Op::Abs, g.var_y())); },
               [](float, float y) { return -std::fabs(y); }});
  for (float c : {0.0f, -0.0f, 1.0f, -1.0f, 2.0f, 0.5f, std::numeric_limits<float>::infinity(),
                  -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()}) {
    f.push_back({fstr(c), [c](Graph& g) { return g.constant(c); }, [c](float, float) { return c; }});
  }
  return f;
}

// Builds op(A) / op(A, B) for all forms and checks the graph's tape against the unfolded
// semantics on all pairs of special values. Min/max are compared by value (==) here because of
// their canonical argument order; the bit-level tie is covered by the test after this one.
TEST(GraphIdentities, FoldedGraphEvaluatesLikeTheUnfoldedSemantics) {
  const std::vector<Form> forms = argument_forms();
  std::vector<float> vals = test::special_floats();
  PointEvaluator ev;
  int checked = 0;
  for (Op op : test::ops_of_arity(1)) {
    for (const Form& A : forms) {
      for (const Form& inner : {Form{"", nullptr, nullptr}, Form{"neg", nullptr, nullptr}, Form{"abs", nullptr, nullptr}}) {
        Graph g;
        NodeId a = A.build(g);
        if (inner.name == "neg") a = g.unary(Op::Neg, a);
        if (inner.name == "abs") a = g.unary(Op::Abs, a);
        const Tape t = Tape::compile(g, g.unary(op, a));
        for (float x : vals)
          for (float y : {0.0f, -2.0f}) {
            float av = A.eval(x, y);
            if (inner.name == "neg") av = op_eval<float>(Op::Neg, av, 0);
            if (inner.name == "abs") av = op_eval<float>(Op::Abs, av, 0);
            const float want = op_eval<float>(op, av, 0);
            const float got = ev.eval(t, x, y, 0);
            ++checked;
            ASSERT_TRUE(same_value(got, want)) << op_name(op) << "(" << inner.name << "(" << A.name << ")) at x="
                                               << fstr(x) << ": " << fstr(got) << " vs " << fstr(want);
          }
      }
    }
  }
  for (Op op : test::ops_of_arity(2)) {
    for (const Form& A : forms)
      for (const Form& B : forms) {
        Graph g;
        const NodeId na = A.build(g), nb = B.build(g);
        const Tape t = Tape::compile(g, g.binary(op, na, nb));
        const bool by_value = op == Op::Min || op == Op::Max;
        for (float x : vals)
          for (float y : vals) {
            const float want = op_eval<float>(op, A.eval(x, y), B.eval(x, y));
            const float got = ev.eval(t, x, y, 0);
            ++checked;
            const bool ok = by_value ? (got == want || (std::isnan(got) && std::isnan(want))) : same_value(got, want);
            ASSERT_TRUE(ok) << op_name(op) << "(" << A.name << ", " << B.name << ") at x=" << fstr(x)
                            << " y=" << fstr(y) << ": graph gives " << fstr(got) << ", semantics " << fstr(want);
          }
      }
  }
  EXPECT_GT(checked, 100000);
}

TEST(GraphIdentities, IdentitiesDoFire) {
  Graph g;
  auto x = g.x(), y = g.y();
  EXPECT_EQ((-(-x)).id(), x.id());
  EXPECT_EQ(abs(abs(x)).id(), abs(x).id());
  EXPECT_EQ(abs(-x).id(), abs(x).id());
  EXPECT_EQ(square(-x).id(), square(x).id());
  EXPECT_EQ(square(abs(x)).id(), square(x).id());
  EXPECT_EQ((x + (-0.0f)).id(), x.id());
  EXPECT_EQ((x - 0.0f).id(), x.id());
  EXPECT_EQ((x + (-y)).id(), (x - y).id());
  EXPECT_EQ((x - (-y)).id(), (x + y).id());
  EXPECT_EQ((-0.0f - y).id(), (-y).id());
  EXPECT_EQ((x * 1.0f).id(), x.id());
  EXPECT_EQ((x * -1.0f).id(), (-x).id());
  EXPECT_EQ((x * x).id(), square(x).id());
  EXPECT_EQ((x / 1.0f).id(), x.id());
  EXPECT_EQ((1.0f / x).id(), recip(x).id());
  EXPECT_EQ(max(y, y).id(), y.id());
  // Identities that would not be exact must not fire.
  EXPECT_NE((x + 0.0f).id(), x.id()) << "-0 + 0 = +0";
  EXPECT_NE((x - (-0.0f)).id(), x.id()) << "-0 - -0 = +0";
}

// Regression: min/max used to be put in canonical argument order, but op_min/op_max return the
// second argument on a (+0, -0) tie, so 1 / min(y, x) at x = +0, y = -0 came out -inf instead
// of +inf. Only add and mul (commutative bit for bit) are reordered now.
TEST(GraphIdentities, CommutativeCanonicalOrderKeepsSignedZeroTies) {
  Graph g;
  const NodeId x = g.var_x(), y = g.var_y();
  const NodeId m = g.binary(Op::Min, y, x);  // y has the larger id
  const Tape t = Tape::compile(g, g.unary(Op::Recip, m));
  PointEvaluator ev;
  const float want = op_eval<float>(Op::Recip, op_eval<float>(Op::Min, -0.0f, 0.0f), 0);  // +inf
  EXPECT_TRUE(same_value(ev.eval(t, 0.0f, -0.0f, 0), want)) << "got " << fstr(ev.eval(t, 0.0f, -0.0f, 0));
  const NodeId mx = g.binary(Op::Max, y, x);
  const Tape t2 = Tape::compile(g, g.unary(Op::Recip, mx));
  EXPECT_TRUE(same_value(ev.eval(t2, 0.0f, -0.0f, 0), op_eval<float>(Op::Recip, op_eval<float>(Op::Max, -0.0f, 0.0f), 0)));
}

// ---------------------------------------------------------------------------------------------
// Million-node chains: load from .vm text, evaluate, print. Nothing may recurse per node.

TEST(GraphScale, MillionMinChainLoadsFromVmEvaluatesAndPrints) {
  constexpr int kN = 1000000;
  std::string text;
  text.reserve(static_cast<std::size_t>(kN) * 24);
  text += "x var-x\n";
  for (int k = 0; k < 997; ++k) text += "c" + std::to_string(k) + " const " + std::to_string(k * 0.01 - 3.0) + "\n";
  text += "m0 min x c0\n";
  for (int i = 1; i < kN; ++i) {
    text += 'm';
    text += std::to_string(i);
    text += " min m";
    text += std::to_string(i - 1);
    text += " c";
    text += std::to_string(i % 997);
    text += '\n';
  }
  const auto t0 = std::chrono::steady_clock::now();
  const Model m = parse_vm(text, "chain.vm");
  std::string().swap(text);
  const Tape t = Tape::compile(*m.graph, m.root);
  EXPECT_GE(t.size(), static_cast<std::size_t>(kN));
  PointEvaluator pe;
  EXPECT_EQ(pe.eval(t, 5.0f, 0, 0), -3.0f);
  EXPECT_EQ(pe.eval(t, -10.0f, 0, 0), -10.0f);
  float xs[3] = {5, -10, -2.995f}, zeros[3] = {0, 0, 0}, out[3];
  BatchEvaluator be;
  be.eval(t, xs, zeros, zeros, out, 3);
  EXPECT_EQ(out[0], -3.0f);
  EXPECT_EQ(out[1], -10.0f);
  IntervalEvaluator ie;
  const Interval r = ie.eval(t, {-1, 1}, {0, 0}, {0, 0});
  EXPECT_EQ(r.lo, -3.0f);
  EXPECT_EQ(r.hi, -3.0f);
  Tape s;
  ie.simplify(t, {-20, -19}, {0, 0}, {0, 0}, s);
  EXPECT_LE(s.size(), 3u) << "on x in [-20, -19] the chain is just x";
  GradEvaluator ge;
  EXPECT_EQ(ge.eval(t, -10.0f, 0, 0).dx, 1.0f);
  std::ostringstream os;
  write_vm(os, *m.graph, m.root);
  const std::string printed = os.str();
  EXPECT_EQ(std::count(printed.begin(), printed.end(), '\n'), static_cast<long>(kN + 998));
  const Model again = parse_vm(printed, "printed.vm");
  EXPECT_EQ(pe.eval(Tape::compile(*again.graph, again.root), -2.995f, 0, 0), pe.eval(t, -2.995f, 0, 0));
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(secs, 30.0);
}

TEST(GraphScale, MillionDeepAddNegChain) {
  constexpr int kN = 500000;  // pairs: 1,000,000 nodes alternating add and neg
  std::string text = "v0 var-x\none const 1\n";
  text.reserve(static_cast<std::size_t>(kN) * 36);
  for (int i = 0; i < kN; ++i) {
    text += "n" + std::to_string(i) + " neg v" + std::to_string(i) + "\n";
    text += "v" + std::to_string(i + 1) + " add n" + std::to_string(i) + " one\n";
  }
  const Model m = parse_vm(text, "deep.vm");
  const Tape t = Tape::compile(*m.graph, m.root);
  EXPECT_GE(t.size(), static_cast<std::size_t>(2 * kN));
  // v_{k+1} = 1 - v_k: after an even number of steps v = x.
  PointEvaluator pe;
  EXPECT_EQ(pe.eval(t, 0.25f, 0, 0), 0.25f);
  GradEvaluator ge;
  const Grad gr = ge.eval(t, 0.25f, 0, 0);
  EXPECT_EQ(gr.v, 0.25f);
  EXPECT_EQ(gr.dx, 1.0f);
  IntervalEvaluator ie;
  const Interval r = ie.eval(t, {0, 1}, {0, 0}, {0, 0});
  EXPECT_TRUE(r.contains(0.0f) && r.contains(1.0f));
  std::ostringstream os;
  write_vm(os, *m.graph, m.root);
  const std::string printed = os.str();
  EXPECT_EQ(std::count(printed.begin(), printed.end(), '\n'), static_cast<long>(2 * kN + 2));

  // The same depth built in C++ through the Expr handles.
  Graph g;
  Expr acc = g.x();
  for (int i = 0; i < kN; ++i) acc = -acc + 1.0f;
  EXPECT_EQ(pe.eval(Tape::compile(g, acc.id()), 0.25f, 0, 0), 0.25f);
}

TEST(GraphOperators, ReadLikeMath) {
  Graph g;
  auto x = g.x(), y = g.y();
  auto box = max(abs(x) - 1, abs(y) - 1);
  const Tape t = Tape::compile(g, box.id());
  PointEvaluator ev;
  EXPECT_FLOAT_EQ(ev.eval(t, 0, 0, 0), -1.0f);
  EXPECT_FLOAT_EQ(ev.eval(t, 2, 0.5f, 0), 1.0f);
  EXPECT_FLOAT_EQ(ev.eval(t, -1.5f, 3, 0), 2.0f);
}

TEST(GraphScale, MemoryPerNodeIsAsDocumented) {
  Graph g;
  auto x = g.x();
  Expr acc = x;
  for (int i = 0; i < 1000000; ++i) acc = min(acc, x - static_cast<float>(i) * 1e-3f);
  // docs/engine.md: 16 bytes per node plus a hash index of 8-byte slots at most half full (32 to
  // 48 bytes per node), plus the node vector's growth slack.
  EXPECT_LE(g.memory_bytes(), g.size() * 64);
  EXPECT_GE(g.memory_bytes(), g.size() * 32);
  Graph sized;
  sized.reserve(g.size());
  const std::size_t before = sized.memory_bytes();
  Expr again = sized.x();
  for (int i = 0; i < 1000000; ++i) again = min(again, sized.x() - static_cast<float>(i) * 1e-3f);
  EXPECT_EQ(sized.memory_bytes(), before) << "reserve() leaves nothing to reallocate";
  EXPECT_LE(sized.memory_bytes(), sized.size() * 48);
}

}  // namespace
}  // namespace frep
