// MeshOracle: a mesh's signed distance through its distance structure, with the closed form on
// demand.
#include "frep/convert/mesh_oracle.hpp"

#include <cmath>
#include <string>

#include "frep/error.hpp"
#include "frep/expr/copy.hpp"

namespace frep {
namespace {

MeshField checked_field(const TriMesh& mesh, const ConvertOptions& o) {
  MeshFieldOptions fo;
  fo.weld_tolerance = o.weld_tolerance;
  fo.threads = o.threads;
  MeshField f(mesh, fo);
  check_convertible(mesh.name, f.report());
  return f;
}

std::string thousands(std::size_t n) {
  std::string s = std::to_string(n);
  for (int i = static_cast<int>(s.size()) - 3; i > 0; i -= 3) s.insert(static_cast<std::size_t>(i), ",");
  return s;
}

}  // namespace

MeshOracle::MeshOracle(const TriMesh& mesh, const ConvertOptions& options)
    : field_(checked_field(mesh, options)), mesh_(mesh), name_(mesh.name), options_(options) {
  options_.progress = nullptr;  // a caller's progress callback may not outlive it
}

// The triangle found by this thread's latest query: batches come from small regions (a leaf's
// corners, a tile's pixels), so it bounds the next search tightly. Any triangle bounds it
// correctly; a stale one (another mesh's index) only costs time.
thread_local std::uint32_t t_hint = MeshDistance::kNoHint;

void MeshOracle::values(const float* x, const float* y, const float* z, float* out, std::size_t n) const {
  const MeshDistance& d = field_.distance();
  std::uint32_t hint = t_hint;
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<float>(d.signed_distance(Vec3{x[i], y[i], z[i]}, field_.sign(), hint));
  t_hint = hint;
}

void MeshOracle::gradients(const float* x, const float* y, const float* z, Grad* out, std::size_t n) const {
  const MeshDistance& d = field_.distance();
  std::uint32_t hint = t_hint;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 p{x[i], y[i], z[i]};
    const ClosestPoint c = d.closest_point(p, hint);
    Grad& g = out[i];
    if (std::isnan(c.distance)) {
      g = {NAN, NAN, NAN, NAN};
      continue;
    }
    const Vec3 n = d.pseudonormal(c);
    const Vec3 v = p - c.point;
    const double s = c.distance > 0 ? d.side(p, c, field_.sign()) : 0;
    const double len = length(v);
    // Off the surface, the unit vector from the closest point (on a face, its normal: no rounding
    // of the closest point); on it, the feature's pseudonormal.
    Vec3 dir;
    if (c.feature == Feature::Face || !(len > 0)) {
      const double nl = length(n);
      dir = nl > 0 ? n / nl : Vec3{};
    } else {
      dir = v * (s / len);
    }
    // The value exactly as values() gives it (0, not -0, on the surface).
    const double value = c.distance > 0 ? s * c.distance : c.distance;
    g = {static_cast<float>(value), static_cast<float>(dir.x), static_cast<float>(dir.y), static_cast<float>(dir.z)};
  }
  t_hint = hint;
}

std::string MeshOracle::describe() const {
  return "mesh " + (name_.empty() ? std::string("(unnamed)") : name_) + " (" +
         thousands(field_.distance().num_triangles()) + " triangles)";
}

NodeId MeshOracle::closed_form(Graph& g) const {
  const ConvertResult r = convert_mesh(mesh_, options_);
  return copy_expression(g, *r.model.graph, r.model.root);
}

Model mesh_model(std::shared_ptr<const MeshOracle> oracle) {
  Model m;
  m.info.lipschitz = 1;
  m.info.bounds = oracle->inside_box();
  m.root = m.graph->oracle(std::move(oracle));
  return m;
}

const MeshOracle* as_mesh_oracle(const Graph& g, NodeId root, Affine3* map) {
  const Node& n = g.node(root);
  if (n.op != Op::Oracle) return nullptr;
  const Oracle* o = &g.oracle_of(n);
  Affine3 a;
  if (const auto* t = dynamic_cast<const TransformedOracle*>(o)) {
    a = t->map();
    o = &t->base();
  }
  const auto* m = dynamic_cast<const MeshOracle*>(o);
  if (m && map) *map = a;
  return m;
}

}  // namespace frep
