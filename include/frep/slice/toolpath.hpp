// One layer's tool paths from its cross-section: walls at exact in-plane offsets, solid skin
// where a top or bottom surface is near, sparse infill elsewhere.
#pragma once

#include <functional>
#include <vector>

#include "frep/slice/polygon.hpp"
#include "frep/slice/print_settings.hpp"

namespace frep::slice {

enum class PathRole { WallOuter, WallInner, Skin, Fill };

// The G-code comment name of a role (";TYPE:WALL-OUTER" and so on).
const char* role_name(PathRole role);

struct ToolPath {
  PathRole role = PathRole::Fill;
  bool closed = false;  // a loop: the last point connects back to the first
  Polyline points;
};

struct LayerPlan {
  int index = 0;
  double z = 0;           // the nozzle's height: the layer's top
  double section_z = 0;   // where the cross-section was taken: the layer's middle
  Region outline;         // the cross-section
  std::vector<ToolPath> paths;  // in printing order
};

// Infill lines from a field: given a layer's height and the region to fill, the lines (open
// polylines, already inside the region). Used for gyroid infill, which the slicer evaluates from
// a field of its own.
using InfillSource = std::function<std::vector<Polyline>(double z, const Region& region)>;

// The region with each ring simplified to within `tolerance` (Douglas-Peucker), normalised.
Region coarse(const Region& region, double tolerance);

// The walls of one island (an outer ring with its holes): the k-th wall's centre lies (k - 1/2)
// line widths inside the island, measured in the plane, for k = 1..perimeters while it exists
// (a thin wall gets the walls that fit). `inner` receives the region left inside the walls.
std::vector<ToolPath> walls(const Region& island, const PrintSettings& settings, Region* inner = nullptr);

// Parallel lines `spacing` apart at `angle_degrees`, on a lattice fixed in the plane (so that
// layers line up), clipped to `region`.
std::vector<Polyline> line_fill(const Region& region, double spacing, double angle_degrees);

// The part of `outline` within `layers` layers of a top surface or a bottom surface: where the
// outline of one of the next `layers` layers above (or below) does not cover it. `above[j]` and
// `below[j]` are the outlines j + 1 layers away (empty when beyond the part).
Region solid_region(const Region& outline, const std::vector<const Region*>& above,
                    const std::vector<const Region*>& below);

// Everything for one layer: walls, skin over `solid`, sparse infill elsewhere (gyroid through
// `gyroid`, required for that pattern), ordered to keep travel short starting near `start`.
LayerPlan plan_layer(int index, double z, double section_z, Region outline, const Region& solid,
                     const PrintSettings& settings, const InfillSource& gyroid = {}, Point2 start = {});

}  // namespace frep::slice
