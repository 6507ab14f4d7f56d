// Repair (repair.hpp): weld and drop triangles that bound nothing; cut the triangles that meet
// badly along each other (arrangement.hpp); split the cut surface into patches, regions whose
// two sides cannot change winding number; keep the patches with inside (winding number >= 1/2)
// on one side and outside on the other, facing outside; fill what is left open; check.
#include "frep/mesh/repair.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <numeric>
#include <optional>
#include <span>

#include "frep/error.hpp"
#include "frep/math/predicates.hpp"
#include "frep/mesh/bvh.hpp"
#include "frep/mesh/mesh_distance.hpp"
#include "frep/mesh/topology.hpp"
#include "frep/mesh/tri_tri.hpp"
#include "frep/mesh/weld.hpp"
#include "frep/util/thread_pool.hpp"
#include "mesh/arrangement.hpp"
#include "mesh/fill_holes.hpp"
#include "util/json.hpp"
#include "util/union_find.hpp"

namespace frep {
namespace {

using Clock = std::chrono::steady_clock;

std::string fmt_g(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}
std::string fmt_point(const Vec3& p) { return "(" + fmt_g(p.x) + ", " + fmt_g(p.y) + ", " + fmt_g(p.z) + ")"; }

class Deadline {
 public:
  Deadline(double limit, std::string file) : limit_(limit), file_(std::move(file)) {}
  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  void poll() const {
    if (limit_ > 0 && seconds() > limit_)
      throw RepairStopped(file_, 0, "repair stopped after " + fmt_g(limit_) + " s (the time limit)");
  }

 private:
  Clock::time_point start_ = Clock::now();
  double limit_;
  std::string file_;
};

// Collinear corners, decided exactly: the triangle spans no plane and bounds nothing.
bool zero_area(const Vec3& a, const Vec3& b, const Vec3& c) {
  return exact::orient2d(a.x, a.y, b.x, b.y, c.x, c.y) == 0 && exact::orient2d(a.y, a.z, b.y, b.z, c.y, c.z) == 0 &&
         exact::orient2d(a.z, a.x, b.z, b.x, c.z, c.x) == 0;
}

// Welded (within `tolerance`), without the triangles that bound nothing (a repeated vertex,
// collinear corners), which are counted in `removed`. Unused vertices are dropped.
TriMesh clean(const TriMesh& m, double tolerance, std::size_t& removed, std::size_t* merged = nullptr) {
  WeldResult w = weld(m, {tolerance});
  if (merged) *merged = w.merged;
  TriMesh out;
  out.name = m.name;
  std::vector<std::uint32_t> index(w.mesh.vertices.size(), kNoVertex);
  for (const Triangle& t : w.mesh.triangles) {
    const Vec3 &a = w.mesh.vertices[t[0]], &b = w.mesh.vertices[t[1]], &c = w.mesh.vertices[t[2]];
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0] || zero_area(a, b, c)) {
      ++removed;
      continue;
    }
    Triangle u;
    for (int k = 0; k < 3; ++k) {
      std::uint32_t& i = index[t[k]];
      if (i == kNoVertex) {
        i = static_cast<std::uint32_t>(out.vertices.size());
        out.vertices.push_back(w.mesh.vertices[t[k]]);
      }
      u[k] = i;
    }
    out.triangles.push_back(u);
  }
  return out;
}

Vec3 face_cross(const TriMesh& m, const Triangle& t) {
  return cross(m.vertices[t[1]] - m.vertices[t[0]], m.vertices[t[2]] - m.vertices[t[0]]);
}

