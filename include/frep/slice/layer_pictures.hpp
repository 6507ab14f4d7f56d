// Pictures of sliced layers: an SVG with one group per layer (Inkscape layers; one shown, the
// others hidden) and a PNG of one layer. Walls, skin and infill in their own colours, each line
// drawn at its real width over the cross-section in grey.
#pragma once

#include <ostream>

#include "frep/render/image.hpp"
#include "frep/slice/print_settings.hpp"
#include "frep/slice/slicer.hpp"

namespace frep::slice {

// Colours by role (RGB).
struct LayerColours {
  static constexpr unsigned char outline[3] = {225, 225, 225};
  static constexpr unsigned char wall_outer[3] = {214, 76, 52};
  static constexpr unsigned char wall_inner[3] = {238, 160, 60};
  static constexpr unsigned char skin[3] = {70, 110, 200};
  static constexpr unsigned char fill[3] = {90, 170, 90};
};

// Layers `first` to `last` (0-based; -1: the last one) in millimetres on the bed; layer `shown` is
// visible, the others hidden.
void write_layers_svg(std::ostream& out, const SlicedPart& part, const PrintSettings& settings, int shown,
                      int first = 0, int last = -1);

// Layer `index` as a picture whose longer side is `pixels` (the other follows the part's aspect),
// white background.
Image layer_preview(const SlicedPart& part, const PrintSettings& settings, int index, int pixels);

}  // namespace frep::slice
