// Processing one leaf: corner samples, surface cells with their face decisions, edge crossings
// (batched root finding), normals (batched gradients) and dual vertices (QEF or snap).
#include "contour/leaf.hpp"

#include <algorithm>
#include <cmath>

#include "contour/cell_topology.hpp"
#include "contour/qef.hpp"
#include "frep/error.hpp"

namespace frep::contour {
namespace {

constexpr double kInside = kVertexInset;
// A QEF minimizer may leave its cell by this much (in cells); beyond, the QEF is minimized over
// the cell instead.
constexpr double kSlack = 0.05;

Vec3 normalized_or_zero(double x, double y, double z) {
  const double l = std::sqrt(x * x + y * y + z * z);
  if (!(l > 1e-30) || !std::isfinite(l)) return {};
  return {x / l, y / l, z / l};
}

}  // namespace

bool LeafMesher::process(const Tape& tape, const IndexBox& box, LeafRecord& out) {
  box_ = box;
  ex_ = box.extent(0);
  ey_ = box.extent(1);
  ez_ = box.extent(2);
  cx_ = ex_ + 1;
  cy_ = ey_ + 1;
  cz_ = ez_ + 1;
  const int cz = cz_;
  const std::size_t corners = static_cast<std::size_t>(cx_) * cy_ * cz;
  stride_[0] = 1;
  stride_[1] = static_cast<std::size_t>(cx_);
  stride_[2] = static_cast<std::size_t>(cx_) * static_cast<std::size_t>(cy_);
  for (int c = 0; c < 8; ++c) off_[c] = (c & 1) * stride_[0] + ((c >> 1) & 1) * stride_[1] + ((c >> 2) & 1) * stride_[2];
  xs_.resize(corners);
  ys_.resize(corners);
  zs_.resize(corners);
  values_.resize(corners);
  {
    const auto& gx = grid_.grid.coords[0];
    const auto& gy = grid_.grid.coords[1];
    const auto& gz = grid_.grid.coords[2];
    std::size_t k = 0;
    for (int z = 0; z < cz; ++z)
      for (int y = 0; y < cy_; ++y) {
        const float fy = gy[static_cast<std::size_t>(box.lo[1] + y)], fz = gz[static_cast<std::size_t>(box.lo[2] + z)];
        for (int x = 0; x < cx_; ++x, ++k) {
          xs_[k] = gx[static_cast<std::size_t>(box.lo[0] + x)];
          ys_[k] = fy;
          zs_[k] = fz;
        }
      }
  }
  sample_corners(tape);
  {
    // Exact zeros inside the grid, next to another along a cell edge: a face or an edge of the
    // shape lies on grid lines (the grid's boundary is 0 where the cut closes the shape, on
    // purpose; a lone zero, a smooth surface through a corner, is harmless).
    const auto interior = [&](int x, int y, int z) {
      return box.lo[0] + x > 0 && box.lo[0] + x < grid_.n[0] && box.lo[1] + y > 0 && box.lo[1] + y < grid_.n[1] &&
             box.lo[2] + z > 0 && box.lo[2] + z < grid_.n[2];
    };
    std::size_t k = 0;
    for (int z = 0; z < cz; ++z)
      for (int y = 0; y < cy_; ++y)
        for (int x = 0; x < cx_; ++x, ++k) {
          if (values_[k] != 0 || !interior(x, y, z)) continue;
          const bool pair = (x + 1 < cx_ && values_[k + 1] == 0 && interior(x + 1, y, z)) ||
                            (y + 1 < cy_ && values_[k + stride_[1]] == 0 && interior(x, y + 1, z)) ||
                            (z + 1 < cz && values_[k + stride_[2]] == 0 && interior(x, y, z + 1));
          zero_corners_ += pair;
        }
  }
  {
    bool in = false, outside = false;
    for (std::size_t k = 0; k < corners; ++k) (values_[k] < 0 ? in : outside) = true;
    if (!in || !outside) return false;
  }

  const std::size_t* stride = stride_;
  const std::size_t* off = off_;

  out.box = box;
  out.cells.clear();
  out.cell_slot.assign(static_cast<std::size_t>(ex_) * ey_ * ez_, kNoCell);
  out.positions.clear();
  out.normals.clear();
  out.mass.clear();
  out.piece.clear();
  out.touches_cap = false;
  crossings_.clear();
  cell_index_.clear();
  for (auto& s : edge_slot_) s.assign(corners, -1);

  for (int z = 0; z < ez_; ++z)
    for (int y = 0; y < ey_; ++y)
      for (int x = 0; x < ex_; ++x) {
        const std::size_t base = x + stride[1] * y + stride[2] * z;
        std::uint8_t config = 0;
        for (int c = 0; c < 8; ++c)
          if (values_[base + off[c]] < 0) config |= static_cast<std::uint8_t>(1u << c);
        if (config == 0 || config == 0xff) continue;
        SurfaceCell sc;
        sc.config = config;
        // Face ambiguities: join the inside corners across the face when the product of the
        // inside diagonal's values exceeds the outside diagonal's (the sign of the bilinear
        // saddle, as in the asymptotic decider). Both cells of a face see the same four values
        // in the same roles, so they agree; products of floats are exact in double.
        const std::uint8_t amb = ambiguous_faces(config);
        for (int f = 0; f < kCellFaces; ++f) {
          if (!(amb >> f & 1)) continue;
          const int a = f / 2, side = f % 2;
          const int p = a == 0 ? 1 : 0, q = a == 2 ? 1 : 2;
          auto val = [&](int u, int v) {
            return static_cast<double>(values_[base + off[(side << a) | (u << p) | (v << q)]]);
          };
          const double d0 = val(0, 0) * val(1, 1), d1 = val(1, 0) * val(0, 1);
          const bool in00 = (config >> ((side << a))) & 1;
          const bool join = in00 ? d0 > d1 : d1 > d0;
          if (join) sc.decisions |= static_cast<std::uint8_t>(1u << f);
        }
        for (int e = 0; e < kCellEdges; ++e) {
          const int c0 = cell_edge_corner(e, 0), c1 = cell_edge_corner(e, 1);
          if (((config >> c0) & 1) == ((config >> c1) & 1)) continue;
          const int axis = e / 4;
          const std::size_t low = base + off[c0];
          std::int32_t& slot = edge_slot_[axis][low];
          if (slot < 0) {
            slot = static_cast<std::int32_t>(crossings_.size());
            crossings_.push_back({static_cast<std::uint32_t>(low), static_cast<std::uint8_t>(axis), 0.5f, {}, {}});
          }
        }
        FREP_ASSERT(out.cells.size() < kNoCell, "too many cells in a leaf");
        out.cell_slot[static_cast<std::size_t>(x) + static_cast<std::size_t>(ex_) * (y + static_cast<std::size_t>(ey_) * z)] =
            static_cast<std::uint16_t>(out.cells.size());
        out.cells.push_back(sc);
        cell_index_.push_back(static_cast<std::uint32_t>(base));
      }
  if (out.cells.empty()) return false;

  // Does the shape reach the box it is cut at? On the box's faces the closed field is
  // max(f, 0): exactly 0 where f <= 0. Checked where crossing edges meet a face of the box.
  {
    std::size_t m = 0;
    for (const Crossing& c : crossings_) {
      const int a = c.axis;
      const auto g = grid_index(c.corner);
      const double p0 = grid_.coord(a, g[a]), p1 = grid_.coord(a, g[a] + 1);
      for (double plane : {cut_.lo[a], cut_.hi[a]}) {
        if (!(plane >= p0 && plane <= p1)) continue;
        float q[3] = {grid_.grid.coords[0][static_cast<std::size_t>(g[0])], grid_.grid.coords[1][static_cast<std::size_t>(g[1])],
                      grid_.grid.coords[2][static_cast<std::size_t>(g[2])]};
        q[a] = static_cast<float>(plane);
        if (m >= cap_x_.size()) cap_x_.resize(m + 1), cap_y_.resize(m + 1), cap_z_.resize(m + 1);
        cap_x_[m] = q[0], cap_y_[m] = q[1], cap_z_[m] = q[2];
        ++m;
      }
    }
    if (m) {
      cap_v_.resize(m);
      batch_.eval(tape, cap_x_.data(), cap_y_.data(), cap_z_.data(), cap_v_.data(), m);
      for (std::size_t i = 0; i < m; ++i) out.touches_cap |= cap_v_[i] == 0;
    }
  }

  // Crossing positions: root finding (dual contouring) or linear interpolation (snap).
  if (o_.method == MeshMethod::DualContouring) {
    find_roots(tape);
  } else {
    for (Crossing& c : crossings_) {
      const double v0 = values_[c.corner], v1 = values_[c.corner + stride[c.axis]];
      const double t = std::isfinite(v0) && std::isfinite(v1) && v0 != v1 ? v0 / (v0 - v1) : 0.5;
      c.t = static_cast<float>(std::clamp(t, 0.0, 1.0));
    }
  }
  for (Crossing& c : crossings_) {
    const Vec3 p0 = corner_position(c.corner), p1 = corner_position(c.corner + stride[c.axis]);
    c.p = p0;
    c.p[c.axis] = p0[c.axis] + static_cast<double>(c.t) * (p1[c.axis] - p0[c.axis]);
  }
  if (o_.method == MeshMethod::DualContouring) {
    find_normals(tape);
    place_vertices_dc(tape, out);
  } else {
    place_vertices_snap(tape, out);
  }

  // The crossings on the edges each cell owns, for the assembly's fan centers.
  for (std::size_t j = 0; j < out.cells.size(); ++j)
    for (int a = 0; a < 3; ++a) {
      const std::int32_t s = edge_slot_[a][cell_index_[j]];
      out.cells[j].t[a] = s < 0 ? NAN : crossings_[static_cast<std::size_t>(s)].t;
    }
  return true;
}

void LeafMesher::sample_corners(const Tape& tape) {
  const std::size_t corners = values_.size();
  // Without a Lipschitz bound every corner is evaluated.
  const double lip = o_.lipschitz > 0 ? std::max(o_.lipschitz, 1.0) : 0;  // the cut at the box has slope 1
  const int extent = std::max({ex_, ey_, ez_});
  if (!(lip > 0) || extent < 4) {
    batch_.eval(tape, xs_.data(), ys_.data(), zs_.data(), values_.data(), corners);
    return;
  }
  // Coarse to fine: first the corners on a lattice of stride s0, then those of stride s0 / 2,
  // ..., 1. A corner q none of whose cells can meet the surface, as an evaluated corner p of the
  // coarser lattice proves (|f(p)| > L (|p - q| + a cell's diagonal), with the float slack of
  // lipschitz_bound), is not a corner of any surface cell: only its sign matters, and it is
  // f(p)'s. Every corner of a surface cell is evaluated, so the mesh is the same as from all
  // corners; corners far from the surface, the dearest ones for fields such as mesh distances,
  // are skipped.
  known_.assign(corners, 0);
  const double diagonal = grid_.h * std::sqrt(3.0) * (1 + 1e-6);
  const int dims[3] = {cx_, cy_, cz_};
  int s0 = 1;
  while (2 * s0 <= extent / 2) s0 *= 2;
  // On the lattice of stride s along every axis (the last corner of an axis counts as on it).
  const auto on = [&](int i, int axis, int s) { return i % s == 0 || i == dims[axis] - 1; };
  const auto evaluate_pending = [&] {
    const std::size_t m = pending_.size();
    px_.resize(m), py_.resize(m), pz_.resize(m), pv_.resize(m);
    for (std::size_t j = 0; j < m; ++j) px_[j] = xs_[pending_[j]], py_[j] = ys_[pending_[j]], pz_[j] = zs_[pending_[j]];
    batch_.eval(tape, px_.data(), py_.data(), pz_.data(), pv_.data(), m);
    for (std::size_t j = 0; j < m; ++j) values_[pending_[j]] = pv_[j], known_[pending_[j]] = 1;
  };
  pending_.clear();
  for (int z = 0; z < cz_; ++z)
    for (int y = 0; y < cy_; ++y)
      for (int x = 0; x < cx_; ++x)
        if (on(x, 0, s0) && on(y, 1, s0) && on(z, 2, s0)) pending_.push_back(static_cast<std::uint32_t>(x + stride_[1] * y + stride_[2] * z));
  evaluate_pending();
  for (int s = s0 / 2; s >= 1; s /= 2) {
    const int c = 2 * s;  // the coarser lattice, all known
    pending_.clear();
    for (int z = 0; z < cz_; ++z)
      for (int y = 0; y < cy_; ++y)
        for (int x = 0; x < cx_; ++x) {
          const std::size_t k = x + stride_[1] * y + stride_[2] * z;
          if (known_[k] || !(on(x, 0, s) && on(y, 1, s) && on(z, 2, s))) continue;
          // The coarse lattice corners around q: per axis, the lattice values at or next to it.
          int lo[3], hi[3];
          const int q[3] = {x, y, z};
          for (int a = 0; a < 3; ++a) {
            lo[a] = on(q[a], a, c) ? q[a] : q[a] / c * c;
            hi[a] = on(q[a], a, c) ? q[a] : std::min((q[a] / c + 1) * c, dims[a] - 1);
          }
          bool implied = false;
          for (int cz2 = 0; cz2 < 2 && !implied; ++cz2)
            for (int cy2 = 0; cy2 < 2 && !implied; ++cy2)
              for (int cx2 = 0; cx2 < 2 && !implied; ++cx2) {
                const std::size_t p = static_cast<std::size_t>(cx2 ? hi[0] : lo[0]) + stride_[1] * (cy2 ? hi[1] : lo[1]) +
                                      stride_[2] * (cz2 ? hi[2] : lo[2]);
                const double f = values_[p];
                if (!known_[p] || !std::isfinite(f) || f == 0) continue;
                const double dx = double(xs_[p]) - xs_[k], dy = double(ys_[p]) - ys_[k], dz = double(zs_[p]) - zs_[k];
                const double dist = std::sqrt(dx * dx + dy * dy + dz * dz);
                const double scale = std::max({std::fabs(double(xs_[k])), std::fabs(double(ys_[k])), std::fabs(double(zs_[k]))});
                const double reach = lip * (dist + diagonal) * (1 + 0x1p-16) + 0x1p-16 * (std::fabs(f) + scale + dist);
                if (std::fabs(f) > reach) {
                  // Its sign, and a magnitude no caller reads (not a surface cell's corner).
                  values_[k] = static_cast<float>(f > 0 ? std::fabs(f) - lip * dist : lip * dist - std::fabs(f));
                  implied = true;
                }
              }
          if (implied) known_[k] = 1;
          else pending_.push_back(static_cast<std::uint32_t>(k));
        }
    evaluate_pending();
  }
}

const LeafMesher::Crossing& LeafMesher::crossing(std::size_t base, int e) const {
  const std::int32_t s = edge_slot_[e / 4][base + off_[cell_edge_corner(e, 0)]];
  FREP_ASSERT(s >= 0, "crossing missing");
  return crossings_[static_cast<std::size_t>(s)];
}

void LeafMesher::find_roots(const Tape& tape) {
  const std::size_t n = crossings_.size();
  const std::size_t* stride = stride_;
  t_in_.resize(n);
  f_in_.resize(n);
  t_out_.resize(n);
  f_out_.resize(n);
  last_side_.assign(n, 0);
  active_.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const Crossing& c = crossings_[i];
    const float v0 = values_[c.corner], v1 = values_[c.corner + stride[c.axis]];
    const bool low_inside = v0 < 0;
    t_in_[i] = low_inside ? 0.0f : 1.0f;
    f_in_[i] = low_inside ? v0 : v1;
    t_out_[i] = low_inside ? 1.0f : 0.0f;
    f_out_[i] = low_inside ? v1 : v0;
    if (f_out_[i] == 0) {
      crossings_[i].t = t_out_[i];  // the corner is on the surface
      continue;
    }
    active_.push_back(static_cast<std::uint32_t>(i));
  }
  const float tol = static_cast<float>(o_.edge_tolerance);
  // Where the tape calls oracles (a mesh's distance), a gradient costs about what a value does:
  // each proposal is evaluated with its gradient, which find_normals then takes for the
  // crossings accepted there (the same point), instead of asking again.
  const bool with_gradients = tape.oracles() != nullptr;
  root_grad_.assign(with_gradients ? n : 0, Grad{});
  has_root_grad_.assign(with_gradients ? n : 0, 0);
  std::vector<float>& proposal = proposal_;
  for (int it = 0; it < o_.edge_iterations && !active_.empty(); ++it) {
    const std::size_t m = active_.size();
    proposal.resize(m);
    xs_.resize(m);
    ys_.resize(m);
    zs_.resize(m);
    for (std::size_t k = 0; k < m; ++k) {
      const std::uint32_t i = active_[k];
      const float lo = std::min(t_in_[i], t_out_[i]), hi = std::max(t_in_[i], t_out_[i]);
      const float fi = f_in_[i], fo = f_out_[i];
      float t = 0.5f * (lo + hi);
      // Secant (Illinois) steps, but bisection once one end has stayed put three times: at a bend
      // (a steep field under the flat cut) halving the far value converges too slowly.
      if (std::isfinite(fi) && std::isfinite(fo) && std::abs(last_side_[i]) < 3) {
        const float r = t_in_[i] + (t_out_[i] - t_in_[i]) * (fi / (fi - fo));
        if (r > lo && r < hi) t = r;
      }
      proposal[k] = t;
      const Crossing& c = crossings_[i];
      // Point on the edge (the corner coordinates of the low end, moved along the axis).
      const auto g = grid_index(c.corner);
      double p[3] = {grid_.coord(0, g[0]), grid_.coord(1, g[1]), grid_.coord(2, g[2])};
      p[c.axis] += static_cast<double>(t) * (grid_.coord(c.axis, g[c.axis] + 1) - p[c.axis]);
      xs_[k] = static_cast<float>(p[0]);
      ys_[k] = static_cast<float>(p[1]);
      zs_[k] = static_cast<float>(p[2]);
    }
    std::vector<float>& f = f_eval_;
    f.resize(m);
    if (with_gradients) {
      grads_.resize(m);
      grad_.eval(tape, xs_.data(), ys_.data(), zs_.data(), grads_.data(), m);
      for (std::size_t k = 0; k < m; ++k) f[k] = grads_[k].v;
    } else {
      batch_.eval(tape, xs_.data(), ys_.data(), zs_.data(), f.data(), m);
    }
    std::size_t kept = 0;
    for (std::size_t k = 0; k < m; ++k) {
      const std::uint32_t i = active_[k];
      const float t = proposal[k], v = f[k];
      // The bracket's end on the new point's side, before it moves there.
      const float t_same = v < 0 ? t_in_[i] : t_out_[i], f_same = v < 0 ? f_in_[i] : f_out_[i];
      if (v < 0) {
        t_in_[i] = t;
        f_in_[i] = v;
        if (last_side_[i] < 0) f_out_[i] *= 0.5f;  // Illinois: the other end was kept twice
        last_side_[i] = static_cast<std::int8_t>(last_side_[i] < 0 ? std::max(last_side_[i] - 1, -100) : -1);
      } else {
        t_out_[i] = t;
        f_out_[i] = v;
        if (last_side_[i] > 0) f_in_[i] *= 0.5f;
        last_side_[i] = static_cast<std::int8_t>(last_side_[i] > 0 ? std::min(last_side_[i] + 1, 100) : 1);
      }
      const float width = std::fabs(t_out_[i] - t_in_[i]);
      bool done = v == 0 || width <= tol;
      if (!done && std::isfinite(v) && std::isfinite(f_in_[i]) && std::isfinite(f_out_[i]) && std::isfinite(f_same)) {
        // Distance to the root estimated from the smaller of the bracket's slope and the slope on
        // the new point's side: where the field bends (a steep field under the flat cut at the
        // bounds, a quartic), the bracket's slope alone accepted points 0.4 cells from the root.
        const float slope = std::min(std::fabs(f_out_[i] - f_in_[i]) / width, std::fabs(v - f_same) / std::fabs(t - t_same));
        done = std::fabs(v) <= tol * slope;
      }
      if (done) {
        crossings_[i].t = t;
        if (with_gradients) root_grad_[i] = grads_[k], has_root_grad_[i] = 1;
      } else {
        active_[kept++] = i;
      }
    }
    active_.resize(kept);
  }
  for (std::uint32_t i : active_) crossings_[i].t = 0.5f * (t_in_[i] + t_out_[i]);
}