// Orientation, before any cut: within each sheet (triangles joined through edges of exactly two
// triangles), triangles that disagree with the sheet's orientation (the one covering more area)
// are turned; closed sheets facing inward are turned unless they lie inside another solid
// (cavities face inward by right). Without this a turned triangle would count against its
// sheet's winding number instead of for it.
void orient_sheets(TriMesh& m, RepairReport& r) {
  const MeshTopology topo(m);
  const std::size_t nt = m.triangles.size();
  constexpr std::uint32_t kUnset = 0xffffffffu;
  std::vector<std::uint32_t> sheet(nt, kUnset);
  std::vector<char> turn(nt, 0);
  std::vector<std::vector<std::uint32_t>> sheets;
  std::vector<char> closed;
  std::vector<std::uint32_t> stack;
  const auto area = [&](std::uint32_t t) { return length(face_cross(m, m.triangles[t])); };
  for (std::uint32_t s = 0; s < nt; ++s) {
    if (sheet[s] != kUnset) continue;
    const auto id = static_cast<std::uint32_t>(sheets.size());
    sheets.emplace_back();
    closed.push_back(1);
    sheet[s] = id;
    stack.push_back(s);
    double agree = 0, disagree = 0;
    while (!stack.empty()) {
      const std::uint32_t t = stack.back();
      stack.pop_back();
      sheets[id].push_back(t);
      (turn[t] ? disagree : agree) += area(t);
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t e = topo.triangle_edges(t)[k];
        if (topo.edge_face_count(e) != 2) {
          closed[id] = 0;
          continue;
        }
        const std::uint32_t g = topo.edge_faces(e)[0] == t ? topo.edge_faces(e)[1] : topo.edge_faces(e)[0];
        // Both traversing the edge the same way: g is turned relative to t.
        const char want = static_cast<char>(turn[t] ^ (topo.consistent(e) ? 0 : 1));
        if (sheet[g] == kUnset) {
          sheet[g] = id, turn[g] = want;
          stack.push_back(g);
        }
      }
    }
    if (disagree > agree)
      for (std::uint32_t t : sheets[id]) turn[t] ^= 1;
  }
  for (std::uint32_t t = 0; t < nt; ++t)
    if (turn[t]) std::swap(m.triangles[t][1], m.triangles[t][2]), ++r.triangles_turned;
  // Closed sheets facing inward, and whether they lie inside the rest.
  std::vector<std::uint32_t> inward;
  for (std::uint32_t id = 0; id < sheets.size(); ++id) {
    if (!closed[id]) continue;
    double volume = 0;
    for (std::uint32_t t : sheets[id]) {
      const Triangle& f = m.triangles[t];
      volume += dot(m.vertices[f[0]], cross(m.vertices[f[1]], m.vertices[f[2]]));
    }
    if (volume < 0) inward.push_back(id);
  }
  if (inward.empty()) return;
  TriMesh rest;
  rest.vertices = m.vertices;
  std::vector<char> is_inward(sheets.size(), 0);
  for (std::uint32_t id : inward) is_inward[id] = 1;
  for (std::uint32_t t = 0; t < nt; ++t)
    if (!is_inward[sheet[t]]) rest.triangles.push_back(m.triangles[t]);
  std::optional<MeshDistance> others;
  if (!rest.triangles.empty()) others.emplace(rest);
  for (std::uint32_t id : inward) {
    std::uint32_t big = sheets[id][0];
    for (std::uint32_t t : sheets[id])
      if (area(t) > area(big)) big = t;
    const Triangle& f = m.triangles[big];
    const Vec3 c = (m.vertices[f[0]] + m.vertices[f[1]] + m.vertices[f[2]]) * (1.0 / 3);
    if (others && others->winding_number(c) >= 0.5) continue;  // a cavity
    for (std::uint32_t t : sheets[id]) std::swap(m.triangles[t][1], m.triangles[t][2]);
    ++r.shells_turned;
  }
}

