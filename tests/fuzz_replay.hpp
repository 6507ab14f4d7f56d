// Replays a fuzz seed corpus (fuzz/corpus/<name>/) in the normal test suite, with truncated and
// mutated variants of every seed, so the parsers' robustness is checked on every build, not only
// when someone runs libFuzzer.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <string_view>

#include "frep/util/atomic_file.hpp"

namespace frep::test {

struct ReplayCounts {
  std::size_t seeds = 0, variants = 0;
};

// Calls parse(bytes) on every seed in fuzz/corpus/<corpus>/ (each must parse: parse returns
// true), on prefixes of it, and on `mutations` randomly mutated copies (which may parse or
// not). `parse` returns false for an expected rejection (the reader's InputError) and must let
// anything else escape so that the test fails.
inline ReplayCounts replay_corpus(const std::string& corpus, const std::function<bool(std::string_view)>& parse,
                                  int mutations = 200, unsigned seed = 1234) {
  ReplayCounts n;
  const std::string path = std::string(FREP_SOURCE_DIR) + "/fuzz/corpus/" + corpus;
  EXPECT_TRUE(std::filesystem::is_directory(path)) << path;
  if (!std::filesystem::is_directory(path)) return n;
  std::mt19937 rng(seed);
  for (const auto& entry : std::filesystem::directory_iterator(path)) {
    const std::string bytes = read_file(entry.path().string());
    EXPECT_TRUE(parse(bytes)) << "seed " << entry.path() << " should be readable";
    ++n.seeds;
    for (std::size_t cut = 0; cut < bytes.size(); cut += 1 + bytes.size() / 64) {
      parse(std::string_view(bytes).substr(0, cut));
      ++n.variants;
    }
    for (int k = 0; k < mutations && !bytes.empty(); ++k) {
      std::string m = bytes;
      const int flips = 1 + k % 4;
      for (int f = 0; f < flips && !m.empty(); ++f) {
        const std::size_t at = rng() % m.size();
        switch (rng() % 4) {
          case 0: m[at] = static_cast<char>(rng()); break;
          case 1: m[at] = "0123456789-+.e \n/#(){};,_"[rng() % 26]; break;
          case 2: m.insert(at, std::string(1 + rng() % 8, "9\n -1e308x"[rng() % 10])); break;
          default: m.erase(at, 1 + rng() % 8); break;
        }
      }
      parse(m);
      ++n.variants;
    }
  }
  return n;
}

}  // namespace frep::test
