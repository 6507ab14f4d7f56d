// MeshOracle: a mesh's signed distance through its distance structure, with the closed form on
// demand.
#include "frep/convert/mesh_oracle.hpp"

#include <cmath>
#include <cstring>
#include <optional>
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
    : MeshOracle(mesh, options, nullptr) {}

MeshOracle::MeshOracle(const TriMesh& mesh, const ConvertOptions& options,
                       std::shared_ptr<const std::string> closed_form_frep)
    : field_(checked_field(mesh, options)),
      mesh_(mesh),
      name_(mesh.name),
      options_(options),
      closed_frep_(std::move(closed_form_frep)) {
  options_.progress = nullptr;  // a caller's progress callback may not outlive it
}

MeshOracle::MeshOracle(const TriMesh& mesh, const ConvertOptions& options, AnyMesh)
    : field_(mesh, [&] {
        MeshFieldOptions fo;
        fo.weld_tolerance = options.weld_tolerance;
        fo.threads = options.threads;
        return fo;
      }()),
      mesh_(mesh),
      name_(mesh.name),
      options_(options) {
  options_.progress = nullptr;
}

std::shared_ptr<const MeshOracle> MeshOracle::any_mesh(const TriMesh& mesh, const ConvertOptions& options) {
  return std::shared_ptr<const MeshOracle>(new MeshOracle(mesh, options, AnyMesh{}));
}

