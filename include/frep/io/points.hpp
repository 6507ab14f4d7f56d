// Query points as text: one `x y [z]` per line, separated by spaces, tabs or commas; `#` starts a
// comment; blank lines are skipped; a missing z is 0. Used by `frep eval` and `frep sdf`.
#pragma once

#include <cmath>

#include <string>
#include <string_view>
#include <vector>

namespace frep {

template <class T>
struct PointColumns {
  std::vector<T> x, y, z;
  std::size_t size() const { return x.size(); }
};

// Parses points in single precision (each number rounded once, straight from its decimal text).
// Numbers are separated by spaces, tabs or single commas. Throws InputError naming `name` and the
// line for anything that is not 2 or 3 numbers (an empty field between commas is a missing
// number), and, when `max_abs` is finite, for NaN and coordinates beyond +-max_abs (a number too
// large for the precision is infinite).
PointColumns<float> parse_points_f32(std::string_view text, const std::string& name, double max_abs = INFINITY);
// Same, in double precision.
PointColumns<double> parse_points_f64(std::string_view text, const std::string& name, double max_abs = INFINITY);

// Reads a points file, or standard input when `path` is "-".
std::string read_points_text(const std::string& path);
// The name used in messages for `path` ("<stdin>" for "-").
std::string points_source_name(const std::string& path);

}  // namespace frep
