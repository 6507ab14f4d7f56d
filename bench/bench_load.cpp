// Loading large expressions: a generated 3-million-line .vm file (a chain of a million `min`
// nodes, as docs/engine.md describes) parsed, hash-consed and compiled; reports time and memory
// (graph bytes per node, the process's peak resident size). Run: build/bench/bench_load
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <string>

#include "frep/eval/tape.hpp"
#include "frep/io/vm.hpp"

namespace {

// x, 997 constants, then a chain m_i = min(m_{i-1}, c_{i mod 997}) of `n` nodes, with a
// two-line detour per link (a square and a sub) so the file has about 3 lines per chain node.
std::string chain_vm(int n) {
  std::string text = "x var-x\n";
  text.reserve(static_cast<std::size_t>(n) * 72);
  for (int k = 0; k < 997; ++k) text += "c" + std::to_string(k) + " const " + std::to_string(k * 0.01 - 3.0) + "\n";
  text += "m0 min x c0\n";
  for (int i = 1; i < n; ++i) {
    const std::string s = std::to_string(i), p = std::to_string(i - 1), c = std::to_string(i % 997);
    text += "q" + s + " square m" + p + "\n";
    text += "d" + s + " sub q" + s + " c" + c + "\n";
    text += "m" + s + " min m" + p + " d" + s + "\n";
  }
  return text;
}

double peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;
}

void BM_LoadVm3MLines(benchmark::State& state) {
  const std::string text = chain_vm(1000000);
  std::size_t lines = 0;
  for (char ch : text) lines += ch == '\n';
  double bytes_per_node = 0;
  std::size_t nodes = 0;
  for (auto _ : state) {
    const frep::Model m = frep::parse_vm(text, "chain.vm");
    const frep::Tape t = frep::Tape::compile(*m.graph, m.root);
    benchmark::DoNotOptimize(t.size());
    nodes = m.graph->size();
    bytes_per_node = static_cast<double>(m.graph->memory_bytes()) / static_cast<double>(nodes);
  }
  state.counters["lines"] = static_cast<double>(lines);
  state.counters["nodes"] = static_cast<double>(nodes);
  state.counters["graph_bytes_per_node"] = bytes_per_node;
  state.counters["peak_rss_MB"] = peak_rss_mb();
}
BENCHMARK(BM_LoadVm3MLines)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