// Where the solid touches itself (two bodies sharing an edge or a corner), its boundary is not a
// manifold. Around each such edge the faces are paired into the wedges of solid between them
// (in angular order, each face with the next one round on its inside); at each vertex the faces
// linked through paired edges form fans, and every fan after the first gets its own copy of the
// vertex. The copies are then moved into their fan's solid by `gap`, so that the bodies meet no
// more and the surface is a manifold. Returns the number of vertices split.
std::size_t separate_touching(TriMesh& m, double gap) {
  const std::size_t nt = m.triangles.size();
  // Read before any corner changes: a face keeps its index, and only a split vertex's corners
  // are replaced.
  const MeshTopology topo(m);
  const auto local_edge = [&](std::uint32_t f, std::uint32_t e) {
    const auto& edges = topo.triangle_edges(f);
    return static_cast<std::uint32_t>(std::find(edges.begin(), edges.end(), e) - edges.begin());
  };
  constexpr std::uint32_t kNone = 0xffffffffu;
  std::vector<std::uint32_t> partner(3 * nt, kNone);  // per (face, edge): the face across, in its wedge
  const auto pair = [&](std::uint32_t f, std::uint32_t g, std::uint32_t e) {
    partner[3 * f + local_edge(f, e)] = g;
    partner[3 * g + local_edge(g, e)] = f;
  };
  for (std::uint32_t e = 0; e < topo.num_edges(); ++e) {
    const std::span<const std::uint32_t> faces = topo.edge_faces(e);
    if (faces.size() == 2) {
      pair(faces[0], faces[1], e);
    } else if (faces.size() > 2) {
      const Vec3 a = m.vertices[topo.edge_vertices(e)[0]];
      Vec3 d = m.vertices[topo.edge_vertices(e)[1]] - a;
      d = d * (1 / length(d));
      const Vec3 e1 = std::fabs(d.x) < 0.6 ? cross(d, Vec3{1, 0, 0}) : cross(d, Vec3{0, 1, 0});
      const Vec3 x1 = e1 * (1 / length(e1)), x2 = cross(d, x1);
      struct Around {
        double angle;
        bool opens;  // the solid lies on its side of increasing angle
        std::uint32_t face;
      };
      std::vector<Around> around;
      for (std::uint32_t f : faces) {
        const Triangle& t = m.triangles[f];
        const Vec3 c = m.vertices[t[(local_edge(f, e) + 2) % 3]];
        Vec3 w = c - a;
        w = w - d * dot(w, d);
        around.push_back({std::atan2(dot(w, x2), dot(w, x1)), dot(face_cross(m, t), cross(d, w)) < 0, f});
      }
      std::sort(around.begin(), around.end(), [](const Around& x, const Around& y) { return x.angle < y.angle; });
      const std::size_t n = around.size();
      std::vector<char> used(n, 0);
      for (std::size_t s = 0; s < n; ++s) {
        if (!around[s].opens || used[s]) continue;
        for (std::size_t step = 1; step < n; ++step) {
          const std::size_t o = (s + step) % n;
          if (used[o] || around[o].opens) continue;
          pair(around[s].face, around[o].face, e);
          used[s] = used[o] = 1;
          break;
        }
      }
    }
  }
  // Fans at every vertex: its faces linked through their paired edges at it.
  const std::size_t nv = m.vertices.size();
  std::size_t split = 0;
  UnionFind fans;
  for (std::uint32_t v = 0; v < nv; ++v) {
    const std::span<const std::uint32_t> faces = topo.vertex_faces(v);
    const auto n = static_cast<std::uint32_t>(faces.size());
    if (n < 2) continue;
    fans.reset(n);
    const auto find = [&](std::uint32_t x) { return fans.find(x); };
    const auto local = [&](std::uint32_t f) {
      return static_cast<std::uint32_t>(std::lower_bound(faces.begin(), faces.end(), f) - faces.begin());
    };
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t f = faces[i];
      const Triangle& t = m.triangles[f];
      for (std::uint8_t k = 0; k < 3; ++k) {
        if (t[k] != v && t[(k + 1) % 3] != v) continue;  // only the two edges at v
        const std::uint32_t g = partner[3 * f + k];
        if (g == kNone) continue;
        fans.unite(i, local(g));
      }
    }
    std::vector<std::uint32_t> roots;
    for (std::uint32_t i = 0; i < n; ++i)
      if (find(i) == i) roots.push_back(i);
    if (roots.size() < 2) continue;
    ++split;
    const Vec3 at = m.vertices[v];
    for (std::size_t r = 0; r < roots.size(); ++r) {
      // The fan's outward direction: its area-weighted normal.
      Vec3 normal{0, 0, 0};
      for (std::uint32_t i = 0; i < n; ++i)
        if (find(i) == roots[r]) normal = normal + face_cross(m, m.triangles[faces[i]]);
      const double len = length(normal);
      const Vec3 moved = len > 0 ? at - normal * (gap / len) : at;
      std::uint32_t copy = v;
      if (r > 0) {
        copy = static_cast<std::uint32_t>(m.vertices.size());
        m.vertices.push_back(moved);
      } else {
        m.vertices[v] = moved;
      }
      for (std::uint32_t i = 0; i < n; ++i) {
        if (find(i) != roots[r]) continue;
        for (std::uint32_t& c : m.triangles[faces[i]])
          if (c == v) c = copy;
      }
    }
  }
  return split;
}