void LeafMesher::find_normals(const Tape& tape) {
  const std::size_t n = crossings_.size();
  xs_.resize(n);
  ys_.resize(n);
  zs_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    xs_[i] = static_cast<float>(crossings_[i].p.x);
    ys_[i] = static_cast<float>(crossings_[i].p.y);
    zs_[i] = static_cast<float>(crossings_[i].p.z);
  }
  // Gradients root finding found at the crossings themselves are taken as they are; the others
  // are evaluated.
  retry_.clear();
  for (std::size_t i = 0; i < n; ++i) {
    if (i < has_root_grad_.size() && has_root_grad_[i]) {
      const Grad& g = root_grad_[i];
      crossings_[i].n = Vec3f(normalized_or_zero(g.dx, g.dy, g.dz));
    } else {
      xs_[retry_.size()] = xs_[i], ys_[retry_.size()] = ys_[i], zs_[retry_.size()] = zs_[i];
      retry_.push_back(static_cast<std::uint32_t>(i));
    }
  }
  grads_.resize(retry_.size());
  grad_.eval(tape, xs_.data(), ys_.data(), zs_.data(), grads_.data(), retry_.size());
  for (std::size_t k = 0; k < retry_.size(); ++k) {
    const Grad& g = grads_[k];
    crossings_[retry_[k]].n = Vec3f(normalized_or_zero(g.dx, g.dy, g.dz));
  }
  // Where the root lands exactly on the surface of an exact distance such as sqrt(d^2) (a
  // converted mesh), the gradient is 0 by convention (sqrt'(0) = 0): take the normal just outside
  // the surface along the edge (a thousandth of a cell beyond the bracket's outside end, where the
  // nearest feature is still the one the crossing lies on), else at the bracket's outside end,
  // else at its inside end, so that the QEF still sees the planes and sharp corners stay sharp.
  // (A corner exactly on a face is its own crossing: its inside end is a cell away, where the
  // nearest feature may be another face.)
  for (int stage = 0; stage < 3; ++stage) {
    retry_.clear();
    for (std::size_t i = 0; i < n; ++i)
      if (crossings_[i].n == Vec3f{0, 0, 0}) retry_.push_back(static_cast<std::uint32_t>(i));
    if (retry_.empty()) return;
    const std::size_t m = retry_.size();
    for (std::size_t k = 0; k < m; ++k) {
      const std::uint32_t i = retry_[k];
      const Crossing& c = crossings_[i];
      const Vec3 p0 = corner_position(c.corner), p1 = corner_position(c.corner + stride_[c.axis]);
      double t = stage == 2 ? t_in_[i] : t_out_[i];
      if (stage == 0) t += t_out_[i] >= t_in_[i] ? 1e-3 : -1e-3;
      Vec3 p = p0;
      p[c.axis] = p0[c.axis] + t * (p1[c.axis] - p0[c.axis]);
      xs_[k] = static_cast<float>(p.x), ys_[k] = static_cast<float>(p.y), zs_[k] = static_cast<float>(p.z);
    }
    grad_.eval(tape, xs_.data(), ys_.data(), zs_.data(), grads_.data(), m);
    for (std::size_t k = 0; k < m; ++k) {
      const Grad& g = grads_[k];
      crossings_[retry_[k]].n = Vec3f(normalized_or_zero(g.dx, g.dy, g.dz));
    }
  }
}

