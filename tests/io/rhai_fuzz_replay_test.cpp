// Replays the Rhai fuzz seed corpus (fuzz/corpus/rhai/) through the reader in the normal build,
// plus truncated and mutated variants: every input must either read into a consistent model or
// raise InputError naming the input; nothing else (crash, other exception) is acceptable.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "frep/error.hpp"
#include "frep/script/rhai.hpp"
#include "frep/util/atomic_file.hpp"

namespace frep {
namespace {

bool try_read(std::string_view bytes) {
  RhaiOptions o;  // the fuzz target's limits
  o.max_steps = 100000;
  o.max_nodes = 100000;
  try {
    const Model m = parse_rhai(bytes, "fuzz", o);
    EXPECT_LT(m.root, m.graph->size());
    return true;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("fuzz:", 0), 0u) << e.what();
    return false;
  }
}

TEST(RhaiFuzzReplay, SeedCorpusAndMutations) {
  const std::string dir = std::string(FREP_SOURCE_DIR) + "/fuzz/corpus/rhai";
  ASSERT_TRUE(std::filesystem::is_directory(dir)) << dir;
  std::mt19937 rng(4321);
  std::size_t seeds = 0, variants = 0, readable = 0;
  // Fragments that make mutations likely to reach deeper code than random bytes do.
  const char* fragments[] = {"(", ")", "{", "}", "[", "]", "#{", ";", ",", ".", "..", "x", "let a = ", "fn f(a) { a }",
                             "f(", "1e9", "-", "**", "%", "\"", "'", "//", "/*", "*/", "if ", "else ", "for i in 0..3 ",
                             "while ", "break", "return ", "remap(", "circle(", ".move([1, 2])", "union(", "[x, y]"};
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string bytes = read_file(entry.path().string());
    EXPECT_TRUE(try_read(bytes)) << "seed " << entry.path() << " should be readable";
    ++seeds;
    for (std::size_t cut = 0; cut < bytes.size(); cut += 1 + bytes.size() / 64) {
      readable += try_read(std::string_view(bytes).substr(0, cut));
      ++variants;
    }
    for (int k = 0; k < 300; ++k) {
      std::string m = bytes;
      const int edits = 1 + k % 4;
      for (int e = 0; e < edits && !m.empty(); ++e) {
        const std::size_t at = rng() % m.size();
        switch (rng() % 4) {
          case 0: m[at] = static_cast<char>(rng()); break;
          case 1: m.insert(at, fragments[rng() % std::size(fragments)]); break;
          case 2: m.erase(at, 1 + rng() % 8); break;
          default: m[at] = "()[]{};,.=+-*/%<>!&|^\"'#0123456789xyz \n"[rng() % 40]; break;
        }
      }
      readable += try_read(m);
      ++variants;
    }
  }
  EXPECT_GE(seeds, 6u);
  EXPECT_GT(variants, 1500u);
  EXPECT_GT(readable, 20u);  // the mutations are not all rejected at the first token
}

}  // namespace
}  // namespace frep