// One round: seeds, the arrangement, patches, the winding number on both sides of each patch,
// and the pieces kept, facing outside.
TriMesh cut_and_keep(const TriMesh& m, RepairReport& r, const Deadline& deadline, int threads) {
  const MeshTopology topo(m);
  const TriangleBvh bvh(m);
  deadline.poll();

  // Seeds: pairs that cross, overlap or touch; triangles along edges not shared by exactly two.
  const int workers = std::min(resolve_thread_count(threads), 1024);
  std::vector<std::vector<std::uint32_t>> found(workers);
  std::vector<std::array<std::size_t, 3>> tally(workers, {0, 0, 0});
  bvh.for_each_overlapping_pair_parallel(workers, [&](std::uint32_t a, std::uint32_t b, int th) {
    const Triangle &ta = m.triangles[a], &tb = m.triangles[b];
    const Vec3 p[3] = {m.vertices[ta[0]], m.vertices[ta[1]], m.vertices[ta[2]]};
    const Vec3 q[3] = {m.vertices[tb[0]], m.vertices[tb[1]], m.vertices[tb[2]]};
    const unsigned pi[3] = {ta[0], ta[1], ta[2]}, qi[3] = {tb[0], tb[1], tb[2]};
    const Contact k = classify_triangle_pair(p, pi, q, qi);
    if (k == Contact::None) return;
    ++tally[th][k == Contact::Cross ? 0 : (k == Contact::Overlap ? 1 : 2)];
    found[th].push_back(a);
    found[th].push_back(b);
  });
  std::vector<std::uint32_t> seeds;
  for (int th = 0; th < workers; ++th) {
    seeds.insert(seeds.end(), found[th].begin(), found[th].end());
    r.crossing_pairs += tally[th][0];
    r.overlapping_pairs += tally[th][1];
    r.touching_pairs += tally[th][2];
  }
  for (std::uint32_t e = 0; e < topo.num_edges(); ++e)
    if (topo.edge_face_count(e) != 2)
      for (std::uint32_t t : topo.edge_faces(e)) seeds.push_back(t);
  std::sort(seeds.begin(), seeds.end());
  seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
  deadline.poll();

  const arrangement::Arrangement arr =
      arrangement::arrange(m, topo, bvh, seeds, [&] { deadline.poll(); });
  r.cut_triangles += arr.cut_triangles;
  r.new_vertices += arr.new_vertices;
  const std::vector<arrangement::Piece>& pieces = arr.pieces;
  const std::vector<Vec3>& V = arr.vertices;
  const std::size_t np = pieces.size();

  // Patches: pieces joined through edges that exactly two pieces use. `flip` says whether a
  // piece is turned relative to its patch's first piece (the two traverse their edge the same way).
  TriMesh cut;
  cut.vertices = V;
  cut.triangles.reserve(np);
  for (const arrangement::Piece& pc : pieces) cut.triangles.push_back(pc.v);
  const MeshTopology pieces_topo(cut);
  constexpr std::uint32_t kUnset = 0xffffffffu;
  std::vector<std::uint32_t> patch(np, kUnset);
  std::vector<char> flip(np, 0);
  std::vector<std::uint32_t> rep;  // per patch: its largest piece
  std::size_t non_orientable = 0;
  {
    std::vector<std::uint32_t> stack;
    for (std::uint32_t s = 0; s < np; ++s) {
      if (patch[s] != kUnset) continue;
      const auto id = static_cast<std::uint32_t>(rep.size());
      rep.push_back(s);
      double best = -1;
      patch[s] = id;
      stack.push_back(s);
      while (!stack.empty()) {
        const std::uint32_t i = stack.back();
        stack.pop_back();
        const double area = length(cross(V[pieces[i].v[1]] - V[pieces[i].v[0]], V[pieces[i].v[2]] - V[pieces[i].v[0]]));
        if (area > best) best = area, rep[id] = i;
        for (std::uint32_t e : pieces_topo.triangle_edges(i)) {
          if (e == MeshTopology::kNone || pieces_topo.edge_face_count(e) != 2) continue;
          const auto faces = pieces_topo.edge_faces(e);
          const std::uint32_t j = faces[0] == i ? faces[1] : faces[0];
          const char f = static_cast<char>(flip[i] ^ (pieces_topo.consistent(e) ? 0 : 1));
          if (patch[j] == kUnset) {
            patch[j] = id, flip[j] = f;
            stack.push_back(j);
          } else if (flip[j] != f) {
            ++non_orientable;
          }
        }
      }
    }
  }
  deadline.poll();

  // Each patch's representative: the winding number just in front of it and just behind, at
  // points close enough that no other surface lies between them and the piece (checked by rays).
  Box3 box;
  for (const Vec3& v : m.vertices) box.add(v);
  const double diag = length(box.size());
  const MeshDistance md(m, topo, {}, &bvh);
  const std::size_t npatch = rep.size();
  std::vector<signed char> keep(npatch, 0);  // 0 drop, 1 keep as the representative faces, -1 keep turned
  std::atomic<std::size_t> unsure{0};
  parallel_for_ranges(threads, npatch, 64, [&](int, std::size_t b, std::size_t e) {
    for (std::size_t p = b; p < e; ++p) {
      const arrangement::Piece& pc = pieces[rep[p]];
      const Vec3 a = V[pc.v[0]], bb = V[pc.v[1]], c = V[pc.v[2]];
      const Vec3 centre = (a + bb + c) * (1.0 / 3);
      const Vec3 cr = cross(bb - a, c - a);
      const double area2 = length(cr);
      if (!(area2 > 0)) {
        ++unsure;
        continue;
      }
      const Vec3 n = cr * (1 / area2);
      double delta = std::min(0.1 * std::sqrt(0.5 * area2), 1e-4 * diag);
      for (int tries = 0; tries < 30; ++tries, delta *= 0.25) {
        const auto clear = [&](const Vec3& from, const Vec3& dir) {
          const auto hit = md.first_hit(from, dir, 2 * delta);
          return hit && hit->t >= delta * (1 - 1e-6);
        };
        if (clear(centre + n * delta, n * -1.0) && clear(centre - n * delta, n)) break;
      }
      // The hierarchy's far-field approximation is off by a few hundredths; near 1/2 (holes), the
      // exact sum decides.
      double front = md.winding_number(centre + n * delta), back = md.winding_number(centre - n * delta);
      if (std::fabs(front - 0.5) < 0.25) front = md.winding_number_exact(centre + n * delta);
      if (std::fabs(back - 0.5) < 0.25) back = md.winding_number_exact(centre - n * delta);
      const bool in_front = front >= 0.5, in_back = back >= 0.5;
      if (std::fabs(front - 0.5) < 0.25 || std::fabs(back - 0.5) < 0.25) ++unsure;
      if (in_front != in_back) keep[p] = static_cast<signed char>(in_back ? 1 : -1);
    }
  });
  deadline.poll();

  // The kept pieces, facing outside.
  r.patches += npatch;
  std::vector<double> patch_area(npatch, 0);
  std::vector<char> patch_turned(npatch, 0);
  TriMesh out;
  out.name = m.name;
  out.vertices = V;
  for (std::uint32_t i = 0; i < np; ++i) {
    const std::uint32_t p = patch[i];
    const arrangement::Piece& pc = pieces[i];
    const Vec3 cr = cross(V[pc.v[1]] - V[pc.v[0]], V[pc.v[2]] - V[pc.v[0]]);
    patch_area[p] += 0.5 * length(cr);
    if (keep[p] == 0) continue;
    // keep[p] is about the representative; flip[] is relative to the patch's first piece.
    const bool turn = (keep[p] < 0) != ((flip[i] != 0) != (flip[rep[p]] != 0));
    Triangle t = pc.v;
    if (turn) std::swap(t[1], t[2]);
    out.triangles.push_back(t);
    if (i == rep[p] && dot(face_cross(out, t), face_cross(m, m.triangles[pc.source])) < 0) patch_turned[p] = 1;
  }
  for (std::size_t p = 0; p < npatch; ++p) {
    if (keep[p] == 0) {
      ++r.patches_removed;
      r.area_removed += patch_area[p];
      if (r.removed_at.size() < 10) {
        const arrangement::Piece& pc = pieces[rep[p]];
        r.removed_at.push_back((V[pc.v[0]] + V[pc.v[1]] + V[pc.v[2]]) * (1.0 / 3));
      }
    } else if (patch_turned[p]) {
      ++r.patches_flipped;
    }
  }
  if (non_orientable) r.notes.push_back(std::to_string(non_orientable) + " edges join patches that cannot be oriented alike");
  if (unsure)
    r.notes.push_back(std::to_string(unsure.load()) +
                      " patches have a winding number near 1/2 beside them (holes nearby): kept where it is at least 1/2");
  return out;
}

