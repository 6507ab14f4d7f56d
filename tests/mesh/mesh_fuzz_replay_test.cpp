// Replays the fuzz seed corpora (fuzz/corpus/<reader>/) through the readers in the normal build,
// plus truncated and byte-flipped variants: every input must either read into a consistent mesh
// or raise InputError; nothing else (crash, other exception) is acceptable.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "frep/error.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/weld.hpp"
#include "frep/util/atomic_file.hpp"

namespace frep {
namespace {

using Reader = TriMesh (*)(std::string_view, const std::string&);

TriMesh read_any(std::string_view b, const std::string& n) { return read_mesh_from_memory(b, n); }

// Returns true if the bytes were read, false on InputError; fails the test on anything else.
bool try_read(Reader r, std::string_view bytes) {
  try {
    const TriMesh m = r(bytes, "fuzz");
    EXPECT_EQ(m.origins.size(), m.triangles.size());
    for (const Triangle& t : m.triangles)
      for (std::uint32_t v : t) EXPECT_LT(v, m.vertices.size());
    weld(m);
    return true;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("fuzz"), std::string::npos) << e.what();
    return false;
  }
}

TEST(MeshFuzzReplay, SeedCorporaAndMutations) {
  const std::pair<const char*, Reader> readers[] = {
      {"stl", read_stl}, {"obj", read_obj}, {"ply", read_ply}, {"off", read_off}};
  std::mt19937 rng(1234);
  std::size_t seeds = 0, variants = 0;
  for (const auto& [dir, reader] : readers) {
    const std::string path = std::string(FREP_SOURCE_DIR) + "/fuzz/corpus/" + dir;
    ASSERT_TRUE(std::filesystem::is_directory(path)) << path;
    for (const auto& entry : std::filesystem::directory_iterator(path)) {
      const std::string bytes = read_file(entry.path().string());
      EXPECT_TRUE(try_read(reader, bytes)) << "seed " << entry.path() << " should be readable";
      try_read(read_any, bytes);
      ++seeds;
      for (std::size_t cut = 0; cut < bytes.size(); cut += 1 + bytes.size() / 64) {
        try_read(reader, std::string_view(bytes).substr(0, cut));
        ++variants;
      }
      for (int k = 0; k < 200; ++k) {
        std::string m = bytes;
        const int flips = 1 + k % 4;
        for (int f = 0; f < flips; ++f) {
          const std::size_t at = rng() % m.size();
          switch (rng() % 4) {
            case 0: m[at] = static_cast<char>(rng()); break;
            case 1: m[at] = "0123456789-+.e \n/#"[rng() % 18]; break;
            case 2: m.insert(at, std::string(1 + rng() % 8, "9\n -1e308"[rng() % 9])); break;
            default: m.erase(at, 1 + rng() % 8); break;
          }
        }
        try_read(reader, m);
        try_read(read_any, m);
        ++variants;
      }
    }
  }
  EXPECT_GE(seeds, 10u);
  EXPECT_GT(variants, 2000u);
}

}  // namespace
}  // namespace frep
