// Helpers for the exporter tests (the scratch directory is cli_test_util.hpp's): running external tools (compilers,
// glslangValidator, pdflatex) with a clean skip where they are absent, and evaluating a batch of
// exported functions at many points through a compiled driver program.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "frep/eval/evaluators.hpp"
#include "frep/eval/tape.hpp"
#include "cli_test_util.hpp"
#include "test_util.hpp"

namespace frep::test {

namespace fs = std::filesystem;

struct CommandResult {
  int code = -1;
  std::string output;  // stdout and stderr together
};

// Runs `cmd` with /bin/sh, capturing its output in `log_file`.
inline CommandResult run_command(const std::string& cmd, const std::string& log_file) {
  const int status = std::system((cmd + " >" + shell_quote(log_file) + " 2>&1").c_str());
  CommandResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.output = read_text(log_file);
  return r;
}

inline bool have_program(const std::string& name) {
  return std::system(("command -v " + shell_quote(name) + " >/dev/null 2>&1").c_str()) == 0;
}

#define FREP_REQUIRE_PROGRAM(name)                                                                \
  do {                                                                                            \
    if (!::frep::test::have_program(name))                                                        \
      GTEST_SKIP() << "'" << (name) << "' is not installed; this check needs it";                 \
  } while (0)

// Writes points as float triples, runs `program IN OUT` and reads back `per_point` floats per
// point (the driver evaluates every function at every point, point-major).
inline std::vector<float> run_driver(const ScratchDir& dir, const std::string& program,
                                     const std::vector<float>& xyz, std::size_t per_point) {
  const std::string in = dir.path("points.bin"), out = dir.path("values.bin");
  {
    std::ofstream f(in, std::ios::binary);
    f.write(reinterpret_cast<const char*>(xyz.data()), static_cast<std::streamsize>(xyz.size() * sizeof(float)));
  }
  const CommandResult r = run_command(shell_quote(program) + " " + shell_quote(in) + " " + shell_quote(out),
                                      dir.path("driver.log"));
  EXPECT_EQ(r.code, 0) << r.output;
  const std::string bytes = read_text(out);
  std::vector<float> values(bytes.size() / sizeof(float));
  std::memcpy(values.data(), bytes.data(), values.size() * sizeof(float));
  EXPECT_EQ(values.size(), xyz.size() / 3 * per_point);
  return values;
}

// The main() of a driver program in C or C++: reads float triples from argv[1] and writes the
// value of every function in `names` at each of them to argv[2]. `call_prefix` qualifies the
// names (e.g. "glsl::"); `args` is the argument list, written in terms of the floats p[0..2].
inline std::string driver_main(const std::vector<std::string>& names, const std::string& call_prefix,
                               const std::string& args) {
  std::string s =
      "#include <stdio.h>\n"
      "int main(int argc, char** argv) {\n"
      "  if (argc != 3) return 2;\n"
      "  FILE* in = fopen(argv[1], \"rb\");\n"
      "  FILE* out = fopen(argv[2], \"wb\");\n"
      "  if (!in || !out) return 3;\n"
      "  float p[3];\n"
      "  while (fread(p, sizeof(float), 3, in) == 3) {\n"
      "    float v;\n";
  for (const std::string& n : names) s += "    v = " + call_prefix + n + "(" + args + "); fwrite(&v, sizeof v, 1, out);\n";
  s += "  }\n  fclose(in);\n  return fclose(out) == 0 ? 0 : 4;\n}\n";
  return s;
}

// `count` random expressions over `ops` (every unary and binary opcode if empty), in one graph,
// with special constants (inf, NaN, -0, ...) now and then.
inline std::vector<NodeId> random_expressions(Graph& g, std::uint64_t seed, int count, std::vector<Op> ops = {}) {
  std::mt19937_64 rng(seed);
  GenOptions opt;
  opt.ops = std::move(ops);
  opt.special_const_prob = 0.1;
  std::vector<NodeId> roots;
  for (int i = 0; i < count; ++i) {
    ExprGen gen(g, rng, opt);
    roots.push_back(gen.gen());
  }
  return roots;
}

// Opcodes that occur in the expressions (to check that a test covers all of them).
inline std::vector<bool> ops_used(const Graph& g, const std::vector<NodeId>& roots) {
  std::vector<bool> used(kOpCount, false);
  for (NodeId r : roots)
    for (NodeId id : reachable_nodes(g, r)) used[static_cast<int>(g.node(id).op)] = true;
  return used;
}

// Points as x, y, z triples: everyday values, wide magnitudes and special values (random_float),
// and every fourth point from a few values that make ties (+0 against -0, x == y) common.
inline std::vector<float> random_points(std::uint64_t seed, int n) {
  std::mt19937_64 rng(seed);
  const float inf = std::numeric_limits<float>::infinity();
  const float few[] = {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, -0.5f, 2.5f, inf, -inf, std::numeric_limits<float>::quiet_NaN()};
  std::vector<float> xyz;
  for (int i = 0; i < 3 * n; ++i) {
    if ((i / 3) % 4 == 3) xyz.push_back(few[rng() % std::size(few)]);
    else xyz.push_back(i % 2 ? random_float(rng) : std::uniform_real_distribution<float>(-3.0f, 3.0f)(rng));
  }
  return xyz;
}

// Points for the shared models (which live in [-1, 1]^3): a grid and random points in [-1.2, 1.2]^3.
inline std::vector<float> model_points(int grid, int random) {
  std::vector<float> xyz;
  for (int i = 0; i < grid; ++i)
    for (int j = 0; j < grid; ++j)
      for (int k = 0; k < grid; ++k) {
        auto at = [&](int t) { return -1.2f + 2.4f * static_cast<float>(t) / static_cast<float>(grid - 1); };
        xyz.insert(xyz.end(), {at(i), at(j), at(k)});
      }
  std::mt19937_64 rng(99);
  for (int i = 0; i < 3 * random; ++i) xyz.push_back(std::uniform_real_distribution<float>(-1.2f, 1.2f)(rng));
  return xyz;
}

// Compares `values` (point-major, one per root) with PointEvaluator, bit for bit (any NaN equals
// any NaN). Returns the number of mismatches and reports the first few.
inline int count_mismatches(const Graph& g, const std::vector<NodeId>& roots, const std::vector<float>& xyz,
                            const std::vector<float>& values, const std::string& what) {
  std::vector<Tape> tapes;
  for (NodeId r : roots) tapes.push_back(Tape::compile(g, r));
  PointEvaluator ev;
  int bad = 0;
  const std::size_t n = xyz.size() / 3;
  if (values.size() != n * roots.size()) return -1;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < roots.size(); ++k) {
      const float want = ev.eval(tapes[k], xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
      const float got = values[i * roots.size() + k];
      if (!same_value(want, got) && ++bad <= 5)
        ADD_FAILURE() << what << " #" << k << " at (" << fstr(xyz[3 * i]) << ", " << fstr(xyz[3 * i + 1]) << ", "
                      << fstr(xyz[3 * i + 2]) << "): exported " << fstr(got) << ", frep " << fstr(want);
    }
  return bad;
}

// GLSL text made C++: float literals (1.5, 2e-3) get an f suffix, since C++ would compute them
// in double; integers and names are left alone.
inline std::string suffix_float_literals(const std::string& s) {
  std::string out;
  auto ident = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.'; };
  for (std::size_t i = 0; i < s.size();) {
    if (std::isdigit(static_cast<unsigned char>(s[i])) && (i == 0 || !ident(s[i - 1]))) {
      std::size_t j = i;
      bool is_float = false;
      while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) ++j;
      if (j < s.size() && s[j] == '.') {
        is_float = true;
        ++j;
        while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) ++j;
      }
      if (j < s.size() && s[j] == 'e') {
        is_float = true;
        ++j;
        if (j < s.size() && (s[j] == '+' || s[j] == '-')) ++j;
        while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) ++j;
      }
      out.append(s, i, j - i);
      if (is_float) out += 'f';
      i = j;
    } else {
      out += s[i++];
    }
  }
  return out;
}

}  // namespace frep::test
