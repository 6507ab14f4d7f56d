// Example: the fields pictured in docs/ugf.md, one .vm file each, all in the plane z = 0 (and
// drawn with `frep render FILE --slice z=0`, see examples/ugf_pictures.sh). Each shows one UGF
// operation on planes or circles through or near the origin, sized for the square [-1, 1]^2.
//
//   ugf_pictures [OUTPUT_DIR]        (default: the current directory)
#include <cmath>
#include <cstdio>
#include <exception>
#include <numbers>
#include <string>

#include "frep/expr/graph.hpp"
#include "frep/io/vm.hpp"
#include "frep/ugf.hpp"

namespace {

namespace ugf = frep::ugf;
using frep::Expr;

std::string dir = ".";

void save(const std::string& name, const Expr& e) {
  const std::string path = dir + "/ugf_" + name + ".vm";
  frep::save_vm(path, e.graph(), e.id());
  std::printf("%-36s %zu nodes\n", path.c_str(), frep::reachable_nodes(e.graph(), e.id()).size());
}

// The signed distance to the line through `p0` with outward unit normal at `degrees`.
Expr plane(frep::Graph& g, double degrees, double px = 0, double py = 0) {
  const double a = degrees * std::numbers::pi / 180;
  const float nx = static_cast<float>(std::cos(a)), ny = static_cast<float>(std::sin(a));
  return g.x() * nx + g.y() * ny - static_cast<float>(nx * px + ny * py);
}

// Two faces through the origin whose outward normals are `phi` degrees apart, symmetric about
// +x: their intersection is a wedge pointing to +x with an interior angle of 180 - phi.
std::pair<Expr, Expr> edge(frep::Graph& g, double phi) { return {plane(g, phi / 2), plane(g, -phi / 2)}; }

// `first` where c >= 0, `second` where c < 0: two fields side by side in one picture.
Expr split(Expr c, Expr first, Expr second) { return frep::if_nonzero_else(compare(c, 0.0f) + 1.0f, first, second); }

Expr circle(frep::Graph& g, float cx, float cy, float r) {
  return sqrt(square(g.x() - cx) + square(g.y() - cy)) - r;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc > 1) dir = argv[1];
    frep::Graph g;
    auto x = g.x(), y = g.y();

    // Offsets: a square as max of slabs offset by 0.25 keeps its corners (mitred, left half); the
    // exact square distance (intersect_exact of the slabs) offsets to a rounded square (right).
    const Expr slab_x = abs(x) - 0.4f, slab_y = abs(y) - 0.4f;
    save("offset", split(-x, ugf::offset(max(slab_x, slab_y), 0.25f), ugf::offset(ugf::intersect_exact(slab_x, slab_y), 0.25f)));

    // Shells of an exact rectangle, wall 0.15: centred, all inward (b = +1), and graded along x
    // from 0.04 to 0.3.
    const Expr rect = ugf::intersect_exact(abs(x) - 0.55f, abs(y) - 0.35f);
    save("shell", ugf::shell(rect, 0.15f));
    save("shell_biased", ugf::shell_biased(rect, 0.15f, 1.0f));
    save("shell_variable", ugf::shell_variable(rect, (x + 1.0f) * 0.13f + 0.04f));

    // Booleans: the intersection of two faces 60 degrees apart, as max (top half) and exact
    // (bottom half).
    {
      auto [A, B] = edge(g, 60);
      save("intersect", split(y, ugf::intersect(A, B), ugf::intersect_exact(A, B)));
    }

    // Blends: the four smooth unions of x <= 0 and y <= 0 (a concave corner), k = 0.5.
    const char* blend_names[] = {"quadratic", "cubic", "exponential", "root"};
    const ugf::Blend blends[] = {ugf::Blend::Quadratic, ugf::Blend::Cubic, ugf::Blend::Exponential, ugf::Blend::Root};
    for (int i = 0; i < 4; ++i) save(std::string("blend_") + blend_names[i], ugf::smooth_union(x, y, 0.5f, blends[i]));

    // The edge frame of a 120-degree edge: Sn (along the bisector) and Dn (across it).
    {
      auto [A, B] = edge(g, 120);
      const ugf::EdgeFrame f = ugf::edge_frame(A, B);
      save("frame_sn", f.Sn);
      save("frame_dn", f.Dn);
    }

