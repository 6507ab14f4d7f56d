// Example: modeling with unit gradient fields (docs/ugf.md). Builds a block with rounded
// vertical edges and a chamfered top, hollows it into a shell for printing, fills the inside
// with a gyroid lattice, and writes each as a .vm file (Fidget's format).
//
//   ugf_example [OUTPUT_DIR]        (default: the current directory)
//   frep render OUTPUT_DIR/ugf_part.vm -o part.png --z 0.2     (a horizontal slice)
//
// Sizes fit the [-1, 1] square that `frep render` draws.
#include <cstdio>
#include <exception>
#include <string>

#include "frep/expr/graph.hpp"
#include "frep/io/vm.hpp"
#include "frep/ugf.hpp"

namespace {

void save(const std::string& dir, const std::string& name, const frep::Expr& e) {
  const std::string path = dir + "/" + name;
  frep::save_vm(path, e.graph(), e.id());
  std::printf("%-20s %zu nodes reachable\n", path.c_str(), frep::reachable_nodes(e.graph(), e.id()).size());
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string dir = argc > 1 ? argv[1] : ".";
    frep::Graph g;
    auto x = g.x(), y = g.y(), z = g.z();
    namespace ugf = frep::ugf;

    // The four sides of a 1.6 x 1.2 block, each a plane's signed distance.
    const float a = 0.8f, b = 0.6f, top = 0.4f, bottom = -0.4f;
    const frep::Expr sides[4] = {x - a, y - b, -x - a, -y - b};

    // Rounded vertical edges, radius 0.15: the max over the corners' rounded wedges, which is the
    // exact distance to the rounded rectangle.
    frep::Expr plan = ugf::round_intersection(sides[3], sides[0], 0.15f);
    for (int i = 0; i < 3; ++i) plan = max(plan, ugf::round_intersection(sides[i], sides[i + 1], 0.15f));

    // A chamfer of width 0.1 between the top face and the (rounded) sides: the chamfer follows
    // the rounded corners, because it is built from the fields, not from edges. The bottom edge
    // is sharp but distance-preserving, so offsets of the part round it instead of mitring.
    const frep::Expr part = ugf::intersect_exact(ugf::chamfer_intersection(plan, z - top, ugf::Chamfer::width(0.1f)),
                                                 bottom - z);
    save(dir, "ugf_part.vm", part);

    // Clearance: the part grown by 0.02 all round (exact where the part is).
    save(dir, "ugf_part_offset.vm", ugf::offset(part, 0.02f));

    // Hollowed for printing: a 0.05 wall inside the surface.
    const frep::Expr shell = ugf::shell_inward(part, 0.05f);
    save(dir, "ugf_shell.vm", shell);

    // The shell filled with a gyroid sheet lattice of period 0.25 and wall 0.02, trimmed to the
    // part's inside.
    const frep::Expr lattice = max(ugf::gyroid_sheet(g, 0.25f, 0.02f, ugf::GyroidScale::Bound), part);
    save(dir, "ugf_infill.vm", min(shell, lattice));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ugf_example: %s\n", e.what());
    return 1;
  }
}
