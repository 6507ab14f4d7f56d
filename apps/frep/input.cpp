#include "input.hpp"

#include <fmt/core.h>

#include "frep/convert/convert.hpp"

namespace frep::cli {

Model load_input(const std::string& path, ConvertStats* stats) {
  ConvertStats s;
  Model m = load_field(path, {}, &s);
  if (stats) *stats = s;
  if (s.triangles > 0)
    fmt::print(stderr, "frep: converted {} ({} triangles) to an expression of {} nodes in {:.2f} s\n", path,
               s.triangles, s.nodes, s.seconds);
  return m;
}

}  // namespace frep::cli