// How far separate_touching moves vertices: 2^-32 of the mesh's size (2^-18 when coordinates are
// floats), far above the rounding of its coordinates and far below any feature one could print
// or machine.
double touching_gap(const TriMesh& m, bool floats) {
  Box3 box;
  for (const Vec3& v : m.vertices) box.add(v);
  return std::ldexp(length(box.size()), floats ? -18 : -32);
}


// With float coordinates, a rounded cut point may land across a triangle that passes within a
// unit of the last place (nearly coincident surfaces). Each such point (not an input vertex) is
// tried at the floats around it, one unit of the last place either way in each coordinate, and
// kept where its triangles cross or overlap the fewest others. Returns the crossings left.
std::size_t settle_float_points(TriMesh& m, const std::vector<Vec3>& input_points) {
  std::vector<Vec3> fixed = input_points;
  const auto less = [](const Vec3& a, const Vec3& b) {
    return a.x != b.x ? a.x < b.x : (a.y != b.y ? a.y < b.y : a.z < b.z);
  };
  std::sort(fixed.begin(), fixed.end(), less);
  const MeshTopology topo(m);  // the faces at each vertex (positions move, corners do not)
  const auto bad_contacts = [&](std::uint32_t f, const TriangleBvh& bvh) {
    const Triangle& ta = m.triangles[f];
    Box3 box;
    for (std::uint32_t v : ta) box.add(m.vertices[v]);
    box = box.inflated(1e-6 * (std::fabs(box.lo.x) + std::fabs(box.lo.y) + std::fabs(box.lo.z) + length(box.size())));
    std::size_t bad = 0;
    bvh.for_each_meeting(box, [&](std::uint32_t g) {
      if (g == f) return;
      const Triangle& tb = m.triangles[g];
      const Vec3 p[3] = {m.vertices[ta[0]], m.vertices[ta[1]], m.vertices[ta[2]]};
      const Vec3 q[3] = {m.vertices[tb[0]], m.vertices[tb[1]], m.vertices[tb[2]]};
      const unsigned pi[3] = {ta[0], ta[1], ta[2]}, qi[3] = {tb[0], tb[1], tb[2]};
      const Contact k = classify_triangle_pair(p, pi, q, qi);
      bad += k == Contact::Cross || k == Contact::Overlap;
    });
    return bad;
  };
  std::size_t left = 0;
  for (int pass = 0; pass < 4; ++pass) {
    const TriangleBvh bvh(m);
    std::vector<std::uint32_t> suspects;
    std::mutex lock;
    bvh.for_each_overlapping_pair_parallel(0, [&](std::uint32_t a, std::uint32_t b, int) {
      const Triangle &ta = m.triangles[a], &tb = m.triangles[b];
      const Vec3 p[3] = {m.vertices[ta[0]], m.vertices[ta[1]], m.vertices[ta[2]]};
      const Vec3 q[3] = {m.vertices[tb[0]], m.vertices[tb[1]], m.vertices[tb[2]]};
      const unsigned pi[3] = {ta[0], ta[1], ta[2]}, qi[3] = {tb[0], tb[1], tb[2]};
      const Contact k = classify_triangle_pair(p, pi, q, qi);
      if (k != Contact::Cross && k != Contact::Overlap) return;
      std::lock_guard<std::mutex> g(lock);
      for (std::uint32_t v : ta) suspects.push_back(v);
      for (std::uint32_t v : tb) suspects.push_back(v);
    });
    std::sort(suspects.begin(), suspects.end());
    suspects.erase(std::unique(suspects.begin(), suspects.end()), suspects.end());
    if (suspects.empty()) return 0;
    bool moved = false;
    left = 0;
    for (std::uint32_t v : suspects) {
      if (std::binary_search(fixed.begin(), fixed.end(), m.vertices[v], less)) continue;
      const Vec3 home = m.vertices[v];
      const auto score = [&] {
        std::size_t bad = 0;
        for (std::uint32_t f : topo.vertex_faces(v)) bad += bad_contacts(f, bvh);
        return bad;
      };
      std::size_t best = score();
      Vec3 best_at = home;
      const auto step = [](double x, int d) {
        const float f = static_cast<float>(x);
        return static_cast<double>(d == 0 ? f : std::nextafter(f, d > 0 ? INFINITY : -INFINITY));
      };
      for (int dx = -1; dx <= 1 && best > 0; ++dx)
        for (int dy = -1; dy <= 1 && best > 0; ++dy)
          for (int dz = -1; dz <= 1 && best > 0; ++dz) {
            m.vertices[v] = {step(home.x, dx), step(home.y, dy), step(home.z, dz)};
            const std::size_t b = score();
            if (b < best) best = b, best_at = m.vertices[v];
          }
      m.vertices[v] = best_at;
      moved = moved || !(best_at.x == home.x && best_at.y == home.y && best_at.z == home.z);
      left += best;
    }
    if (!moved) break;
  }
  return left;
}