void LeafMesher::place_vertices_dc(const Tape& tape, LeafRecord& out) {
  const double h = grid_.h;
  // Vertices of cells whose crossings span one direction of normals (a smooth or flat piece of
  // surface: no edge or corner to keep) move onto the surface afterwards.
  smooth_.clear();
  for (std::size_t j = 0; j < out.cells.size(); ++j) {
    SurfaceCell& sc = out.cells[j];
    const std::size_t base = cell_index_[j];
    const Vec3 lo = corner_position(base), hi = corner_position(base + off_[7]);
    const Vec3 size = (hi - lo) / h;  // about (1, 1, 1)
    const Box3 cell{{kInside, kInside, kInside}, size - Vec3{kInside, kInside, kInside}};
    const CellTopology& topo = cell_topology(sc.config, sc.decisions);
    sc.first_vertex = static_cast<std::uint32_t>(out.positions.size());
    Vec3 local[kMaxCellVertices];
    Qef qefs[kMaxCellVertices];
    for (int v = 0; v < topo.vertices; ++v) {
      Qef& q = qefs[v];
      Vec3 nsum;
      for (std::uint32_t bits = topo.edges[v]; bits; bits &= bits - 1) {
        const Crossing& c = crossing(base, __builtin_ctz(bits));
        const Vec3 p = (c.p - lo) / h;
        const Vec3 nrm(c.n);
        if (nrm.x != 0 || nrm.y != 0 || nrm.z != 0) {
          q.add(p, nrm);
          nsum += nrm;
        } else {
          q.add_point(p);
        }
      }
      local[v] = q.solve_in(cell, o_.qef_threshold, kSlack);
      out.normals.push_back(Vec3f(normalized_or_zero(nsum.x, nsum.y, nsum.z)));
      if (topo.vertices == 1 && q.planes() > 0 && q.points() == q.planes()) {
        int rank = 0;
        q.solve(o_.qef_threshold, 3, &rank);
        if (rank == 1) smooth_.push_back(static_cast<std::uint32_t>(out.positions.size()));
      }
    }
    // Several pieces of surface in one cell: each vertex at the centroid of its own crossings,
    // which keeps the pieces apart (the assembly keeps their triangles inside the cell).
    if (topo.vertices > 1)
      for (int v = 0; v < topo.vertices; ++v) local[v] = max(cell.lo, min(cell.hi, qefs[v].mass_point()));
    const Box3 inside{lo + Vec3{kInside, kInside, kInside} * h, hi - Vec3{kInside, kInside, kInside} * h};
    for (int v = 0; v < topo.vertices; ++v) {
      out.positions.push_back(to_f32_inside(lo + local[v] * h, inside));
      out.mass.push_back(to_f32_inside(lo + max(cell.lo, min(cell.hi, qefs[v].mass_point())) * h, inside));
      out.piece.push_back(static_cast<std::uint8_t>(v | topo.vertices << 4));
    }
  }
  if (!smooth_.empty()) project_smooth_vertices(tape, out);
}

