// A mesh's exact signed distance as a leaf of an expression (an oracle, frep/expr/oracle.hpp):
// values, gradients and box bounds come from its distance structure (a BVH over its triangles,
// MeshField), not from its closed form of ~75 nodes per triangle. The closed form is still what
// file writers and exports write in its place (closed_form builds it with convert_mesh).
//
// Values: the exact (double precision) signed distance, rounded once to float, negative inside;
// the sign of the closest feature's pseudonormal, exact for the valid solids it accepts.
// Gradients: the unit vector from the closest point to the point, negated inside; on the
// surface (distance 0), the closest feature's normalized pseudonormal (the face normal on a face).
// Bounds: the value at a box's centre +- its half-diagonal (a distance is 1-Lipschitz).
#pragma once

#include <memory>
#include <mutex>
#include <string>

#include "frep/convert/convert.hpp"
#include "frep/expr/model.hpp"
#include "frep/expr/oracle.hpp"
#include "frep/io/frep_file.hpp"
#include "frep/mesh/mesh.hpp"
#include "frep/mesh/mesh_field.hpp"

namespace frep {

class MeshOracle final : public Oracle {
 public:
  // Checks the mesh as convert_mesh does and refuses what it refuses, with the same InputError
  // (a mesh `frep check` rejects, zero-area triangles), then indexes it. `options` are kept for
  // the closed form (sign method, TetGen); options.weld_tolerance and threads apply here too.
  explicit MeshOracle(const TriMesh& mesh, const ConvertOptions& options = {});
  // The same with its closed form given as .frep bytes (version 2, no oracles): what a .frep
  // file keeps, so that its formula stays bit for bit what was converted (TetGen's signs too).
  MeshOracle(const TriMesh& mesh, const ConvertOptions& options, std::shared_ptr<const std::string> closed_form_frep);
  // Any mesh with triangles, valid solid or not: broken ones are signed by the generalized winding
  // number (inside where it is at least 1/2), the field repair's approximation meshes. Their
  // closed form cannot be built (closed_form throws the check's InputError).
  static std::shared_ptr<const MeshOracle> any_mesh(const TriMesh& mesh, const ConvertOptions& options = {});

  const MeshField& field() const { return field_; }
  const std::string& name() const { return name_; }
  // The mesh as it was given (what the closed form converts and .frep files keep).
  const TriMesh& mesh() const { return mesh_; }
  const ConvertOptions& options() const { return options_; }
  // The closed form as .frep bytes: the ones given, or converted (once) and serialized.
  std::shared_ptr<const std::string> closed_form_frep() const;

  void values(const float* x, const float* y, const float* z, float* out, std::size_t n) const override;
  void gradients(const float* x, const float* y, const float* z, Grad* out, std::size_t n) const override;
  // Oracle::bounds, raised to the distance from the box to the mesh's bounding box where they are
  // apart (the distance to the surface is at least that): far boxes are proven positive.
  void bounds(const Interval* x, const Interval* y, const Interval* z, Interval* out, std::size_t n) const override;
  double lipschitz() const override { return 1; }
  Box3 inside_box() const override { return field_.box(); }
  std::string describe() const override;
  NodeId closed_form(Graph& g) const override;
  // Rays meet the triangles (MeshDistance::first_hit); the normal is the hit triangle's.
  bool casts_rays() const override { return true; }
  std::optional<RayHit> first_hit(const Vec3& o, const Vec3& dir, double t_max) const override;

 private:
  struct AnyMesh {};
  MeshOracle(const TriMesh& mesh, const ConvertOptions& options, AnyMesh);
  MeshField field_;
  TriMesh mesh_;  // as read: what the closed form converts
  std::string name_;
  ConvertOptions options_;
  mutable std::mutex closed_mutex_;
  mutable std::shared_ptr<const std::string> closed_frep_;  // given, or made by closed_form_frep()
};

// Keeps mesh oracles (moved or not) in .frep files: the mesh as given, the weld tolerance, the
// map, and the closed form's bytes. Reading checks the mesh again, as from a mesh file.
const FrepOracleCodec& mesh_oracle_codec();

// A model whose field is the mesh's signed distance through a MeshOracle: the root is the
// oracle, FieldInfo says L = 1 and gives the mesh's bounding box.
Model mesh_model(std::shared_ptr<const MeshOracle> oracle);

// The mesh oracle `root` of `g` stands for, if the expression is one mesh oracle (possibly
// moved: then `map` receives the map from the expression's coordinates to the mesh's), else
// null. Jobs with a faster method for a whole mesh (grids by the closest point transform) use it.
const MeshOracle* as_mesh_oracle(const Graph& g, NodeId root, Affine3* map = nullptr);

}  // namespace frep
