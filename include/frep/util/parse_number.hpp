// One number parser for every text reader (.vm, point lists, mesh formats, Rhai, TetGen's output).
#pragma once

#include <charconv>
#include <cstdlib>
#include <string>
#include <string_view>
#include <type_traits>

namespace frep {

// Parses a whole token as a float or double ("+1", "1e5", "-.5", "inf", "nan"); false unless
// the entire token is a number. Out-of-range values behave as strtof/strtod: overflow gives
// +-inf, underflow 0 or a denormal.
template <class T>
inline bool parse_real(std::string_view tok, T& out) {
  static_assert(std::is_floating_point_v<T>);
  const char* b = tok.data();
  const char* e = b + tok.size();
  if (b != e && *b == '+') ++b;  // from_chars takes no plus sign
  if (b == e) return false;
  const auto r = std::from_chars(b, e, out);
  if (r.ptr != e) return false;
  if (r.ec == std::errc::result_out_of_range) {
    const std::string copy(b, e);  // from_chars cannot tell overflow from underflow
    if constexpr (std::is_same_v<T, float>) out = std::strtof(copy.c_str(), nullptr);
    else out = static_cast<T>(std::strtod(copy.c_str(), nullptr));
    return true;
  }
  return r.ec == std::errc();
}

}  // namespace frep
