// Reading a big Rhai script against reading the same expression as .vm. The expression is made
// here: the unsigned distance to a triangulated sphere written the way mesh converters write it
// (per triangle: the plane distance inside the triangle's prism, else the distance to the closest
// edge segment; triangles combined by a balanced min tree; shared edges hash-consed), about
// 2.5 million nodes. Three inputs are read: frep's own Rhai (write_rhai), a naive script with one
// `let` per node (as a simple converter writes it), and .vm (write_vm). The ratios Rhai / .vm are
// printed at the end. Run: build/bench/bench_rhai [--benchmark_filter=...]
// FREP_RHAI_BENCH_TRIANGLES sets the triangle count (default 36000).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "frep/expr/expr.hpp"
#include "frep/script/rhai.hpp"
#include "frep/io/vm.hpp"

namespace {

struct V3 {
  float x, y, z;
};
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
float dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

struct Inputs {
  std::size_t nodes = 0;
  std::string vm, rhai, naive;
};

// Distance from p to segment ab: t = clamp(dot(p - a, d) / dot(d, d), 0, 1), |p - a - t d|.
frep::Expr segment(frep::Expr px, frep::Expr py, frep::Expr pz, V3 a, V3 b) {
  const V3 d = b - a;
  const frep::Expr ax = px - a.x, ay = py - a.y, az = pz - a.z;
  const frep::Expr t = max(min((ax * d.x + ay * d.y + az * d.z) / dot(d, d), 1.0f), 0.0f);
  return sqrt(square(ax - t * d.x) + square(ay - t * d.y) + square(az - t * d.z));
}

frep::Expr triangle(frep::Expr px, frep::Expr py, frep::Expr pz, V3 a, V3 b, V3 c) {
  const V3 n = cross(b - a, c - a);
  const float len = std::sqrt(dot(n, n));
  const V3 u{n.x / len, n.y / len, n.z / len};
  const frep::Expr plane = abs(px * u.x + py * u.y + pz * u.z - dot(u, a));
  // Inside the prism: p is on the inner side of the three planes through the edges along n.
  frep::Expr inside = px.graph().c(1.0f);
  const V3 v[3] = {a, b, c};
  for (int i = 0; i < 3; ++i) {
    const V3 e = v[(i + 1) % 3] - v[i];
    const V3 m = cross(u, e);
    const frep::Expr side = (px - v[i].x) * m.x + (py - v[i].y) * m.y + (pz - v[i].z) * m.z;
    inside = logical_and(inside, compare(side, 0.0f) + 1.0f);  // non-zero unless side < 0
  }
  const frep::Expr edges = min(min(segment(px, py, pz, a, b), segment(px, py, pz, b, c)), segment(px, py, pz, c, a));
  return if_nonzero_else(inside, plane, edges);
}

frep::NodeId balanced_min(frep::Graph& g, const std::vector<frep::NodeId>& items, std::size_t lo, std::size_t hi) {
  if (hi - lo == 1) return items[lo];
  const std::size_t mid = lo + (hi - lo) / 2;
  const frep::NodeId l = balanced_min(g, items, lo, mid);
  return g.binary(frep::Op::Min, l, balanced_min(g, items, mid, hi));
}

// One `let` per node, in node order: what a simple converter writes.
std::string naive_rhai(const frep::Graph& g, frep::NodeId root) {
  std::string out;
  char buf[64];
  for (frep::NodeId id : frep::reachable_nodes(g, root)) {
    const frep::Node& n = g.node(id);
    out += "let t" + std::to_string(id) + " = ";
    switch (n.op) {
      case frep::Op::VarX: out += "x"; break;
      case frep::Op::VarY: out += "y"; break;
      case frep::Op::VarZ: out += "z"; break;
      case frep::Op::Const:
        std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(n.value));
        out += buf;
        if (out.find_first_of(".e", out.size() - std::strlen(buf)) == std::string::npos) out += ".0";
        break;
      case frep::Op::Add: out += "t" + std::to_string(n.a) + " + t" + std::to_string(n.b); break;
      case frep::Op::Sub: out += "t" + std::to_string(n.a) + " - t" + std::to_string(n.b); break;
      case frep::Op::Mul: out += "t" + std::to_string(n.a) + " * t" + std::to_string(n.b); break;
      case frep::Op::Div: out += "t" + std::to_string(n.a) + " / t" + std::to_string(n.b); break;
      case frep::Op::Neg: out += "-t" + std::to_string(n.a); break;
      case frep::Op::Recip: out += "1.0 / t" + std::to_string(n.a); break;
      default:
        out += std::string(frep::op_name(n.op)) + "(t" + std::to_string(n.a);
        if (frep::op_arity(n.op) == 2) out += ", t" + std::to_string(n.b);
        out += ")";
    }
    out += ";\n";
  }
  return out + "t" + std::to_string(root) + "\n";
}

