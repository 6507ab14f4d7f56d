// FieldInfo in the text formats (.vm, and Rhai in the script layer): leading comments that
// Fidget ignores, one per known fact,
//   # frep: lipschitz 1 (|f(p) - f(q)| <= 1 |p - q|)
//   # frep: bounds x0 y0 z0 x1 y1 z1 (every point where the field is negative)
//   # frep: growth box|distance (how far small values reach beyond the bounds: FieldInfo::growth)
// with `//` instead of `#` in Rhai. Only comments before the first other line count.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>

#include "frep/error.hpp"
#include "frep/expr/model.hpp"
#include "frep/util/text_scan.hpp"

namespace frep::detail {

// The comment lines for `info` (nothing for what is unknown), each ending in a newline.
inline std::string field_info_comments(const FieldInfo& info, std::string_view comment) {
  std::string out;
  char buf[64];
  if (info.lipschitz > 0) {
    std::snprintf(buf, sizeof buf, "%.9g", info.lipschitz);
    out += std::string(comment) + " frep: lipschitz " + buf + " (|f(p) - f(q)| <= " + buf + " |p - q|)\n";
  }
  if (!info.bounds.empty()) {
    out += std::string(comment) + " frep: bounds";
    for (const Vec3* v : {&info.bounds.lo, &info.bounds.hi})
      for (int a = 0; a < 3; ++a) {
        std::snprintf(buf, sizeof buf, " %.17g", (*v)[a]);
        out += buf;
      }
    out += " (every point where the field is negative)\n";
  }
  if (!info.bounds.empty() && info.growth != Growth::Unknown)
    out += std::string(comment) + (info.growth == Growth::Box ? " frep: growth box (where f < t >= 0 lies in the bounds grown by t)\n"
                                                                : " frep: growth distance (f is at least the distance to its inside)\n");
  return out;
}

// Reads those comments among the comment lines before the first other line. A marker without
// valid values (a finite L >= 0; six finite numbers with lo <= hi) is an InputError naming its line.
inline FieldInfo leading_field_info(std::string_view text, std::string_view comment, const std::string& name) {
  FieldInfo info;
  std::size_t pos = text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;  // UTF-8 byte order mark
  auto skip_space = [](std::string_view& l) {
    while (!l.empty() && is_space(l.front())) l.remove_prefix(1);
  };
  auto token = [&](std::string_view& l) {
    skip_space(l);
    const std::size_t end = std::min(l.find_first_of(" \t\r\f\v"), l.size());
    const std::string_view t = l.substr(0, end);
    l.remove_prefix(end);
    return t;
  };
  for (std::uint64_t line = 1; pos < text.size(); ++line) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    std::string_view l = text.substr(pos, eol - pos);
    pos = eol + 1;
    skip_space(l);
    while (!l.empty() && is_space(l.back())) l.remove_suffix(1);
    if (l.empty()) continue;
    if (l.substr(0, comment.size()) != comment) break;
    l.remove_prefix(comment.size());
    skip_space(l);
    if (l.substr(0, 6) != "frep: ") continue;
    l.remove_prefix(6);
    const std::string_view key = token(l);
    if (key == "lipschitz") {
      const std::string_view t = token(l);
      double v = 0;
      if (!parse_double(t, v) || !std::isfinite(v) || v < 0)
        throw InputError(name, line, "bad 'frep: lipschitz' comment: expected a number >= 0, got " + quoted(t));
      info.lipschitz = v;
    } else if (key == "bounds") {
      double v[6];
      for (double& x : v) {
        const std::string_view t = token(l);
        if (!parse_double(t, x) || !std::isfinite(x))
          throw InputError(name, line, "bad 'frep: bounds' comment: expected six finite numbers x0 y0 z0 x1 y1 z1, got " +
                                           quoted(t));
      }
      const Box3 b{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}};
      if (b.empty()) throw InputError(name, line, "bad 'frep: bounds' comment: the box is empty (x0 > x1, y0 > y1 or z0 > z1)");
      info.bounds = b;
    } else if (key == "growth") {
      const std::string_view t = token(l);
      if (t == "box") info.growth = Growth::Box;
      else if (t == "distance") info.growth = Growth::Distance;
      else throw InputError(name, line, "bad 'frep: growth' comment: expected box or distance, got " + quoted(t));
    }
  }
  if (info.bounds.empty()) info.growth = Growth::Unknown;  // growth is about the bounds
  return info;
}

}  // namespace frep::detail