void LeafMesher::project_smooth_vertices(const Tape& tape, LeafRecord& out) {
  // One Newton step onto the surface, p - f(p) grad f / |grad f|^2: a vertex at its crossings'
  // tangent plane is off a curved surface by its sag over the cell, which the step removes to
  // second order. Steps longer than half a cell are not taken; the vertex stays in its cell, as
  // the QEF kept it.
  const std::size_t m = smooth_.size();
  xs_.resize(m), ys_.resize(m), zs_.resize(m), grads_.resize(m);
  for (std::size_t i = 0; i < m; ++i) {
    const Vec3& p = out.positions[smooth_[i]];
    xs_[i] = static_cast<float>(p.x), ys_[i] = static_cast<float>(p.y), zs_[i] = static_cast<float>(p.z);
  }
  grad_.eval(tape, xs_.data(), ys_.data(), zs_.data(), grads_.data(), m);
  const double h = grid_.h;
  for (std::size_t i = 0; i < m; ++i) {
    const Grad& g = grads_[i];
    const Vec3 d{g.dx, g.dy, g.dz};
    const double d2 = length2(d);
    if (!(d2 > 0) || !std::isfinite(d2) || !std::isfinite(g.v)) continue;
    const Vec3 step = d * (g.v / d2);
    if (!(length2(step) <= 0.25 * h * h)) continue;
    Vec3& p = out.positions[smooth_[i]];
    // The vertex's cell (positions are inside it by kInside cells).
    Vec3 lo, hi;
    for (int a = 0; a < 3; ++a) {
      const int c = std::clamp(static_cast<int>(std::floor((p[a] - grid_.box.lo[a]) / h)), 0, grid_.n[a] - 1);
      lo[a] = grid_.coord(a, c) + kInside * h;
      hi[a] = grid_.coord(a, c + 1) - kInside * h;
    }
    p = to_f32_inside(p - step, Box3{lo, hi});
  }
}

