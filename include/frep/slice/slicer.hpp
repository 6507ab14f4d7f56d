// Slicing a field for 3D printing: the part's exact cross-section at every layer's mid-height,
// placed on the bed, and each layer's tool paths. The field's own values decide everything: the
// layer stack runs from the lowest to the highest point where f < 0 (found by bisection on
// planes), and top and bottom skins from the cross-sections of the layers around.
#pragma once

#include <functional>
#include <vector>

#include "frep/eval/tape.hpp"
#include "frep/expr/model.hpp"
#include "frep/slice/polygon.hpp"
#include "frep/slice/print_settings.hpp"
#include "frep/slice/toolpath.hpp"

namespace frep::slice {

struct SliceProgress {
  const char* phase;  // "cross-sections" or "tool paths"
  double fraction;    // 0..1 within the phase
};

struct SlicerOptions {
  int threads = 0;        // worker threads; 0 = all hardware threads
  double lipschitz = -1;  // bound L on |f(p) - f(q)| / |p - q| if known; < 0: the field's own (FieldInfo)
  std::function<void(const SliceProgress&)> progress;  // called now and then, from the calling thread
};

struct SlicedPart {
  std::vector<LayerPlan> layers;  // bottom up, in printer coordinates
  Point2 shift;                   // printer x, y = model x, y + shift
  double z_shift = 0;             // printer z = model z + z_shift (the part's bottom at 0)
  Point2 lo, hi;                  // extent of the outlines on the bed
  double height = 0;              // the part's height as found (before rounding to layers)
  double volume = 0;              // the layers' outline areas times the layer height
};

// Slices the field `tape` (negative inside, model units taken as millimetres). `info` gives its
// bounds (else they are found by interval search) and Lipschitz bound. Throws InputError (no
// file name) if the field is unbounded, empty, thinner than half a layer, or does not fit the
// printer.
SlicedPart slice_field(const Tape& tape, const FieldInfo& info, const PrintSettings& settings,
                       const SlicerOptions& options = {});

// The gyroid infill's period for a density d (0..1] and line width w: lines of width w on the
// gyroid's cross-sections cover a fraction d of a plane (their length per area is about
// 2.43 / period, from the gyroid's area per volume of about 3.09 / period).
double gyroid_period(double density, double line_width);

}  // namespace frep::slice
