// An independent reader of G-code for the slicer's tests: it knows nothing of the slicer's
// types, only the text. It checks what any printer needs (finite moves on the bed, temperatures
// set before the first extrusion, layers rising by the layer height, the units and modes set)
// and collects the extrusion moves with their ;TYPE: so tests can measure them against a field.
#pragma once

#include <cmath>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace frep::test {

struct GcodeMove {
  double x0, y0, x1, y1, z;  // start and end on the bed, nozzle height
  double e;                  // filament extruded (mm)
  std::string type;          // the ;TYPE: in force
  int layer;                 // the ;LAYER: in force
};

struct GcodeFacts {
  std::vector<std::string> problems;  // empty if the program passes every check
  std::vector<GcodeMove> extrusions;
  std::vector<double> layer_z;        // per ;LAYER:, the height it prints at
  double filament = 0;                // total extruded (mm)
  double shift[3] = {0, 0, 0};        // from the header's "; part: ... shift X Y Z", if any
  bool has_shift = false;
};

struct GcodeLimits {
  double bed_x = 220, bed_y = 220;
  double layer_height = 0.2;
};

inline GcodeFacts read_gcode(const std::string& text, const GcodeLimits& lim = {}) {
  GcodeFacts f;
  auto problem = [&](int line, const std::string& what) {
    if (f.problems.size() < 20) f.problems.push_back("line " + std::to_string(line) + ": " + what);
  };
  std::istringstream in(text);
  std::string line;
  int n = 0, layer = -1;
  double x = 0, y = 0, z = 0;
  bool g21 = false, g90 = false, m83 = false, nozzle_hot = false, bed_set = false, extruded = false;
  bool relative_xyz = false;
  std::string type;
  while (std::getline(in, line)) {
    ++n;
    if (line.rfind("; part:", 0) == 0) {
      const auto at = line.find("shift ");
      if (at != std::string::npos) {
        std::istringstream s(line.substr(at + 6));
        f.has_shift = static_cast<bool>(s >> f.shift[0] >> f.shift[1] >> f.shift[2]);
      }
    }
    if (line.rfind(";LAYER:", 0) == 0) {
      const int next = std::stoi(line.substr(7));
      if (next != layer + 1) problem(n, "layer " + std::to_string(next) + " after layer " + std::to_string(layer));
      layer = next;
      f.layer_z.push_back(NAN);
      continue;
    }
    if (line.rfind(";TYPE:", 0) == 0) {
      type = line.substr(6);
      continue;
    }
    const std::string code = line.substr(0, line.find(';'));
    std::istringstream s(code);
    std::string word;
    if (!(s >> word)) continue;
    std::map<char, double> arg;
    std::string a;
    while (s >> a) {
      try {
        arg[a[0]] = std::stod(a.substr(1));
      } catch (...) {
        problem(n, "unreadable word " + a);
      }
      if (!std::isfinite(arg[a[0]])) problem(n, "not a finite number: " + a);
    }
    if (word == "G21") g21 = true;
    else if (word == "G90") g90 = true, relative_xyz = false;
    else if (word == "G91") relative_xyz = true;
    else if (word == "M83") m83 = true;
    else if (word == "M104" || word == "M109") nozzle_hot = arg.count('S') && arg['S'] > 150;
    else if (word == "M140" || word == "M190") bed_set = arg.count('S') > 0;
    else if (word == "G0" || word == "G1") {
      if (!g21 || !g90 || !m83) problem(n, "a move before G21, G90 and M83");
      double nx = x, ny = y, nz = z;
      if (relative_xyz) {
        nx += arg.count('X') ? arg['X'] : 0, ny += arg.count('Y') ? arg['Y'] : 0, nz += arg.count('Z') ? arg['Z'] : 0;
      } else {
        if (arg.count('X')) nx = arg['X'];
        if (arg.count('Y')) ny = arg['Y'];
        if (arg.count('Z')) nz = arg['Z'];
      }
      if (!relative_xyz && (nx < 0 || nx > lim.bed_x || ny < 0 || ny > lim.bed_y || nz < 0))
        problem(n, "a move off the bed");
      const double e = arg.count('E') ? arg['E'] : 0;
      const bool moves_xy = nx != x || ny != y;
      if (e > 0 && moves_xy) {
        if (!nozzle_hot || !bed_set) problem(n, "extrusion before the temperatures are set");
        if (word == "G0") problem(n, "extrusion on a G0 travel");
        if (layer < 0) problem(n, "extrusion before the first ;LAYER:");
        else {
          double& lz = f.layer_z[static_cast<std::size_t>(layer)];
          if (std::isnan(lz)) lz = nz;
          else if (std::fabs(lz - nz) > 1e-9) problem(n, "the height changes within a layer");
        }
        f.extrusions.push_back({x, y, nx, ny, nz, e, type, layer});
        extruded = true;
      }
      if (e > 0 && !moves_xy && !extruded && !nozzle_hot) problem(n, "priming before the nozzle is hot");
      f.filament += e;
      x = nx, y = ny, z = nz;
    }
  }
  // Layers rise by the layer height, from one layer height up.
  for (std::size_t k = 0; k < f.layer_z.size(); ++k) {
    const double want = (static_cast<double>(k) + 1) * lim.layer_height;
    if (!std::isnan(f.layer_z[k]) && std::fabs(f.layer_z[k] - want) > 1e-6)
      problem(0, "layer " + std::to_string(k) + " prints at z " + std::to_string(f.layer_z[k]) + ", not " + std::to_string(want));
  }
  if (f.layer_z.empty()) problem(0, "no layers");
  return f;
}

// Points every `step` mm along each extrusion move (both ends included), with the move's layer.
inline void for_each_extruded_point(const GcodeFacts& f, double step,
                                    const std::function<void(const GcodeMove&, double x, double y)>& visit) {
  for (const GcodeMove& m : f.extrusions) {
    const double len = std::hypot(m.x1 - m.x0, m.y1 - m.y0);
    const int k = std::max(1, static_cast<int>(std::ceil(len / step)));
    for (int i = 0; i <= k; ++i) {
      const double t = static_cast<double>(i) / k;
      visit(m, m.x0 + t * (m.x1 - m.x0), m.y0 + t * (m.y1 - m.y0));
    }
  }
}

}  // namespace frep::test
