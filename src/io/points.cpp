#include "frep/io/points.hpp"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <iterator>

#include "frep/error.hpp"
#include "frep/util/atomic_file.hpp"
#include "frep/util/parse_number.hpp"

namespace frep {
namespace {

template <class T>
PointColumns<T> parse(std::string_view text, const std::string& name, double max_abs) {
  PointColumns<T> p;
  std::size_t pos = 0;
  std::uint64_t line_no = 0;
  auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (pos < text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    std::string_view line = text.substr(pos, eol - pos);
    pos = eol + 1;
    ++line_no;
    if (auto h = line.find('#'); h != std::string_view::npos) line = line.substr(0, h);
    T v[3];
    int n = 0;
    std::size_t i = 0;
    bool after_comma = false;  // a value must follow (a trailing comma is fine: nothing follows)
    while (true) {
      while (i < line.size() && space(line[i])) ++i;
      if (i >= line.size()) break;
      if (line[i] == ',') {
        // "1,,2" is a missing value, not the point (1, 2).
        if (n == 0 || after_comma) throw InputError(name, line_no, "a value is missing (an empty field between commas)");
        after_comma = true;
        ++i;
        continue;
      }
      std::size_t j = i;
      while (j < line.size() && !space(line[j]) && line[j] != ',') ++j;
      std::string_view tok = line.substr(i, j - i);
      if (n == 3) throw InputError(name, line_no, "expected 2 or 3 numbers per line, got more");
      if (!parse_real(tok, v[n]))
        throw InputError(name, line_no, "bad number '" + std::string(tok.substr(0, 40)) + "'");
      if (std::isfinite(max_abs) && !(std::fabs(static_cast<double>(v[n])) <= max_abs)) {
        char limit[32];
        std::snprintf(limit, sizeof limit, "%g", max_abs);
        throw InputError(name, line_no,
                         "coordinate '" + std::string(tok.substr(0, 40)) +
                             (std::isnan(v[n]) ? "' is not a number" : "' is out of range (at most " + std::string(limit) + " in absolute value)"));
      }
      ++n;
      after_comma = false;
      i = j;
    }
    if (n == 0) continue;
    if (n == 1) throw InputError(name, line_no, "expected 2 or 3 numbers per line, got 1");
    p.x.push_back(v[0]);
    p.y.push_back(v[1]);
    p.z.push_back(n == 3 ? v[2] : T(0));
  }
  return p;
}

}  // namespace

PointColumns<float> parse_points_f32(std::string_view text, const std::string& name, double max_abs) {
  return parse<float>(text, name, max_abs);
}
PointColumns<double> parse_points_f64(std::string_view text, const std::string& name, double max_abs) {
  return parse<double>(text, name, max_abs);
}

std::string read_points_text(const std::string& path) {
  if (path == "-") return std::string(std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>());
  return read_file(path);
}

std::string points_source_name(const std::string& path) { return path == "-" ? "<stdin>" : path; }

}  // namespace frep
