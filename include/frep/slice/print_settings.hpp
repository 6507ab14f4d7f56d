// What a print is made with: layer and line sizes, walls, infill, the printer and its materials.
// The defaults are a common 0.4 mm nozzle printer with a 220 x 220 mm bed printing PLA. All
// lengths in millimetres, speeds in mm/s, temperatures in degrees Celsius.
#pragma once

#include <string>
#include <vector>

namespace frep::slice {

enum class InfillPattern { Lines, Grid, Gyroid };

struct PrintSettings {
  double layer_height = 0.2;          // every layer, the first included
  double line_width = 0.45;           // extrusion width of every line (walls, skin, infill)
  int perimeters = 2;                 // walls around every island
  double infill = 20;                 // sparse infill density in percent (0 to 100)
  InfillPattern infill_pattern = InfillPattern::Lines;  // lines alternate +-45 degrees; grid crosses both; gyroid from the field
  double infill_overlap = 0.15;       // how far infill lines reach into the innermost wall, in line widths
  int top_layers = 4;                 // solid layers under every top surface
  int bottom_layers = 4;              // solid layers over every bottom surface
  double nozzle_diameter = 0.4;
  double filament_diameter = 1.75;
  double extrusion_multiplier = 1.0;  // scales every E value
  double nozzle_temperature = 210;
  double bed_temperature = 60;
  double bed_x = 220, bed_y = 220;    // bed size; x and y run from 0
  double max_height = 250;            // tallest printable part
  double perimeter_speed = 45, outer_perimeter_speed = 30, infill_speed = 80, skin_speed = 40;
  double first_layer_speed = 20;      // every move of the first layer but travel
  double travel_speed = 150;
  double retract_length = 0.8;        // filament pulled back before long travels
  double retract_speed = 35;
  double retract_min_travel = 2;      // travels shorter than this do not retract
  double fan_speed = 100;             // percent, from the second layer on
  bool keep_position = false;         // keep the model's x and y instead of centring it on the bed
  double section_cell = 0.05;         // grid cell of the cross-sections (marching squares), model units
  double section_tolerance = 0.0005;  // cross-section vertices and chords within this of the exact contour
  double path_tolerance = 0.001;      // tool paths simplified to within this of the exact offsets (fewer, longer moves)
};

// Sets one setting by name (the names above, with '_' or '-'), from its text. Throws
// std::invalid_argument with a message naming the key if the key is unknown or the value is not
// of its type or range.
void set_print_setting(PrintSettings& settings, const std::string& key, const std::string& value);

// Reads `key = value` lines (blank lines and lines starting with '#' or ';' are ignored) into
// `settings`. Throws InputError naming the file and line for unknown keys and bad values.
void read_print_settings(const std::string& path, PrintSettings& settings);

// Throws InputError (no file) if the settings cannot make a print: sizes out of range, a line
// narrower than the layer is high, infill outside 0..100, and so on.
void check_print_settings(const PrintSettings& settings);

// The names set_print_setting accepts, for help texts.
std::vector<std::string> print_setting_names();
// A setting's value as set_print_setting reads it back ("0.2", "lines", "true").
std::string print_setting_text(const PrintSettings& settings, const std::string& key);

// The filament length extruded per millimetre of a line: the line's cross-section (line width
// times layer height: adjacent lines one width apart fill their lanes) over the filament's,
// times the extrusion multiplier.
double extrusion_per_mm(const PrintSettings& settings);

}  // namespace frep::slice
