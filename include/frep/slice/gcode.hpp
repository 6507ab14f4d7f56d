// G-code for a sliced part, in the dialect common printers (Marlin and its kin) and viewers read:
// millimetres (G21), absolute positions (G90), relative extrusion (M83), `;LAYER:n` before each
// layer and `;TYPE:WALL-OUTER|WALL-INNER|SKIN|FILL` before each run of moves of one kind.
#pragma once

#include <cstddef>
#include <ostream>
#include <string>

#include "frep/slice/print_settings.hpp"
#include "frep/slice/slicer.hpp"

namespace frep::slice {

struct GcodeStats {
  std::size_t moves = 0;         // G0 and G1 lines
  double filament = 0;           // mm of filament extruded
  double extruded_volume = 0;    // mm^3: filament times its cross-section
  double seconds = 0;            // print time at the programmed speeds (no acceleration)
};

// Writes the program; `source` names the input in the header comment.
GcodeStats write_gcode(std::ostream& out, const SlicedPart& part, const PrintSettings& settings,
                       const std::string& source);

}  // namespace frep::slice
