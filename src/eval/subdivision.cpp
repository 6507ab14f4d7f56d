// The non-template part of the subdivision driver: options checks and per-worker scratch.
#include "frep/eval/subdivision.hpp"

#include <cmath>
#include <cstdio>
#include <string>

namespace frep {

Subdivider::Subdivider(SubdivisionOptions options) : options_(std::move(options)) {
  if (options_.tiles.empty()) throw std::invalid_argument("subdivision needs at least one tile level");
  for (std::size_t i = 0; i < options_.tiles.size(); ++i) {
    if (options_.tiles[i] < 1) throw std::invalid_argument("tile sizes must be positive");
    if (i > 0 && options_.tiles[i] > options_.tiles[i - 1]) throw std::invalid_argument("tile sizes must not increase");
  }
  pool_ = std::make_unique<ThreadPool>(options_.threads);
  for (int i = 0; i < pool_->size(); ++i) workers_.push_back(std::make_unique<Worker>());
}

Subdivider::~Subdivider() = default;

void SampleGrid::check(const char* what) const {
  for (int a = 0; a < 3; ++a) {
    const std::vector<float>& c = coords[static_cast<std::size_t>(a)];
    for (float v : c)
      if (!std::isfinite(v))
        throw InputError("", 0, std::string("the ") + what + " reaches beyond 32-bit floats along " + "xyz"[a] +
                                    ": give smaller --bounds");
    // Samples that round to one float would all see the same value: a silently flat result.
    // (An axis of two equal coordinates is a plane on purpose: a slice's cells.)
    for (std::size_t i = 0; c.size() > 2 && i + 1 < c.size(); ++i)
      if (c[i + 1] == c[i]) {
        char msg[200];
        std::snprintf(msg, sizeof msg, " samples along %c are closer than 32-bit floats can tell apart near %g: give larger --bounds or fewer samples",
                      "xyz"[a], static_cast<double>(c[i]));
        throw InputError("", 0, std::string("the ") + what + "'s" + msg);
      }
  }
}

}  // namespace frep
