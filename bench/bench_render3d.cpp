// 3D render benchmark: the pruned column search (1 and 2 threads, warm renderer) against
// brute-force per-pixel column search in the same run, on one model.
//   FREP_RENDER3D_MODEL  a .vm, .rhai or .frep file, or a mesh (converted first; default
//                        ../shared/data/vm/bear.vm)
//   FREP_RENDER3D_LIPSCHITZ  the Lipschitz bound to assume (default: the model's own, 1 for
//                        converted meshes and the files frep convert writes; 0 turns it off)
//   FREP_RENDER3D_SIZE   image size (default 1024)
//   FREP_RENDER3D_VIEW   view direction (default front)
//   FREP_RENDER3D_ROWS   brute force renders every k-th row and is scaled by k (default 16;
//                        1 = the whole image, exact but slow: minutes for the bear at 1024)
//   FREP_TILES           tile sizes, e.g. 256,64,16,4 (tuning; default automatic)
// Before timing, the pruned depth map is checked against brute force on the rows brute force
// renders: depths and normals must be bit-identical; a mismatch aborts the benchmark.
#include <benchmark/benchmark.h>

#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>

#include "frep/convert/convert.hpp"
#include "frep/script/load.hpp"
#include "frep/render/render3d.hpp"

namespace {

std::string env(const char* name, const std::string& fallback) {
  const char* v = std::getenv(name);
  return v && *v ? v : fallback;
}

struct Setup {
  std::string path;
  frep::Model model;
  frep::Tape tape;
  frep::Render3DOptions options;
  int row_step = 16;
  double load_ms = 0;
};

const Setup* setup() {
  static std::optional<Setup> s;
  static bool tried = false;
  if (tried) return s ? &*s : nullptr;
  tried = true;
  Setup st;
  st.path = env("FREP_RENDER3D_MODEL", FREP_SOURCE_DIR "/../shared/data/vm/bear.vm");
  if (!std::filesystem::exists(st.path)) {
    std::fprintf(stderr, "model not found: %s\n", st.path.c_str());
    return nullptr;
  }
  const auto t0 = std::chrono::steady_clock::now();
  st.model = frep::load_field(st.path);
  st.tape = frep::Tape::compile(*st.model.graph, st.model.root);
  st.load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  st.options.size = std::atoi(env("FREP_RENDER3D_SIZE", "1024").c_str());
  if (!frep::parse_view_direction(env("FREP_RENDER3D_VIEW", "front"), st.options.view)) {
    std::fprintf(stderr, "unknown FREP_RENDER3D_VIEW\n");
    return nullptr;
  }
  st.row_step = std::max(1, std::atoi(env("FREP_RENDER3D_ROWS", "16").c_str()));
  st.options.lipschitz = std::atof(env("FREP_RENDER3D_LIPSCHITZ", std::to_string(st.model.info.lipschitz)).c_str());
  if (const char* t = std::getenv("FREP_TILES")) {
    st.options.tiles.clear();
    for (const char* p = t; *p;) {
      st.options.tiles.push_back(std::atoi(p));
      while (*p && *p != ',') ++p;
      if (*p == ',') ++p;
    }
  }
  std::fprintf(stderr, "model %s: %zu instructions, loaded and compiled in %.0f ms; %dx%d, view %s, Lipschitz %g, tiles",
               st.path.c_str(), st.tape.size(), st.load_ms, st.options.size, st.options.size,
               frep::view_direction_name(st.options.view), st.options.lipschitz);
  for (int t : st.options.tiles) std::fprintf(stderr, " %d", t);
  std::fprintf(stderr, "%s\n", st.options.tiles.empty() ? " automatic" : "");
  s = std::move(st);
  return &*s;
}

bool same(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Pruned and brute-force results agree on every row brute force rendered.
void check(const frep::DepthMap& pruned, const frep::DepthMap& brute, int row_step) {
  long hits = 0;
  for (int y = 0; y < pruned.height(); y += row_step)
    for (int x = 0; x < pruned.width(); ++x) {
      const std::size_t p = pruned.index(x, y);
      const bool ok = same(pruned.depth[p], brute.depth[p]) && same(pruned.normal[p].x, brute.normal[p].x) &&
                      same(pruned.normal[p].y, brute.normal[p].y) && same(pruned.normal[p].z, brute.normal[p].z);
      if (!ok) {
        std::fprintf(stderr, "MISMATCH at pixel (%d, %d): depth %.9g vs brute force %.9g\n", x, y, pruned.depth[p],
                     brute.depth[p]);
        std::exit(1);
      }
      hits += pruned.hit(x, y);
    }
  std::fprintf(stderr, "check: pruned render equals brute force on every %d%s row (%ld hits there)\n", row_step,
               row_step == 1 ? "" : "th", hits);
}

void BM_Render3D(benchmark::State& state) {
  const Setup* s = setup();
  if (!s) return state.SkipWithError("model not found");
  frep::Render3DOptions o = s->options;
  o.threads = static_cast<int>(state.range(0));
  frep::Renderer3D renderer(o);
  frep::DepthMap map = renderer.render(s->tape);  // warm-up
  for (auto _ : state) {
    map = renderer.render(s->tape);
    benchmark::DoNotOptimize(map.depth.data());
  }
  long hits = 0;
  for (float d : map.depth) hits += d == d;
  state.counters["hits"] = static_cast<double>(hits);
}
// CPU time is the whole process's (all threads): on a busy machine it is the steadier figure.
BENCHMARK(BM_Render3D)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();

// Brute force on every row_step-th row, reported as the time for the whole image (x row_step);
// one thread, so its CPU time (the cpu_ms counter) is its work.
void BM_Render3DBruteForce(benchmark::State& state) {
  const Setup* s = setup();
  if (!s) return state.SkipWithError("model not found");
  frep::DepthMap brute;
  double cpu_ms = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    brute = frep::render3d_brute_force(s->tape, s->options, s->row_step);
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    cpu_ms = 1000.0 * static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC * s->row_step;
    state.SetIterationTime(sec * s->row_step);
  }
  state.counters["cpu_ms"] = cpu_ms;  // process CPU time, scaled to the whole image
  frep::Render3DOptions o = s->options;
  o.threads = 1;
  check(frep::render3d(s->tape, o), brute, s->row_step);
  state.counters["rows_sampled_every"] = s->row_step;
}
BENCHMARK(BM_Render3DBruteForce)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
