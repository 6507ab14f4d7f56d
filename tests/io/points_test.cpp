// Query points as text: separators, comments, two-number lines, and what is refused, by line.
#include "frep/io/points.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "frep/error.hpp"

namespace frep {
namespace {

std::string error_of(std::string_view text, double max_abs = INFINITY) {
  try {
    parse_points_f64(text, "p.txt", max_abs);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Points, SeparatorsCommentsAndMissingZ) {
  const auto p = parse_points_f64("1 2 3\n# a comment\n\n4,5,6\n7\t8  # z is 0\n9, 10, 11,\r\n", "p.txt");
  ASSERT_EQ(p.size(), 4u);
  EXPECT_EQ(p.x[1], 4);
  EXPECT_EQ(p.z[1], 6);
  EXPECT_EQ(p.y[2], 8);
  EXPECT_EQ(p.z[2], 0);
  EXPECT_EQ(p.z[3], 11);  // a trailing comma ends the line
}

TEST(Points, MissingValuesAndBadLinesNameTheLine) {
  EXPECT_NE(error_of("1 2 3\n1,,2\n").find("p.txt:2: a value is missing"), std::string::npos);
  EXPECT_NE(error_of(",1,2\n").find("p.txt:1: a value is missing"), std::string::npos);
  EXPECT_NE(error_of("1 2 3 4\n").find("p.txt:1: expected 2 or 3 numbers"), std::string::npos);
  EXPECT_NE(error_of("\n5\n").find("p.txt:2: expected 2 or 3 numbers per line, got 1"), std::string::npos);
  EXPECT_NE(error_of("1 x 2\n").find("p.txt:1: bad number 'x'"), std::string::npos);
}

TEST(Points, RangeIsCheckedOnlyWhenAsked) {
  EXPECT_EQ(error_of("1e300 nan inf\n"), "");
  EXPECT_NE(error_of("0 0 0\n1 nan 2\n", 1e150).find("p.txt:2: coordinate 'nan' is not a number"), std::string::npos);
  EXPECT_NE(error_of("1e151 0 0\n", 1e150).find("p.txt:1: coordinate '1e151' is out of range"), std::string::npos);
  EXPECT_NE(error_of("-inf 0 0\n", 1e150).find("is out of range"), std::string::npos);
  // In single precision, 1e39 is infinite: beyond the float limit.
  try {
    parse_points_f32("1e39 0 0\n", "p.txt", std::numeric_limits<float>::max());
    ADD_FAILURE() << "1e39 accepted as a float coordinate";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("p.txt:1: coordinate '1e39' is out of range"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace frep
