// The source tree's layering, as docs/layout.md states it: every module includes only modules
// below it, private headers (under src/<module>/) are included only by their own module (src/util
// is the library's shared toolbox, open to every module of the library), and the layers above
// the library (the script language, the command-line tool, the Python bindings) use public headers only.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

// Bottom to top: each may include those before it. The top-level headers error.hpp (the error
// types, used by all) and the umbrellas frep.hpp and ugf.hpp are placed by name below.
const std::vector<std::string> kOrder = {"error",  "util",   "math",    "expr",   "eval",   "mesh",
                                         "io",     "model",   "ugf",     "contour", "sample", "render", "slice",
                                         "convert", "export", "script",  "apps",
                                         "python"};

int rank_of(const std::string& module) {
  const auto it = std::find(kOrder.begin(), kOrder.end(), module);
  return it == kOrder.end() ? -1 : static_cast<int>(it - kOrder.begin());
}

// The module a public header path (relative to include/ or script/include/, "frep/...") is in.
std::string module_of_header(const std::string& rel) {
  const std::string s = rel.substr(5);  // past "frep/"
  const auto slash = s.find('/');
  if (slash != std::string::npos) return s.substr(0, slash);
  if (s == "error.hpp") return "error";
  if (s == "ugf.hpp") return "ugf";
  return "umbrella";  // frep.hpp: reaches everything by design
}

struct Source {
  fs::path path;       // absolute
  std::string where;   // relative to the source tree, for messages
  std::string module;  // its module
  bool library;        // under src/ or include/ (the library proper)
};

std::vector<Source> sources(const fs::path& root) {
  std::vector<Source> out;
  const auto add_tree = [&](const fs::path& dir, auto&& module_for, bool library) {
    if (!fs::exists(dir)) return;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
      const std::string ext = e.path().extension().string();
      if (!e.is_regular_file() || (ext != ".hpp" && ext != ".cpp" && ext != ".h")) continue;
      const std::string rel = fs::relative(e.path(), dir).generic_string();
      out.push_back({e.path(), fs::relative(e.path(), root).generic_string(), module_for(rel), library});
    }
  };
  add_tree(root / "include", [](const std::string& rel) { return module_of_header(rel); }, true);
  add_tree(root / "src", [](const std::string& rel) {
    const auto slash = rel.find('/');
    return slash == std::string::npos ? std::string(rel == "error.cpp" ? "error" : "umbrella") : rel.substr(0, slash);
  }, true);
  add_tree(root / "script", [](const std::string&) { return std::string("script"); }, false);
  add_tree(root / "apps", [](const std::string&) { return std::string("apps"); }, false);
  add_tree(root / "python" / "src", [](const std::string&) { return std::string("python"); }, false);
  return out;
}

TEST(Layering, NoModuleIncludesOneAboveItOrAnotherModulesPrivateHeaders) {
  const fs::path root = FREP_SOURCE_DIR;
  const std::regex include_re(R"re(^\s*#\s*include\s*"([^"]+)")re");
  std::vector<std::string> problems;
  std::map<std::string, int> checked;
  for (const Source& s : sources(root)) {
    std::ifstream in(s.path);
    std::string line;
    int n = 0;
    while (std::getline(in, line)) {
      ++n;
      std::smatch m;
      if (!std::regex_search(line, m, include_re)) continue;
      const std::string inc = m[1];
      const std::string at = s.where + ":" + std::to_string(n) + ": \"" + inc + "\": ";
      ++checked[s.module];
      if (inc.rfind("frep/", 0) == 0) {
        const std::string target = module_of_header(inc);
        if (s.module == "umbrella" || target == s.module) continue;
        if (target == "umbrella") {
          problems.push_back(at + "only programs include the umbrella header");
        } else if (rank_of(target) < 0 || rank_of(s.module) < 0) {
          problems.push_back(at + "a module missing from the layering (add it to docs/layout.md and this test)");
        } else if (rank_of(target) > rank_of(s.module)) {
          problems.push_back(at + s.module + " is below " + target);
        }
        continue;
      }
      // A private header: beside the file, or src/<module>/... of the library.
      if (fs::exists(s.path.parent_path() / inc)) continue;  // its own directory
      const auto slash = inc.find('/');
      const std::string target = slash == std::string::npos ? "" : inc.substr(0, slash);
      if (!s.library) {
        problems.push_back(at + "above the library only public headers (frep/...) may be included");
      } else if (target != s.module && target != "util") {
        problems.push_back(at + "a private header of " + (target.empty() ? "?" : target));
      }
    }
  }
  // The walk must have seen the tree, not an empty directory.
  EXPECT_GT(checked["eval"], 20);
  EXPECT_GT(checked["script"], 20);
  EXPECT_GT(checked["apps"], 20);
  EXPECT_GT(checked["python"], 10);
  for (const std::string& p : problems) ADD_FAILURE() << p;
}

// Only public headers are installed: everything under include/ and script/include/, and the
// private ones stay under src/ and script/src/ beside their sources.
TEST(Layering, PrivateHeadersLiveBesideTheirSources) {
  const fs::path root = FREP_SOURCE_DIR;
  for (const char* dir : {"include", "script/include"})
    for (const auto& e : fs::recursive_directory_iterator(root / dir))
      if (e.is_regular_file()) {
        EXPECT_EQ(e.path().extension(), ".hpp") << e.path();
        EXPECT_EQ(fs::relative(e.path(), root / dir).generic_string().rfind("frep/", 0), 0u) << e.path();
      }
}

}  // namespace
