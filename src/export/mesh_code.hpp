// Private: mesh oracles in the C and GLSL exports as data plus a loop, instead of their closed
// form (~75 nodes per triangle, which compilers choke on beyond a few thousand triangles). Each
// distinct mesh is written once: its welded vertices, its triangles in the leaf order of a
// bounding-box hierarchy, the hierarchy itself, the triangle across each edge and the vertices'
// angle-weighted pseudonormals (face and edge pseudonormals are recomputed from the corners, with
// the library's operations). One function per export walks the hierarchy nearest-first, keeps
// the nearest triangle and signs the distance with the pseudonormal of the feature the closest
// point lies on, as MeshOracle does; each oracle node calls it at its (possibly moved) point.
#pragma once

#include <array>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "frep/expr/graph.hpp"
#include "frep/expr/model.hpp"
#include "frep/math/affine.hpp"
#include "frep/math/vec.hpp"

namespace frep {
class MeshOracle;
}

namespace frep::export_detail {

// Whether every oracle reachable from `root` is a mesh oracle, moved or not (as_mesh_oracle).
bool only_mesh_oracles(const Graph& g, const std::vector<NodeId>& order);

// `root` of `g` with the oracles that are not mesh oracles replaced by their closed forms, in a
// new graph (mesh oracles are kept). Exports have no data form for other oracles.
Model expand_other_oracles(const Graph& g, NodeId root);

// The meshes an expression's oracles stand for, as flat tables (every mesh's entries one after
// the other, indices global).
struct MeshTables {
  struct Mesh {
    const MeshOracle* oracle = nullptr;
    std::uint32_t root = 0;            // its hierarchy's root node
    std::uint32_t first_triangle = 0;  // its triangles: first_triangle .. + triangles
    std::uint32_t triangles = 0;
    std::uint32_t vertices = 0;
  };
  // How an oracle node (by oracle index) reads a mesh: at map(p).
  struct Use {
    std::uint32_t oracle = 0;  // index in the graph's oracle table
    std::uint32_t mesh = 0;    // index in `meshes`
    Affine3 map;               // from the expression's coordinates to the mesh's
    bool moved = false;        // map is not the identity
  };
  std::vector<Mesh> meshes;  // distinct MeshOracle objects, in order of first use
  std::vector<Use> uses;     // one per oracle reachable from the root, in increasing index
  std::vector<Vec3> vertices;        // the used vertices of the welded meshes
  std::vector<Vec3> vertex_normals;  // angle-weighted pseudonormals (sums, not normalized)
  std::vector<std::array<std::uint32_t, 3>> triangles;   // corner vertices, hierarchy leaf order
  std::vector<std::array<std::uint32_t, 3>> neighbours;  // the triangle across edge k (corners k, k+1)
  struct Node {
    float lo[3], hi[3];  // rounded outward: holds its triangles
    std::uint32_t first, count;  // leaf: triangles first .. + count; inner (count 0): children first, first + 1
  };
  std::vector<Node> nodes;
  std::uint32_t depth = 0;  // of the deepest node (a root is at 0): sizes the walk's stack

  bool empty() const { return meshes.empty(); }
};

// The tables of the mesh oracles among `order` (reachable_nodes); empty if there are none.
// Every oracle there must be a mesh oracle (only_mesh_oracles).
MeshTables mesh_tables(const Graph& g, const std::vector<NodeId>& order);

// Writes the C99 data and functions: helpers under an include guard, then `prefix`-named arrays,
// `static double <prefix>mesh(int mesh, double x, double y, double z)` and one
// `static float <prefix>oracle<i>(float x, float y, float z)` per use. Computes in double.
void write_c_meshes(std::ostream& out, const std::string& prefix, const MeshTables& t);

// Bytes of constant arrays the GLSL data form may take (all meshes together): Mesa's llvmpipe
// compiles a shader with up to 64 KB of constant data in a few seconds and does not finish one
// with more (measured: 5400 vec3 in 3.3 s, 5500 not in a minute; the total counts, not each
// array). About 1,900 triangles of a typical mesh (docs/export.md).
inline constexpr std::size_t kMaxGlslMeshBytes = 65536;

// The bytes of constant arrays write_glsl_meshes writes for `t`.
std::size_t glsl_mesh_bytes(const MeshTables& t);

// Throws InputError (suggesting --closed-form) for meshes the GLSL data form cannot hold: more
// than kMaxGlslMeshBytes, or coordinates beyond 1e9 or a size below 1e-9 (squared normals,
// size^4, must stay finite and normal in float).
void check_glsl_meshes(const MeshTables& t);

// Writes the GLSL (ES 3.00 / 3.30) arrays and functions: `float <prefix>mesh(int mesh, vec3 p)`
// and one `float <prefix>oracle<i>(vec3 p)` per use. Computes in float. Call check_glsl_meshes
// first.
void write_glsl_meshes(std::ostream& out, const std::string& prefix, const MeshTables& t);

// One line for the exports' opening comments: "1 mesh, 12946 triangles, 6475 vertices".
std::string mesh_summary(const MeshTables& t);

}  // namespace frep::export_detail