std::size_t count(const ValidationReport& v, DefectKind k) { return v.defect(k).count; }

}  // namespace

RepairResult repair_mesh(const TriMesh& input, const RepairOptions& options) {
  input.check_consistent();
  const Deadline deadline(options.time_limit, input.name);
  RepairReport r;
  r.file = input.name;
  r.triangles_in = input.triangles.size();
  ValidationOptions vo;
  vo.weld_tolerance = options.weld_tolerance;
  vo.threads = options.threads;
  // With float coordinates the input is rounded first, and "before" is the check of what is cut.
  TriMesh rounded;
  if (options.float_coordinates) {
    rounded = input;
    round_vertices_to_float(rounded);
  }
  const TriMesh& in = options.float_coordinates ? rounded : input;
  r.before = validate_mesh(in, vo);
  r.volume_before = r.before.volume;
  if (input.triangles.empty()) throw InputError(input.name, 0, "the mesh has no triangles: nothing to repair");
  const auto say = [&](const std::string& s) {
    if (!options.quiet) std::fprintf(stderr, "frep: repair: %s (%.2f s)\n", s.c_str(), deadline.seconds());
  };
  TriMesh m;
  if (r.before.is_solid()) {
    // Nothing to cut: the welded input as it is (its zero-area triangles close it).
    m = weld(in, {options.weld_tolerance}).mesh;
    m.origins.clear();
    r.after = r.before;
  } else {
    // Cracks: vertices closer than the tolerance (by default a fraction of the part's size) are
    // merged; where coordinates are too far from the origin for that fraction to be resolved,
    // only identical positions.
    const Box3 box = bounding_box(in);
    double tol = options.weld_tolerance > 0 ? options.weld_tolerance : options.weld_relative * length(box.size());
    const double far = std::max({std::fabs(box.lo.x), std::fabs(box.lo.y), std::fabs(box.lo.z), std::fabs(box.hi.x),
                                 std::fabs(box.hi.y), std::fabs(box.hi.z)});
    if (!(tol > 0) || !std::isfinite(tol) || !(far / tol < 1e15)) tol = options.weld_tolerance;
    r.weld_tolerance = tol;
    std::size_t merged = 0;
    m = clean(in, tol, r.degenerate_removed, &merged);
    // Merges within the exact weld are what frep check welds too: count only the closed cracks.
    const std::size_t used = r.before.file_vertices - r.before.defect(DefectKind::UnusedVertices).count;
    r.vertices_merged = merged - (used - r.before.welded_vertices);
    if (!m.triangles.empty()) orient_sheets(m, r);
    vo.weld_tolerance = 0;
    const int rounds = std::max(1, options.max_rounds) * (options.float_coordinates ? 2 : 1);
    std::size_t last_defects = 0;
    for (int round = 1; round <= rounds; ++round) {
      if (m.triangles.empty()) break;
      r.rounds = round;
      say("round " + std::to_string(round) + ": cutting " + std::to_string(m.triangles.size()) + " triangles");
      m = cut_and_keep(m, r, deadline, options.threads);
      std::size_t dropped = 0;
      // Rounded to float, cut points may land across a triangle that passes within a unit of
      // the last place: settle_float_points moves them to a float that does not; what is left
      // crossing, the next round cuts.
      if (options.float_coordinates) round_vertices_to_float(m);
      m = clean(m, 0, dropped);
      if (m.triangles.empty()) break;
      if (options.float_coordinates) settle_float_points(m, in.vertices);
      if (const std::size_t split = separate_touching(m, touching_gap(m, options.float_coordinates))) {
        r.vertices_separated += split;
        if (options.float_coordinates) round_vertices_to_float(m);
        m = clean(m, 0, dropped);
      }
      r.after = validate_mesh(m, vo);
      say("after round " + std::to_string(round) + ": " + r.after.summary());
      if (r.after.is_solid()) break;
      // Another round helps where rounding left a few crossings; where the defects grow instead,
      // the exact path has failed (make_solid then approximates).
      std::size_t defects = 0;
      for (DefectKind k : {DefectKind::OpenEdges, DefectKind::NonManifoldEdges, DefectKind::SelfIntersections,
                           DefectKind::Overlaps, DefectKind::InconsistentOrientation, DefectKind::DuplicateTriangles})
        defects += count(r.after, k);
      if (round > 1 && defects >= last_defects) break;
      last_defects = defects;
      const bool only_holes = count(r.after, DefectKind::OpenEdges) > 0 &&
                              count(r.after, DefectKind::SelfIntersections) == 0 &&
                              count(r.after, DefectKind::Overlaps) == 0 &&
                              count(r.after, DefectKind::NonManifoldEdges) == 0 &&
                              count(r.after, DefectKind::InconsistentOrientation) == 0;
      if (only_holes && options.fill_holes) {
        say("filling holes");
        holes::Filled filled;
        std::string why;
        if (!holes::fill(m, 5000, filled, why)) throw InputError(input.name, 0, "holes could not be filled: " + why);
        r.holes.insert(r.holes.end(), filled.holes.begin(), filled.holes.end());
        if (filled.unfaired)
          r.notes.push_back(std::to_string(filled.unfaired) + " filled holes could not be faired (left flat)");
        m = std::move(filled.mesh);
        if (options.float_coordinates) round_vertices_to_float(m);
        m = clean(m, 0, dropped);
        r.after = validate_mesh(m, vo);
        if (r.after.is_solid()) break;
      } else if (only_holes) {
        throw InputError(input.name, 0, "the mesh has holes (" + std::to_string(count(r.after, DefectKind::OpenEdges)) +
                                            " open edges) and hole filling is off");
      }
      deadline.poll();
    }
    if (m.triangles.empty())
      throw InputError(input.name, 0, "the mesh encloses no volume (no part of it has winding number 1/2 or more)");
    if (!r.after.is_solid())
      throw InputError(input.name, 0, "repair could not make a valid solid; what is left: " + r.after.summary());
    r.changed = true;
  }
  r.exact = r.holes.empty();
  r.triangles_out = m.triangles.size();
  r.volume_after = r.after.volume;
  return {std::move(m), std::move(r)};
}

