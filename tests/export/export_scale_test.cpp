// Million-node expressions export without recursion, in linear time: a linear chain of a
// million-long min (what a naive mesh converter emits) and a 150000-deep chain of single-use
// nodes that nothing can flatten. Prints the times; fails only far beyond them (slow machines).
#include <gtest/gtest.h>

#include <chrono>
#include <sstream>

#include "frep/export/c_source.hpp"
#include "frep/export/glsl.hpp"
#include "frep/export/latex.hpp"
#include "frep/expr/expr.hpp"

namespace frep {
namespace {

template <class F>
double seconds(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void export_all(const Graph& g, NodeId root, const char* what) {
  const std::size_t nodes = reachable_nodes(g, root).size();
  struct Format {
    const char* name;
    void (*write)(std::ostream&, const Graph&, NodeId);
  };
  const Format formats[] = {
      {"c", [](std::ostream& o, const Graph& g, NodeId r) { write_c(o, g, r); }},
      {"glsl", [](std::ostream& o, const Graph& g, NodeId r) { write_glsl(o, g, r); }},
      {"latex", [](std::ostream& o, const Graph& g, NodeId r) { write_latex(o, g, r); }},
  };
  for (const Format& f : formats) {
    std::ostringstream out;
    const double s = seconds([&] { f.write(out, g, root); });
    const std::string text = out.str();
    std::printf("%s, %zu nodes, %s: %.2f s, %.1f MB\n", what, nodes, f.name, s, static_cast<double>(text.size()) / 1e6);
    EXPECT_LT(s, 30.0) << f.name;
    EXPECT_GT(text.size(), nodes) << f.name;
    // Complete output: the function or document is closed.
    const std::string tail = text.substr(text.size() - 20);
    EXPECT_TRUE(tail.find(f.name == std::string("latex") ? "\\end{document}" : "}\n") != std::string::npos) << tail;
  }
}

TEST(ExportScale, MillionNodeMinChain) {
  Graph g;
  auto x = g.x(), y = g.y();
  Expr e = x;
  for (int i = 0; i < 125000; ++i) {
    const float t = static_cast<float>(i) * 1e-3f;
    e = min(e, abs(x - t) + abs(y + t) - 0.01f);  // six nodes and two constants per step: 1M in all
  }
  export_all(g, e.id(), "linear min chain");
}

TEST(ExportScale, DeepSingleUseChain) {
  Graph g;
  auto x = g.x();
  Expr e = x;
  for (int i = 0; i < 150000; ++i) e = sqrt(abs(e) + 0.5f);
  export_all(g, e.id(), "deep sqrt chain");
}

}  // namespace
}  // namespace frep
