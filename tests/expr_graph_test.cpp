#include <gtest/gtest.h>

#include <cmath>

#include "frep/eval/evaluators.hpp"
#include "frep/eval/tape.hpp"
#include "frep/expr/expr.hpp"

namespace frep {
namespace {

TEST(Graph, HashConsingMakesOneNodePerSubexpression) {
  Graph g;
  auto x = g.x(), y = g.y();
  auto a = square(x - 1) + square(y);
  auto b = square(x - 1) + square(y);
  EXPECT_EQ(a.id(), b.id());
  EXPECT_EQ((x + y).id(), (y + x).id());  // add and mul are canonical
  EXPECT_EQ((x * y).id(), (y * x).id());
  const std::size_t before = g.size();
  auto c = square(x - 1.0f);
  (void)c;
  EXPECT_EQ(g.size(), before);
}

TEST(Graph, FoldsConstantsAndExactIdentities) {
  Graph g;
  auto x = g.x();
  EXPECT_TRUE(g.is_const((g.c(2) * g.c(3) + 1).id()));
  EXPECT_EQ(g.node((g.c(2) * g.c(3) + 1).id()).value, 7.0f);
  EXPECT_EQ((x * 1.0f).id(), x.id());
  EXPECT_EQ((-(-x)).id(), x.id());
  EXPECT_EQ(min(x, x).id(), x.id());
  EXPECT_EQ(logical_and(g.c(0), x).id(), g.c(0).id());
  EXPECT_EQ(logical_and(g.c(2), x).id(), x.id());
  EXPECT_EQ(logical_or(g.c(2), x).id(), g.c(2).id());
}

TEST(Graph, OperatorsReadLikeMath) {
  Graph g;
  auto x = g.x(), y = g.y();
  auto box = max(abs(x) - 1, abs(y) - 1);
  const Tape t = Tape::compile(g, box.id());
  PointEvaluator ev;
  EXPECT_FLOAT_EQ(ev.eval(t, 0, 0, 0), -1.0f);
  EXPECT_FLOAT_EQ(ev.eval(t, 2, 0.5f, 0), 1.0f);
  EXPECT_FLOAT_EQ(ev.eval(t, -1.5f, 3, 0), 2.0f);
}

TEST(Graph, MillionNodeMinChainCompilesAndEvaluates) {
  Graph g;
  auto x = g.x();
  Expr acc = x;
  for (int i = 0; i < 1000000; ++i) acc = min(acc, x - static_cast<float>(i) * 1e-3f);
  const Tape t = Tape::compile(g, acc.id());
  EXPECT_GE(t.size(), 1000000u);
  PointEvaluator ev;
  EXPECT_FLOAT_EQ(ev.eval(t, 0, 0, 0), -999.999f);
  EXPECT_LE(g.memory_bytes(), g.size() * 48) << "documented: 24 to 32 bytes per node, plus vector slack";
}

}  // namespace
}  // namespace frep
