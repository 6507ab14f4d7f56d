// <frep/frep.hpp> is everything public: every header under include/frep/ is reachable from it
// (directly or through another umbrella such as frep/ugf.hpp), and this file compiles with it
// alone.
#include "frep/frep.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

namespace frep {
namespace {

namespace fs = std::filesystem;

std::set<std::string> includes_of(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  static const std::regex re(R"re(#include\s+"(frep/[^"]+)")re");
  std::set<std::string> out;
  for (std::sregex_iterator it(text.begin(), text.end(), re), end; it != end; ++it) out.insert((*it)[1]);
  return out;
}

TEST(UmbrellaHeader, ReachesEveryPublicHeader) {
  const fs::path root = fs::path(FREP_SOURCE_DIR) / "include";
  std::set<std::string> reached, todo{"frep/frep.hpp"};
  while (!todo.empty()) {
    const std::string h = *todo.begin();
    todo.erase(todo.begin());
    if (!reached.insert(h).second) continue;
    for (const std::string& inc : includes_of(root / h))
      if (!reached.count(inc)) todo.insert(inc);
  }
  int headers = 0;
  for (const auto& e : fs::recursive_directory_iterator(root / "frep")) {
    if (e.path().extension() != ".hpp") continue;
    ++headers;
    const std::string rel = fs::relative(e.path(), root).generic_string();
    EXPECT_TRUE(reached.count(rel)) << rel << " is not included by frep/frep.hpp";
  }
  EXPECT_GT(headers, 40);
}

}  // namespace
}  // namespace frep
