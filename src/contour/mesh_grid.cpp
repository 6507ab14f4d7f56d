// Grid setup and the box that closes the field at the grid's boundary.
#include "contour/mesh_grid.hpp"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "frep/eval/ssa_builder.hpp"
#include "frep/error.hpp"

namespace frep::contour {

MeshGrid make_grid(const Box3& region, double h, int margin, double shift) {
  constexpr double kShiftAxis[3] = {1.0, 0.71, 0.43};
  MeshGrid g;
  g.h = h;
  for (int a = 0; a < 3; ++a) {
    const double ext = region.hi[a] - region.lo[a];
    const double cells = std::ceil(ext / h * (1 - 1e-12));
    if (!(cells <= kMaxMeshResolution)) {
      char msg[300];
      std::snprintf(msg, sizeof msg,
                    "cells of %g need %.3g cells along %c, more than the limit of %d: use a larger cell or a "
                    "smaller region",
                    h, cells, "xyz"[a], kMaxMeshResolution);
      throw InputError("", 0, msg);
    }
    const int n = std::max(1, static_cast<int>(cells)) + 2 * margin;
    g.n[static_cast<std::size_t>(a)] = n;
    const double lo = 0.5 * (region.lo[a] + region.hi[a]) - 0.5 * n * h + shift * kShiftAxis[a] * h;
    auto& c = g.grid.coords[static_cast<std::size_t>(a)];
    c.resize(static_cast<std::size_t>(n) + 1);
    for (int i = 0; i <= n; ++i) c[static_cast<std::size_t>(i)] = static_cast<float>(lo + i * h);
  }
  for (int a = 0; a < 3; ++a)
    for (float c : {g.grid.coords[static_cast<std::size_t>(a)].front(), g.grid.coords[static_cast<std::size_t>(a)].back()})
      if (!std::isfinite(c)) {
        char msg[200];
        std::snprintf(msg, sizeof msg, "cells of %g reach beyond 32-bit floats along %c: use a smaller cell", h, "xyz"[a]);
        throw InputError("", 0, msg);
      }
  g.grid.check("region to mesh");
  for (int a = 0; a < 3; ++a) {
    const auto& c = g.grid.coords[static_cast<std::size_t>(a)];
    // Corners must be distinct in f32, with room for crossings between them.
    for (int i = 0; i + 1 < static_cast<int>(c.size()); ++i) {
      const float a0 = c[static_cast<std::size_t>(i)], a1 = c[static_cast<std::size_t>(i) + 1];
      if (!(a1 > a0) || (a1 - a0) < 64 * (std::nextafter(a0, INFINITY) - a0)) {
        char msg[300];
        std::snprintf(msg, sizeof msg,
                      "cells of %g at coordinates near %g are too fine for 32-bit floats: use a larger cell",
                      h, static_cast<double>(a0));
        throw InputError("", 0, msg);
      }
    }
    g.box.lo[a] = c.front();
    g.box.hi[a] = c.back();
  }
  g.grid.cells = true;
  return g;
}

Tape close_at_box(const Tape& tape, const Box3& box) {
  SsaBuilder ssa;
  const SsaBuilder::Vars xyz = ssa.variables();
  const SsaBuilder::Ref f = ssa.append(tape, xyz);
  SsaBuilder::Ref d = 0;
  for (int a = 0; a < 3; ++a) {
    const SsaBuilder::Ref lo = ssa.constant(static_cast<float>(box.lo[a]));
    const SsaBuilder::Ref hi = ssa.constant(static_cast<float>(box.hi[a]));
    const SsaBuilder::Ref below = ssa.emit(Op::Sub, lo, xyz[a]);
    const SsaBuilder::Ref above = ssa.emit(Op::Sub, xyz[a], hi);
    const SsaBuilder::Ref m = ssa.emit(Op::Max, below, above);
    d = a == 0 ? m : ssa.emit(Op::Max, d, m);
  }
  return ssa.finish(ssa.emit(Op::Max, f, d), tape.oracles());
}

}  // namespace frep::contour
