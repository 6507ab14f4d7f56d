// Exact cross-sections of a field: the region where f(x, y, z) < 0 in the plane of a given z, as
// closed, oriented, non-crossing rings. Found by marching squares on a square grid that the
// subdivision driver prunes (tiles whose interval excludes 0 are skipped, the others evaluate
// their own simplified tape). Every vertex is refined onto the zero set along its grid edge;
// where the curve turns sharply inside a cell, the corner where the two tangents meet is added
// (sharp edges of CAD parts stay sharp); chords farther than a tolerance from the zero set are
// split at points projected onto it (up to three rounds). The rings are made non-crossing by a
// final union (Clipper), whatever the refinements did.
#pragma once

#include <memory>

#include "frep/eval/tape.hpp"
#include "frep/slice/polygon.hpp"

namespace frep {
class Subdivider;
}

namespace frep::slice {

struct CrossSectionOptions {
  double cell = 0.05;           // edge of the grid's square cells (model units)
  double tolerance = 0.0005;    // chords are split (three rounds at most) where their midpoints are farther than this from the zero set (estimated as |f| / |grad f|)
  double corner_cosine = 0.95;  // a cell whose two crossings' normals meet at a cosine below this gets a corner vertex
  double lipschitz = 0;         // known bound L on |f(p) - f(q)| / |p - q| (1 for exact distances); 0 = unknown
  int threads = 0;              // worker threads; 0 = all hardware threads
};

// Reusable over many planes of one field: keeps the subdivision driver's threads and scratch.
class CrossSectioner {
 public:
  // `tape` is kept by reference and must outlive this object. [lo, hi] is the region of the plane
  // to search; it should hold the whole inside: a shape reaching its border is cut there (the
  // section is then intersected with the region).
  // Throws InputError if the region is empty, not finite, or needs more than 2^20 cells along an axis.
  CrossSectioner(const Tape& tape, Point2 lo, Point2 hi, CrossSectionOptions options = {});
  ~CrossSectioner();
  CrossSectioner(const CrossSectioner&) = delete;
  CrossSectioner& operator=(const CrossSectioner&) = delete;

  // The region where f < 0 on the plane at height z (NaN counts as outside).
  Region section(double z);
  // True if some grid point of the plane at height z is inside (f < 0): cheaper than section().
  bool has_inside(double z);

  const CrossSectionOptions& options() const { return options_; }

  struct Impl;  // the grid, the driver and per-worker scratch (cross_section.cpp)

 private:
  const Tape& tape_;
  CrossSectionOptions options_;
  std::unique_ptr<Impl> impl_;
};

// One-shot helper.
Region cross_section(const Tape& tape, double z, Point2 lo, Point2 hi, const CrossSectionOptions& options = {});

}  // namespace frep::slice