std::string repair_summary(const RepairReport& r) {
  if (!r.changed) return "nothing to repair";
  std::string s;
  const auto add = [&](const std::string& part) { s += (s.empty() ? "" : ", ") + part; };
  if (r.remeshed) return "no exact repair: remeshed its winding-number field at " + std::to_string(r.remeshed) +
                         " cells (" + std::to_string(r.triangles_out) + " triangles, volume " + fmt_g(r.volume_after) + ")";
  if (r.vertices_merged) add("merged " + std::to_string(r.vertices_merged) + " vertices (cracks)");
  if (r.degenerate_removed) add("removed " + std::to_string(r.degenerate_removed) + " flat triangles");
  if (r.triangles_turned || r.shells_turned)
    add("turned " + std::to_string(r.triangles_turned) + " triangles and " + std::to_string(r.shells_turned) + " shells");
  if (r.cut_triangles) add("cut " + std::to_string(r.cut_triangles) + " triangles where they meet");
  if (r.patches_removed) add("removed " + std::to_string(r.patches_removed) + " inner patches");
  if (r.vertices_separated) add("separated touching bodies at " + std::to_string(r.vertices_separated) + " vertices");
  if (!r.holes.empty()) add("filled " + std::to_string(r.holes.size()) + " holes");
  return s + "; volume " + fmt_g(r.volume_after) + (r.exact ? " (exact)" : "");
}

