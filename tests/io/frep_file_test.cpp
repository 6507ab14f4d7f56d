// The .frep binary format: round trips bit for bit, is several times smaller than .vm, and
// refuses wrong magic, other versions, truncation and corruption with clear errors; its fuzz
// corpus is replayed with mutations.
#include <gtest/gtest.h>

#include <sstream>

#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/io/frep_file.hpp"
#include "frep/io/vm.hpp"
#include "fuzz_replay.hpp"
#include "test_util.hpp"

namespace frep {
namespace {

std::string error_of(std::string_view bytes) {
  try {
    parse_frep(bytes, "x.frep");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(FrepFile, RoundTripsRandomExpressionsBitForBit) {
  std::mt19937_64 rng(17);
  for (int trial = 0; trial < 200; ++trial) {
    Graph g;
    test::ExprGen gen(g, rng, {});
    const NodeId root = gen.gen();
    const std::string bytes = serialize_frep(g, root);
    const Model back = parse_frep(bytes, "x.frep");
    EXPECT_EQ(serialize_frep(*back.graph, back.root), bytes);
    const Tape a = Tape::compile(g, root), b = Tape::compile(*back.graph, back.root);
    PointEvaluator pe;
    for (int i = 0; i < 20; ++i) {
      const float x = test::random_float(rng), y = test::random_float(rng), z = test::random_float(rng);
      ASSERT_TRUE(test::same_value(pe.eval(a, x, y, z), pe.eval(b, x, y, z)));
    }
  }
}

TEST(FrepFile, SmallerThanVm) {
  FREP_REQUIRE_DATA("prospero.vm");
  const Model m = read_vm(test::data_file("prospero.vm"));
  std::ostringstream vm;
  write_vm(vm, *m.graph, m.root);
  const std::string bytes = serialize_frep(*m.graph, m.root);
  EXPECT_LT(bytes.size() * 3, vm.str().size()) << bytes.size() << " vs " << vm.str().size();
}

TEST(FrepFile, ClearErrorsForBadFiles) {
  Graph g;
  const NodeId root = (sqrt(square(g.x()) + square(g.y())) - 1.0f).id();
  const std::string good = serialize_frep(g, root);
  EXPECT_NE(error_of("hello").find("not a .frep file"), std::string::npos);
  for (std::size_t cut : {std::size_t(9), std::size_t(20), good.size() / 2, good.size() - 1}) {
    const std::string e = error_of(std::string_view(good).substr(0, cut));
    EXPECT_NE(e.find("truncated"), std::string::npos) << cut << ": " << e;
    EXPECT_NE(e.find("x.frep"), std::string::npos) << e;
  }
  std::string flipped = good;
  flipped[good.size() / 2] ^= 0x10;
  EXPECT_NE(error_of(flipped).find("checksum"), std::string::npos) << error_of(flipped);
  std::string version = good;
  version[8] = 7;
  EXPECT_NE(error_of(version).find("version 7"), std::string::npos) << error_of(version);
}

TEST(FrepFile, FuzzCorpusAndMutations) {
  const auto n = test::replay_corpus("frep", [](std::string_view bytes) {
    try {
      const Model m = parse_frep(bytes, "fuzz.frep");
      PointEvaluator pe;
      pe.eval(Tape::compile(*m.graph, m.root), 0.5f, -0.25f, 2.0f);
      return true;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("fuzz.frep"), std::string::npos) << e.what();
      return false;
    }
  }, 500);
  EXPECT_GE(n.seeds, 3u);
}

}  // namespace
}  // namespace frep