const Inputs& inputs() {
  static const Inputs in = [] {
    int triangles = 36000;
    if (const char* s = std::getenv("FREP_RHAI_BENCH_TRIANGLES")) triangles = std::max(8, std::atoi(s));
    // A UV sphere with about `triangles` triangles.
    const int lat = std::max(2, static_cast<int>(std::sqrt(triangles / 2.0)));
    const int lon = std::max(3, triangles / (2 * lat));
    auto vertex = [&](int i, int j) {
      const double th = M_PI * i / lat, ph = 2 * M_PI * j / lon;
      return V3{static_cast<float>(std::sin(th) * std::cos(ph)), static_cast<float>(std::sin(th) * std::sin(ph)),
                static_cast<float>(std::cos(th))};
    };
    frep::Graph g;
    const frep::Expr px = g.x(), py = g.y(), pz = g.z();
    std::vector<frep::NodeId> tris;
    for (int i = 0; i < lat; ++i) {
      for (int j = 0; j < lon; ++j) {
        const V3 a = vertex(i, j), b = vertex(i + 1, j), c = vertex(i + 1, j + 1), d = vertex(i, j + 1);
        if (i + 1 < lat) tris.push_back(triangle(px, py, pz, a, b, c).id());
        if (i > 0) tris.push_back(triangle(px, py, pz, a, c, d).id());
      }
    }
    const frep::NodeId root = balanced_min(g, tris, 0, tris.size());
    Inputs out;
    out.nodes = frep::reachable_nodes(g, root).size();
    std::ostringstream vm, rhai;
    frep::write_vm(vm, g, root);
    frep::write_rhai(rhai, g, root);
    out.vm = vm.str();
    out.rhai = rhai.str();
    out.naive = naive_rhai(g, root);
    std::fprintf(stderr, "%zu triangles, %zu nodes; .vm %.1f MB, Rhai %.1f MB, one-let-per-node Rhai %.1f MB\n",
                 tris.size(), out.nodes, out.vm.size() / 1e6, out.rhai.size() / 1e6, out.naive.size() / 1e6);
    return out;
  }();
  return in;
}

void report(benchmark::State& state, std::size_t bytes) {
  state.counters["nodes"] = static_cast<double>(inputs().nodes);
  state.counters["ns/node"] = benchmark::Counter(static_cast<double>(inputs().nodes) * state.iterations(),
                                                 benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.SetBytesProcessed(static_cast<std::int64_t>(bytes) * state.iterations());
}

void BM_ReadVm(benchmark::State& state) {
  const std::string& text = inputs().vm;
  for (auto _ : state) {
    frep::Model m = frep::parse_vm(text, "bench.vm");
    benchmark::DoNotOptimize(m.root);
  }
  report(state, text.size());
}

void BM_ReadRhai(benchmark::State& state) {
  const std::string& text = inputs().rhai;
  for (auto _ : state) {
    frep::Model m = frep::parse_rhai(text, "bench.rhai");
    benchmark::DoNotOptimize(m.root);
  }
  report(state, text.size());
}

void BM_ReadRhaiOneLetPerNode(benchmark::State& state) {
  const std::string& text = inputs().naive;
  for (auto _ : state) {
    frep::Model m = frep::parse_rhai(text, "bench_naive.rhai");
    benchmark::DoNotOptimize(m.root);
  }
  report(state, text.size());
}

BENCHMARK(BM_ReadVm)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_ReadRhai)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_ReadRhaiOneLetPerNode)->Unit(benchmark::kMillisecond)->MinTime(2.0);

// Prints the usual table, then the read-time ratios against .vm.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs)
      if (!r.error_occurred && r.iterations > 0) seconds_[r.run_name.function_name] = r.GetAdjustedCPUTime();
    ConsoleReporter::ReportRuns(runs);
  }
  void Finalize() override {
    ConsoleReporter::Finalize();
    auto it = seconds_.find("BM_ReadVm");
    if (it == seconds_.end()) return;
    for (const auto& [name, t] : seconds_)
      if (name != it->first) std::printf("%s / BM_ReadVm = %.2f (CPU time)\n", name.c_str(), t / it->second);
  }

 private:
  std::map<std::string, double> seconds_;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  return 0;
}