std::string format_repair_report(const RepairReport& r) {
  std::string s = r.file + ": " + std::to_string(r.triangles_in) + " triangles in, " + std::to_string(r.triangles_out) +
                  " out\n  before: " + r.before.summary() + "\n";
  if (!r.changed) return s + "  nothing to repair\n";
  if (r.vertices_merged)
    s += "  merged " + std::to_string(r.vertices_merged) + " vertices closer than " + fmt_g(r.weld_tolerance) + " (cracks)\n";
  if (r.degenerate_removed) s += "  removed " + std::to_string(r.degenerate_removed) + " triangles that bound nothing (a repeated vertex or collinear corners)\n";
  if (r.triangles_turned) s += "  turned " + std::to_string(r.triangles_turned) + " triangles to agree with their neighbours\n";
  if (r.shells_turned) s += "  turned " + std::to_string(r.shells_turned) + " closed shells that faced inward (not cavities)\n";
  if (r.crossing_pairs || r.overlapping_pairs || r.touching_pairs)
    s += "  cut " + std::to_string(r.cut_triangles) + " triangles where they meet: " + std::to_string(r.crossing_pairs) +
         " crossing pairs, " + std::to_string(r.overlapping_pairs) + " coplanar overlaps, " +
         std::to_string(r.touching_pairs) + " touching pairs; " + std::to_string(r.new_vertices) + " new vertices\n";
  s += "  " + std::to_string(r.patches) + " patches: " + std::to_string(r.patches_removed) + " removed (area " +
       fmt_g(r.area_removed) + "), " + std::to_string(r.patches_flipped) + " turned to face outside\n";
  for (std::size_t i = 0; i < std::min<std::size_t>(r.removed_at.size(), 5); ++i)
    s += "    removed a patch at " + fmt_point(r.removed_at[i]) + "\n";
  for (const FilledHole& h : r.holes)
    s += "  filled a hole of " + std::to_string(h.boundary_edges) + " edges at " + fmt_point(h.at) + " (area " +
         fmt_g(h.area) + ")\n";
  if (r.vertices_separated)
    s += "  separated the bodies at " + std::to_string(r.vertices_separated) +
         " vertices where they touch (each copy moved a hair, 2^-32 of the size or 2^-18 with float coordinates, into its own body)\n";
  s += "  components: " + std::to_string(r.before.components) + " before, " + std::to_string(r.after.components) + " after\n";
  s += "  volume: " + fmt_g(r.volume_before) + " before (signed, overlaps counted as often as covered), " +
       fmt_g(r.volume_after) + " after\n";
  for (const std::string& n : r.notes) s += "  note: " + n + "\n";
  if (r.remeshed)
    s += "  approximate: remeshed the winding-number signed distance at " + std::to_string(r.remeshed) + " cells across\n";
  else
    s += std::string("  ") + (r.exact ? "exact: the output bounds the region the input winds around"
                                      : "approximate where holes were filled; exact elsewhere") + "\n";
  s += "  after: " + r.after.summary() + "\n";
  return s;
}

std::string repair_report_json(const RepairReport& r) {
  const auto num = [](std::size_t v) { return std::to_string(v); };
  std::string s = "{\n  \"file\": \"" + json_escape(r.file) + "\",\n";
  s += "  \"triangles_in\": " + num(r.triangles_in) + ",\n  \"triangles_out\": " + num(r.triangles_out) + ",\n";
  s += "  \"changed\": " + std::string(r.changed ? "true" : "false") + ",\n  \"exact\": " + (r.exact ? "true" : "false") + ",\n";
  s += "  \"weld_tolerance\": " + json_num(r.weld_tolerance) + ",\n  \"vertices_merged\": " + num(r.vertices_merged) + ",\n";
  s += "  \"degenerate_removed\": " + num(r.degenerate_removed) + ",\n  \"crossing_pairs\": " + num(r.crossing_pairs) +
       ",\n  \"overlapping_pairs\": " + num(r.overlapping_pairs) + ",\n  \"touching_pairs\": " + num(r.touching_pairs) +
       ",\n  \"cut_triangles\": " + num(r.cut_triangles) + ",\n  \"new_vertices\": " + num(r.new_vertices) +
       ",\n  \"patches\": " + num(r.patches) + ",\n  \"patches_removed\": " + num(r.patches_removed) +
       ",\n  \"area_removed\": " + json_num(r.area_removed) + ",\n  \"patches_flipped\": " + num(r.patches_flipped) + ",\n  \"triangles_turned\": " + num(r.triangles_turned) +
       ",\n  \"shells_turned\": " + num(r.shells_turned) +
       ",\n  \"vertices_separated\": " + num(r.vertices_separated) + ",\n  \"remeshed\": " + std::to_string(r.remeshed) + ",\n  \"rounds\": " + std::to_string(r.rounds) + ",\n";
  s += "  \"removed_at\": [";
  for (std::size_t i = 0; i < r.removed_at.size(); ++i)
    s += (i ? ", [" : "[") + json_num(r.removed_at[i].x) + ", " + json_num(r.removed_at[i].y) + ", " +
         json_num(r.removed_at[i].z) + "]";
  s += "],\n  \"holes\": [";
  for (std::size_t i = 0; i < r.holes.size(); ++i) {
    const FilledHole& h = r.holes[i];
    s += std::string(i ? ", " : "") + "{\"boundary_edges\": " + num(h.boundary_edges) + ", \"area\": " + json_num(h.area) +
         ", \"at\": [" + json_num(h.at.x) + ", " + json_num(h.at.y) + ", " + json_num(h.at.z) + "]}";
  }
  s += "],\n  \"volume_before\": " + json_num(r.volume_before) + ",\n  \"volume_after\": " + json_num(r.volume_after) + ",\n";
  s += "  \"notes\": [";
  for (std::size_t i = 0; i < r.notes.size(); ++i) s += std::string(i ? ", " : "") + "\"" + json_escape(r.notes[i]) + "\"";
  s += "],\n  \"before\": \"" + json_escape(r.before.summary()) + "\",\n  \"after\": \"" + json_escape(r.after.summary()) + "\"\n}\n";
  return s;
}

}  // namespace frep