    // Chamfers of a right-angled corner (x <= 0.3, y <= 0.3): inset 0.2, setback 0.4, width 0.5,
    // setbacks 0.25 along A (x = 0.3) and 0.6 along B; and setback 0.4 plain (above the
    // diagonal) and distance-preserving (below it).
    {
      const Expr A = x - 0.3f, B = y - 0.3f;
      save("chamfer_inset", ugf::chamfer_intersection(A, B, ugf::Chamfer::inset(0.2f)));
      save("chamfer_setback", ugf::chamfer_intersection(A, B, ugf::Chamfer::setback(0.4f)));
      save("chamfer_width", ugf::chamfer_intersection(A, B, ugf::Chamfer::width(0.5f)));
      save("chamfer_setbacks", ugf::chamfer_intersection(A, B, ugf::Chamfer::setbacks(0.25f, 0.6f)));
      const ugf::Chamfer s = ugf::Chamfer::setback(0.4f);
      save("chamfer_exact", split(y - x, ugf::chamfer_intersection(A, B, s),
                                  ugf::chamfer_intersection(A, B, s.distance_preserving())));
    }

    // Rounds, r = 0.3, of edges whose normals are 45 and 135 degrees apart.
    for (int phi : {45, 135}) {
      auto [A, B] = edge(g, phi);
      save("round_intersection_" + std::to_string(phi), ugf::round_intersection(A, B, 0.3f));
      save("round_union_" + std::to_string(phi), ugf::round_union(A, B, 0.3f));
    }

    // Pencils: planes through a 90-degree edge at theta = -45 (face B) to +45 (face A) and the
    // bisector plane (90): the picture is min over theta of |pencil(theta)| - 0.01, the fan of
    // lines drawn as thin strips (a zero line is drawn where the field changes sign).
    {
      auto [A, B] = edge(g, 90);
      const ugf::EdgeFrame f = ugf::edge_frame(A, B);
      Expr fan = abs(ugf::pencil(f, static_cast<float>(std::numbers::pi / 2)));
      for (int deg = -45; deg <= 45; deg += 15)
        fan = min(fan, abs(ugf::pencil(f, static_cast<float>(deg * std::numbers::pi / 180))));
      save("pencils", fan - 0.01f);
    }

    // Two bodies: circles A and B. Xi; the surfaces Xi = -0.5, 0, 0.5 (min of |between| - 0.01,
    // thin strips); and the
    // clearance field S = A + B less (gap + 0.02), negative only next to S's minimum, the
    // segment between the circles' closest points.
    {
      const Expr A = circle(g, -0.45f, -0.1f, 0.25f), B = circle(g, 0.45f, 0.15f, 0.3f);
      save("two_body_xi", ugf::two_body(A, B));
      save("two_body_between", min(min(abs(ugf::between(A, B, -0.5f)), abs(ugf::between(A, B, 0.0f))),
                                   abs(ugf::between(A, B, 0.5f))) - 0.01f);
      const float gap = std::hypot(0.9f, 0.25f) - 0.55f;
      save("two_body_clearance", ugf::clearance_field(A, B) - (gap + 0.02f));
    }

    // Gyroid, period 0.8 (the slice z = 0): network (bias 0) and sheet (wall 0.1), Sampson
    // normalized (left half) and bound-scaled (right half).
    save("gyroid_network", split(-x, ugf::gyroid_network(g, 0.8f, 0.0f, ugf::GyroidScale::Sampson),
                                 ugf::gyroid_network(g, 0.8f, 0.0f, ugf::GyroidScale::Bound)));
    save("gyroid_sheet", split(-x, ugf::gyroid_sheet(g, 0.8f, 0.1f, ugf::GyroidScale::Sampson),
                               ugf::gyroid_sheet(g, 0.8f, 0.1f, ugf::GyroidScale::Bound)));

    // Medial tracking: m of a 1.4 x 0.8 rectangle built from four planes, the distance to its
    // crease set (the diagonal planes and the middle segment).
    {
      ugf::Tracked r = ugf::track_plane(x - 0.7f);
      r = ugf::intersect(r, ugf::track_plane(-x - 0.7f));
      r = ugf::intersect(r, ugf::track_plane(y - 0.4f));
      r = ugf::intersect(r, ugf::track_plane(-y - 0.4f));
      save("medial_m", r.m);
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ugf_pictures: %s\n", e.what());
    return 1;
  }
}
