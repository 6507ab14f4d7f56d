#include "frep/slice/print_settings.hpp"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <variant>

#include "frep/error.hpp"
#include "frep/util/parse_number.hpp"

namespace frep::slice {
namespace {

struct Entry {
  const char* name;
  std::variant<double PrintSettings::*, int PrintSettings::*, bool PrintSettings::*, InfillPattern PrintSettings::*> field;
  double lo, hi;  // accepted range (numbers)
};

constexpr double kInf = std::numeric_limits<double>::infinity();

const std::vector<Entry>& entries() {
  using P = PrintSettings;
  static const std::vector<Entry> e = {
      {"layer_height", &P::layer_height, 0.01, 2},
      {"line_width", &P::line_width, 0.05, 5},
      {"perimeters", &P::perimeters, 0, 100},
      {"infill", &P::infill, 0, 100},
      {"infill_pattern", &P::infill_pattern, 0, 0},
      {"infill_overlap", &P::infill_overlap, 0, 0.5},
      {"top_layers", &P::top_layers, 0, 1000},
      {"bottom_layers", &P::bottom_layers, 0, 1000},
      {"nozzle_diameter", &P::nozzle_diameter, 0.05, 5},
      {"filament_diameter", &P::filament_diameter, 0.1, 10},
      {"extrusion_multiplier", &P::extrusion_multiplier, 0.1, 10},
      {"nozzle_temperature", &P::nozzle_temperature, 0, 500},
      {"bed_temperature", &P::bed_temperature, 0, 200},
      {"bed_x", &P::bed_x, 1, 10000},
      {"bed_y", &P::bed_y, 1, 10000},
      {"max_height", &P::max_height, 1, 10000},
      {"perimeter_speed", &P::perimeter_speed, 0.1, 10000},
      {"outer_perimeter_speed", &P::outer_perimeter_speed, 0.1, 10000},
      {"infill_speed", &P::infill_speed, 0.1, 10000},
      {"skin_speed", &P::skin_speed, 0.1, 10000},
      {"first_layer_speed", &P::first_layer_speed, 0.1, 10000},
      {"travel_speed", &P::travel_speed, 0.1, 10000},
      {"retract_length", &P::retract_length, 0, 100},
      {"retract_speed", &P::retract_speed, 0.1, 10000},
      {"retract_min_travel", &P::retract_min_travel, 0, kInf},
      {"fan_speed", &P::fan_speed, 0, 100},
      {"keep_position", &P::keep_position, 0, 0},
      {"section_cell", &P::section_cell, 1e-4, 10},
      {"section_tolerance", &P::section_tolerance, 1e-7, 1},
      {"path_tolerance", &P::path_tolerance, 0, 1},
  };
  return e;
}

std::string canonical(std::string key) {
  std::replace(key.begin(), key.end(), '-', '_');
  return key;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

std::string range_text(const Entry& e) {
  auto num = [](double v) {
    std::string s = std::to_string(v);
    s.erase(s.find_last_not_of('0') + 1);
    if (!s.empty() && s.back() == '.') s.pop_back();
    return s;
  };
  return "from " + num(e.lo) + (e.hi == kInf ? " up" : " to " + num(e.hi));
}

}  // namespace

void set_print_setting(PrintSettings& s, const std::string& key_in, const std::string& value_in) {
  const std::string key = canonical(trim(key_in)), value = trim(value_in);
  for (const Entry& e : entries()) {
    if (key != e.name) continue;
    if (auto* d = std::get_if<double PrintSettings::*>(&e.field)) {
      double v = 0;
      if (!parse_real(value, v) || !std::isfinite(v) || v < e.lo || v > e.hi)
        throw std::invalid_argument(key + " must be a number " + range_text(e) + ", got '" + value + "'");
      s.*(*d) = v;
    } else if (auto* i = std::get_if<int PrintSettings::*>(&e.field)) {
      double v = 0;
      if (!parse_real(value, v) || v != std::floor(v) || v < e.lo || v > e.hi)
        throw std::invalid_argument(key + " must be a whole number " + range_text(e) + ", got '" + value + "'");
      s.*(*i) = static_cast<int>(v);
    } else if (auto* b = std::get_if<bool PrintSettings::*>(&e.field)) {
      if (value == "1" || value == "true" || value == "yes") s.*(*b) = true;
      else if (value == "0" || value == "false" || value == "no") s.*(*b) = false;
      else throw std::invalid_argument(key + " must be true or false (1 or 0), got '" + value + "'");
    } else {
      auto* p = std::get_if<InfillPattern PrintSettings::*>(&e.field);
      if (value == "lines") s.*(*p) = InfillPattern::Lines;
      else if (value == "grid") s.*(*p) = InfillPattern::Grid;
      else if (value == "gyroid") s.*(*p) = InfillPattern::Gyroid;
      else throw std::invalid_argument(key + " must be lines, grid or gyroid, got '" + value + "'");
    }
    return;
  }
  throw std::invalid_argument("unknown setting '" + trim(key_in) + "' (frep slice --list-settings lists them)");
}

void read_print_settings(const std::string& path, PrintSettings& settings) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot read the settings file");
  std::string line;
  std::uint64_t n = 0;
  while (std::getline(in, line)) {
    ++n;
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#' || t[0] == ';') continue;
    const auto eq = t.find('=');
    if (eq == std::string::npos) throw InputError(path, n, "expected 'key = value', got '" + t + "'");
    try {
      set_print_setting(settings, t.substr(0, eq), t.substr(eq + 1));
    } catch (const std::invalid_argument& e) {
      throw InputError(path, n, e.what());
    }
  }
}

void check_print_settings(const PrintSettings& s) {
  auto fail = [](const std::string& m) { throw InputError("", 0, m); };
  if (s.layer_height > 0.8 * s.nozzle_diameter + 1e-12)
    fail("the layer height (" + std::to_string(s.layer_height) + " mm) must be at most 0.8 times the nozzle diameter");
  if (s.line_width < s.layer_height) fail("the line width must be at least the layer height");
  if (s.line_width < 0.6 * s.nozzle_diameter || s.line_width > 3 * s.nozzle_diameter)
    fail("the line width must be between 0.6 and 3 times the nozzle diameter");
  if (s.section_cell > s.line_width / 2) fail("section_cell must be at most half the line width");
  for (const Entry& e : entries())
    if (auto* d = std::get_if<double PrintSettings::*>(&e.field)) {
      const double v = s.*(*d);
      if (!std::isfinite(v) || v < e.lo || v > e.hi) fail(std::string(e.name) + " must be a number " + range_text(e));
    } else if (auto* i = std::get_if<int PrintSettings::*>(&e.field)) {
      const int v = s.*(*i);
      if (v < e.lo || v > e.hi) fail(std::string(e.name) + " must be a whole number " + range_text(e));
    }
}

std::vector<std::string> print_setting_names() {
  std::vector<std::string> out;
  for (const Entry& e : entries()) out.push_back(e.name);
  return out;
}

std::string print_setting_text(const PrintSettings& s, const std::string& key) {
  const std::string k = canonical(key);
  for (const Entry& e : entries()) {
    if (k != e.name) continue;
    if (auto* d = std::get_if<double PrintSettings::*>(&e.field)) {
      char b[64];
      std::snprintf(b, sizeof b, "%g", s.*(*d));
      return b;
    }
    if (auto* i = std::get_if<int PrintSettings::*>(&e.field)) return std::to_string(s.*(*i));
    if (auto* b = std::get_if<bool PrintSettings::*>(&e.field)) return s.*(*b) ? "true" : "false";
    const InfillPattern p = s.*std::get<InfillPattern PrintSettings::*>(e.field);
    return p == InfillPattern::Lines ? "lines" : p == InfillPattern::Grid ? "grid" : "gyroid";
  }
  throw std::invalid_argument("unknown setting '" + key + "'");
}

double extrusion_per_mm(const PrintSettings& s) {
  const double filament = M_PI * s.filament_diameter * s.filament_diameter / 4;
  return s.line_width * s.layer_height / filament * s.extrusion_multiplier;
}

}  // namespace frep::slice
