// Example: model a part from exact distance fields and mesh it. A rectangular plate with a round
// hole through it, whose two rims are chamfered, written as an STL file (docs/ugf.md).
//
//   bracket_chamfer [OUTPUT.stl] [RESOLUTION]     (defaults: bracket_chamfer.stl, 96)
//
// Exit code 0 when the mesh was written and is a valid solid (closed, manifold, outward).
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include <frep/frep.hpp>

int main(int argc, char** argv) {
  try {
    const std::string output = argc > 1 ? argv[1] : "bracket_chamfer.stl";
    const int resolution = argc > 2 ? std::atoi(argv[2]) : 96;
    namespace ugf = frep::ugf;

    // Every shape is a field f(x, y, z): negative inside, zero on the surface. Build it in a
    // graph from the coordinates.
    frep::Graph g;
    auto x = g.x(), y = g.y(), z = g.z();

    // The plate: 2 x 1.2 x 0.3, centred at the origin. intersect_exact keeps the field an exact
    // distance outside the edges too (a plain max would be a bound there).
    const float half_x = 1.0f, half_y = 0.6f, half_z = 0.15f;
    const frep::Expr plate =
        ugf::intersect_exact(ugf::intersect_exact(abs(x) - half_x, abs(y) - half_y), abs(z) - half_z);

    // The hole: a vertical cylinder of radius 0.3 (its exact distance). "Not in the hole" is its
    // negation.
    const frep::Expr hole = sqrt(square(x) + square(y)) - 0.3f;

    // Plate minus hole, with a chamfer 0.08 wide where the hole meets the top and bottom faces.
    // The chamfer is computed from the two fields, not from edges, so it follows the round rim.
    const frep::Expr part = ugf::chamfer_intersection(plate, -hole, ugf::Chamfer::width(0.08f));

    // Mesh it, `resolution` cells across the longest side. The part lies in the plate's box: say
    // so, since interval arithmetic alone cannot bound the chamfer formula well. Dual contouring
    // keeps the flat faces and the chamfer's sharp edges.
    frep::MeshOptions options;
    options.resolution = resolution;
    options.known_bounds = frep::Box3({-half_x, -half_y, -half_z}, {half_x, half_y, half_z});
    options.lipschitz = 1;  // the field is a distance bound: lets cells settle quickly
    frep::MeshStats stats;
    const frep::TriMesh mesh = frep::mesh_expression(part, options, &stats);
    frep::write_mesh(output, mesh);
    std::printf("%s: %zu triangles, %d x %d x %d cells\n", output.c_str(), mesh.num_triangles(), stats.cells[0],
                stats.cells[1], stats.cells[2]);

    // Check what was written, as a user of the file would.
    const frep::ValidationReport report = frep::validate_mesh(frep::read_mesh(output));
    std::printf("%s\n", report.summary().c_str());
    return report.is_solid() ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bracket_chamfer: %s\n", e.what());
    return 1;
  }
}