std::shared_ptr<const std::string> MeshOracle::closed_form_frep() const {
  std::lock_guard<std::mutex> lock(closed_mutex_);
  if (!closed_frep_) {
    const ConvertResult r = convert_mesh(mesh_, options_);
    closed_frep_ = std::make_shared<const std::string>(serialize_frep(*r.model.graph, r.model.root, r.model.info));
  }
  return closed_frep_;
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

void MeshOracle::bounds(const Interval* x, const Interval* y, const Interval* z, Interval* out, std::size_t n) const {
  Oracle::bounds(x, y, z, out, n);
  const Box3& mb = field_.box();
  for (std::size_t k = 0; k < n; ++k) {
    if (out[k].is_unknown()) continue;
    const Interval* axes[3] = {&x[k], &y[k], &z[k]};
    double gap2 = 0;
    for (int a = 0; a < 3; ++a) {
      const double g = std::max({mb.lo[a] - axes[a]->hi, axes[a]->lo - mb.hi[a], 0.0});
      gap2 += g * g;
    }
    if (!(gap2 > 0)) continue;  // the box meets the mesh's box: nothing to add
    // Rounded down to a float below the true gap, so that the bound still holds.
    const double gap = std::sqrt(gap2) * (1 - 1e-12);
    float lo = static_cast<float>(gap);
    if (static_cast<double>(lo) > gap) lo = std::nextafter(lo, 0.0f);
    if (lo > out[k].lo) out[k].lo = std::min(lo, out[k].hi);
  }
}

std::optional<Oracle::RayHit> MeshOracle::first_hit(const Vec3& o, const Vec3& dir, double t_max) const {
  const MeshDistance& d = field_.distance();
  const auto h = d.first_hit(o, dir, t_max);
  if (!h) return std::nullopt;
  const Vec3 n = d.pseudonormal(ClosestPoint{0, o + dir * h->t, h->triangle, Feature::Face});
  const double l = length(n);
  return RayHit{h->t, l > 0 ? n / l : Vec3{}};
}

std::string MeshOracle::describe() const {
  return "mesh " + (name_.empty() ? std::string("(unnamed)") : name_) + " (" +
         thousands(field_.distance().num_triangles()) + " triangles)";
}

NodeId MeshOracle::closed_form(Graph& g) const {
  std::shared_ptr<const std::string> stored;
  {
    std::lock_guard<std::mutex> lock(closed_mutex_);
    stored = closed_frep_;
  }
  if (stored) {
    const Model m = parse_frep(*stored, name_ + " (its closed form)");
    return copy_expression(g, *m.graph, m.root);
  }
  const ConvertResult r = convert_mesh(mesh_, options_);
  return copy_expression(g, *r.model.graph, r.model.root);
}

namespace {

// A mesh oracle's record in a .frep file (little-endian):
//   4 bytes "MESH", u32 name length and name, f64 weld tolerance,
//   u32 vertex count and 3 f64 each, u32 triangle count and 3 u32 each,
//   12 f64 the map the mesh is evaluated at (rows of [M | t]; the identity if not moved),
//   u64 length and the bytes of its closed form (.frep, version 2).
template <class T>
void put(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out.append(b, sizeof(T));
}

class RecordReader {
 public:
  RecordReader(std::string_view b, const std::string& file) : b_(b), file_(file) {}
  template <class T>
  T get() {
    need(sizeof(T));
    T v;
    std::memcpy(&v, b_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return v;
  }
  std::string_view bytes(std::uint64_t n) {
    need(n);
    const std::string_view v = b_.substr(at_, n);
    at_ += n;
    return v;
  }
  void need(std::uint64_t n) const {
    if (n > b_.size() - at_) throw InputError(file_, 0, "truncated mesh record (oracle) in the .frep file");
  }
  bool done() const { return at_ == b_.size(); }

 private:
  std::string_view b_;
  const std::string& file_;
  std::size_t at_ = 0;
};

std::optional<std::string> encode_mesh(const Oracle& o) {
  const Oracle* base = &o;
  Affine3 map;
  if (const auto* t = dynamic_cast<const TransformedOracle*>(base)) {
    map = t->map();
    base = &t->base();
  }
  const auto* mesh = dynamic_cast<const MeshOracle*>(base);
  if (!mesh) return std::nullopt;
  const TriMesh& m = mesh->mesh();
  std::string out = "MESH";
  put<std::uint32_t>(out, static_cast<std::uint32_t>(mesh->name().size()));
  out += mesh->name();
  put<double>(out, mesh->options().weld_tolerance);
  put<std::uint32_t>(out, static_cast<std::uint32_t>(m.vertices.size()));
  for (const Vec3& v : m.vertices) put(out, v.x), put(out, v.y), put(out, v.z);
  put<std::uint32_t>(out, static_cast<std::uint32_t>(m.triangles.size()));
  for (const Triangle& t : m.triangles) put(out, t[0]), put(out, t[1]), put(out, t[2]);
  for (const auto& row : map.m)
    for (double v : row) put(out, v);
  const auto closed = mesh->closed_form_frep();
  put<std::uint64_t>(out, closed->size());
  out += *closed;
  return out;
}

std::shared_ptr<const Oracle> decode_mesh(std::string_view record, const std::string& file) {
  RecordReader r(record, file);
  if (r.bytes(4) != "MESH") throw InputError(file, 0, "unknown oracle record in the .frep file (not a mesh)");
  TriMesh m;
  m.name = std::string(r.bytes(r.get<std::uint32_t>()));
  ConvertOptions options;
  options.weld_tolerance = r.get<double>();
  if (!(options.weld_tolerance >= 0) || !std::isfinite(options.weld_tolerance))
    throw InputError(file, 0, "bad weld tolerance in a mesh record of the .frep file");
  const std::uint32_t nv = r.get<std::uint32_t>();
  r.need(std::uint64_t{24} * nv);
  m.vertices.resize(nv);
  for (Vec3& v : m.vertices) v = {r.get<double>(), r.get<double>(), r.get<double>()};
  const std::uint32_t nt = r.get<std::uint32_t>();
  r.need(std::uint64_t{12} * nt);
  m.triangles.resize(nt);
  for (Triangle& t : m.triangles) {
    t = {r.get<std::uint32_t>(), r.get<std::uint32_t>(), r.get<std::uint32_t>()};
    for (std::uint32_t v : t)
      if (v >= nv) throw InputError(file, 0, "a mesh record of the .frep file has a triangle corner out of range");
  }
  Affine3 map;
  for (auto& row : map.m)
    for (double& v : row) v = r.get<double>();
  if (!map.finite()) throw InputError(file, 0, "a mesh record of the .frep file has a map that is not finite");
  auto closed = std::make_shared<const std::string>(r.bytes(r.get<std::uint64_t>()));
  if (!r.done()) throw InputError(file, 0, "unexpected bytes after a mesh record of the .frep file");
  if (!is_frep_file(*closed)) throw InputError(file, 0, "a mesh record of the .frep file has no closed form");
  std::shared_ptr<const Oracle> o;
  try {
    o = std::make_shared<const MeshOracle>(m, options, std::move(closed));
  } catch (const InputError& e) {
    throw InputError(file, 0, "its mesh " + m.name + ": " + e.detail());
  }
  return o->transformed(map);
}

}  // namespace

const FrepOracleCodec& mesh_oracle_codec() {
  static const FrepOracleCodec codec{encode_mesh, decode_mesh};
  return codec;
}

Model mesh_model(std::shared_ptr<const MeshOracle> oracle) {
  Model m;
  m.info.lipschitz = 1;
  m.info.bounds = oracle->inside_box();
  m.info.growth = Growth::Distance;
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
