// Private to the renderers: a model's tape re-expressed in a camera's view coordinates, so that
// the subdivision driver's axis-aligned boxes of pixels and depth samples are boxes of the tape's
// own variables (interval arithmetic then bounds the rotated region tightly enough).
#pragma once

#include "frep/eval/tape.hpp"
#include "frep/render/camera.hpp"

namespace frep {

// The tape of f(center + u right + v up + w toward) with x, y, z of the result standing for
// (u, v, w). Unless the camera is axis aligned, the result is max(f, box) with `box` negative
// exactly inside `bounds`, so that the corners of the view volume outside the box stay empty.
Tape view_tape(const Tape& model, const Camera& camera, const Box3& bounds);

}  // namespace frep