void LeafMesher::place_vertices_snap(const Tape& tape, LeafRecord& out) {
  const double h = grid_.h;
  keep_in_.clear();
  for (std::size_t j = 0; j < out.cells.size(); ++j) {
    SurfaceCell& sc = out.cells[j];
    const std::size_t base = cell_index_[j];
    const Vec3 lo = corner_position(base), hi = corner_position(base + off_[7]);
    const Vec3 margin{kInside * h, kInside * h, kInside * h};
    const Box3 cell{lo + margin, hi - margin};
    const CellTopology& topo = cell_topology(sc.config, sc.decisions);
    sc.first_vertex = static_cast<std::uint32_t>(out.positions.size());
    const Vec3 center = (lo + hi) * 0.5;
    for (int v = 0; v < topo.vertices; ++v) {
      Vec3 p = center;
      Box3 keep = cell;
      if (topo.vertices > 1) {
        // Several pieces: each stays at the centroid of its own crossings (not snapped), which
        // keeps the pieces apart.
        Vec3 m;
        int count = 0;
        for (std::uint32_t bits = topo.edges[v]; bits; bits &= bits - 1) {
          m += crossing(base, __builtin_ctz(bits)).p;
          ++count;
        }
        p = to_f32_inside(m / static_cast<double>(count), cell);
        keep = Box3{p, p};
      }
      out.positions.push_back(to_f32_inside(p, cell));
      out.mass.push_back(out.positions.back());
      out.piece.push_back(static_cast<std::uint8_t>(v | topo.vertices << 4));
      keep_in_.push_back(keep);
    }
  }
  std::vector<Vec3f> normals;
  snapper_.snap(tape, out.positions, keep_in_, h, o_.snap, &normals);
  out.normals = std::move(normals);
  for (std::size_t i = 0; i < out.positions.size(); ++i) {
    // Back inside the cell (not the point box of a vertex kept at its centroid).
    const Box3& keep = keep_in_[i];
    out.positions[i] = keep.lo == keep.hi ? keep.lo : to_f32_inside(out.positions[i], keep);
  }
}

}  // namespace frep::contour
