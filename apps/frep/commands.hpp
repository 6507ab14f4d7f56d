// Each subcommand lives in its own cmd_*.cpp and registers itself here.
#pragma once

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>

namespace frep::cli {

// A CLI11 check for tolerances: a finite number >= 0 (CLI::NonNegativeNumber lets NaN through).
inline CLI::Validator finite_non_negative() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(s, v) || !std::isfinite(v) || v < 0)
          return "Value " + s + " is not a finite number >= 0";
        return {};
      },
      "FINITE >= 0");
}

// A number finite in single precision, as the evaluators use it (CLI11's number checks let NaN
// and infinities through), optionally > 0.
inline CLI::Validator finite_number(bool positive = false) {
  return CLI::Validator(
      [positive](std::string& s) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(s, v) || !(std::fabs(v) <= 3.4028234663852886e38) || (positive && !(v > 0)))
          return "Value " + s + (positive ? " is not a finite number > 0" : " is not a finite number");
        return {};
      },
      positive ? "FINITE > 0" : "FINITE");
}

// A CLI11 check for counts and seeds held in unsigned types, which would take "-1" as 2^64 - 1:
// a whole number >= 0 (digits only, so that the message is short).
inline CLI::Validator whole_non_negative() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        std::uint64_t v = 0;
        const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
        if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos || r.ec != std::errc())
          return "Value " + s + " is not a whole number from 0 to 2^64 - 1";
        return {};
      },
      "WHOLE >= 0");
}

void register_info(CLI::App& app);
void register_eval(CLI::App& app);
void register_render(CLI::App& app);
void register_check(CLI::App& app);
void register_sdf(CLI::App& app);
void register_convert(CLI::App& app);
void register_mesh(CLI::App& app);
void register_export(CLI::App& app);
void register_sample(CLI::App& app);
void register_offset(CLI::App& app);
void register_shell(CLI::App& app);
void register_clearance(CLI::App& app);
void register_repair(CLI::App& app);
void register_dataset(CLI::App& app);
void register_slice(CLI::App& app);

inline void register_commands(CLI::App& app) {
  register_info(app);
  register_eval(app);
  register_render(app);
  register_check(app);
  register_repair(app);
  register_sdf(app);
  register_convert(app);
  register_mesh(app);
  register_export(app);
  register_sample(app);
  register_dataset(app);
  register_offset(app);
  register_shell(app);
  register_clearance(app);
  register_slice(app);
}

}  // namespace frep::cli
