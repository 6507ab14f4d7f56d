// Helpers for the Rhai reader's tests: run a script, and compare two expressions point by point
// (bit for bit, NaN equal to NaN) over a grid and random points, with the independent graph
// evaluator of test_util.hpp.
#pragma once

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <string_view>

#include "frep/error.hpp"
#include "frep/expr/expr.hpp"
#include "frep/script/rhai.hpp"
#include "test_util.hpp"

namespace frep::test {

inline Model run_rhai(std::string_view script, const RhaiOptions& options = {}) {
  return parse_rhai(script, "test.rhai", options);
}

inline std::string shared_rhai_dir() { return std::string(FREP_SOURCE_DIR) + "/../shared/data/rhai"; }

// Sample points: a 7x7x7 grid over [-extent, extent]^3 and random points in the same box.
inline std::vector<Point3> sample_points(float extent, int random_count, std::uint64_t seed) {
  std::vector<Point3> pts;
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 7; ++j)
      for (int k = 0; k < 7; ++k)
        pts.push_back({extent * (i / 3.0f - 1), extent * (j / 3.0f - 1), extent * (k / 3.0f - 1)});
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(-extent, extent);
  for (int i = 0; i < random_count; ++i) pts.push_back({u(rng), u(rng), u(rng)});
  return pts;
}

// Both expressions evaluate to the same bits at every sample point.
inline ::testing::AssertionResult same_field(const Graph& ga, NodeId ra, const Graph& gb, NodeId rb, float extent = 2.0f,
                                             int random_count = 200) {
  for (const Point3& p : sample_points(extent, random_count, 99)) {
    const float a = eval_graph<float>(ga, ra, p.x, p.y, p.z);
    const float b = eval_graph<float>(gb, rb, p.x, p.y, p.z);
    if (!same_value(a, b))
      return ::testing::AssertionFailure() << "at (" << p.x << ", " << p.y << ", " << p.z << "): " << fstr(a) << " vs "
                                           << fstr(b);
  }
  return ::testing::AssertionSuccess();
}

// The script's shape equals the expression `build` makes in a fresh graph.
template <class Build>
::testing::AssertionResult script_matches(std::string_view script, Build build, float extent = 2.0f) {
  Model m;
  try {
    m = run_rhai(script);
  } catch (const InputError& e) {
    return ::testing::AssertionFailure() << "script failed: " << e.what();
  }
  Graph g;
  const Expr ref = build(g);
  return same_field(*m.graph, m.root, g, ref.id(), extent);
}

// The script fails with InputError at `line`, with "column `column`:" and `fragment` in the message.
inline ::testing::AssertionResult fails_at(std::string_view script, std::uint64_t line, std::uint64_t column,
                                           const std::string& fragment, const RhaiOptions& options = {}) {
  try {
    run_rhai(script, options);
  } catch (const InputError& e) {
    const std::string col = "column " + std::to_string(column) + ":";
    if (e.line() != line || e.detail().rfind(col, 0) != 0 || e.detail().find(fragment) == std::string::npos)
      return ::testing::AssertionFailure() << "wrong error: " << e.what() << " (expected line " << line << ", " << col
                                           << " and \"" << fragment << "\")";
    return ::testing::AssertionSuccess();
  } catch (const std::exception& e) {
    return ::testing::AssertionFailure() << "not an InputError: " << e.what();
  }
  return ::testing::AssertionFailure() << "the script ran without error";
}

}  // namespace frep::test
