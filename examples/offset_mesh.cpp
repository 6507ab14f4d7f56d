// Example: load a triangle mesh, grow it by a distance and mesh the result. The mesh becomes an
// exact signed-distance field (a MeshOracle: distances from a BVH over its triangles); the
// offset of an exact distance is just that distance minus r, rounded wherever it is convex.
//
//   offset_mesh [INPUT.stl|obj|ply|off] [DISTANCE] [OUTPUT.stl] [RESOLUTION]
//   (defaults: examples/bracket.obj, 0.05, offset.stl, 64)
//
// Exit code 0 when the offset mesh was written and is a valid solid.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <string>

#include <frep/frep.hpp>

int main(int argc, char** argv) {
  try {
    const std::string input = argc > 1 ? argv[1] : "examples/bracket.obj";
    const float distance = argc > 2 ? std::strtof(argv[2], nullptr) : 0.05f;
    const std::string output = argc > 3 ? argv[3] : "offset.stl";
    const int resolution = argc > 4 ? std::atoi(argv[4]) : 64;

    // Read the mesh (the format comes from the extension) and make it a field. MeshOracle
    // checks that it is a valid solid and throws frep::InputError if not.
    const frep::TriMesh input_mesh = frep::read_mesh(input);
    auto oracle = std::make_shared<const frep::MeshOracle>(input_mesh);
    const frep::Model model = frep::mesh_model(oracle);  // info: Lipschitz 1, the mesh's box

    // The offset surface: where the distance equals `distance` (negative shrinks the part).
    const frep::Expr grown = frep::ugf::offset(model.root_expr(), distance);

    // Far from the mesh, intervals cannot prove a sign, so tell the mesher where the shape is:
    // the mesh's box grown by the offset. Lipschitz 1 lets it settle cells from one value.
    frep::MeshOptions options;
    options.resolution = resolution;
    options.known_bounds = model.info.bounds.inflated(distance > 0 ? distance : 0.0);
    options.lipschitz = model.info.lipschitz;
    const frep::TriMesh mesh = frep::mesh_expression(grown, options);
    frep::write_mesh(output, mesh);

    const frep::ValidationReport before = frep::validate_mesh(input_mesh);
    const frep::ValidationReport after = frep::validate_mesh(frep::read_mesh(output));
    std::printf("%s: volume %.4f\n%s: %zu triangles, volume %.4f\n%s\n", input.c_str(), before.volume,
                output.c_str(), mesh.num_triangles(), after.volume, after.summary().c_str());
    // Growing must add volume, shrinking remove it.
    const bool volume_ok = distance > 0 ? after.volume > before.volume : after.volume < before.volume;
    return after.is_solid() && volume_ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "offset_mesh: %s\n", e.what());
    return 1;
  }
}
