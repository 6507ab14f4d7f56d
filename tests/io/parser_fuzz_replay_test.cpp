// Replays the .vm and points-file fuzz corpora (fuzz/corpus/vm, fuzz/corpus/points) with
// truncated and mutated variants: every input either parses into a consistent result or raises
// InputError naming the input; nothing else is acceptable.
#include <gtest/gtest.h>

#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/io/points.hpp"
#include "frep/io/vm.hpp"
#include "fuzz_replay.hpp"

namespace frep {
namespace {

TEST(ParserFuzzReplay, VmCorpusAndMutations) {
  const auto n = test::replay_corpus("vm", [](std::string_view bytes) {
    try {
      const Model m = parse_vm(bytes, "fuzz.vm");
      const Tape t = Tape::compile(*m.graph, m.root);
      PointEvaluator ev;
      ev.eval(t, 0.5f, -0.25f, 2.0f);
      return true;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("fuzz.vm"), std::string::npos) << e.what();
      return false;
    }
  }, 500);
  EXPECT_GE(n.seeds, 2u);
  EXPECT_GT(n.variants, 1000u);
}

TEST(ParserFuzzReplay, PointsCorpusAndMutations) {
  const auto n = test::replay_corpus("points", [](std::string_view bytes) {
    bool ok = true;
    for (double limit : {static_cast<double>(INFINITY), 1e30}) {
      const bool finite = limit < INFINITY;
      try {
        const auto p = parse_points_f32(bytes, "fuzz.txt", limit);
        EXPECT_TRUE(p.y.size() == p.x.size() && p.z.size() == p.x.size());
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("fuzz.txt"), std::string::npos) << e.what();
        if (!finite) ok = false;
      }
    }
    try {
      parse_points_f64(bytes, "fuzz.txt");
    } catch (const InputError&) {
      ok = false;
    }
    return ok;
  }, 500);
  EXPECT_GE(n.seeds, 2u);
}

}  // namespace
}  // namespace frep
