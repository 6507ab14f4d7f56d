#include "frep/ugf/mesh_clearance.hpp"

namespace frep::ugf {

ClearanceOptions mesh_interference_options(const MeshPairResult& pair, bool in_place, ClearanceOptions opt) {
  if (pair.surfaces_meet()) {
    for (const MeshPairContactExample& e : pair.examples) opt.seeds.push_back(Vec3f(e.point));
  } else {
    opt.seeds.push_back(Vec3f(pair.a_shells_inside_b > 0 ? pair.point_a : pair.point_b));
  }
  opt.lipschitz = in_place ? 2 : 0;
  return opt;
}

bool only_touching(const MeshPairResult& pair, const ClearanceResult& r, double tolerance) {
  return pair.surfaces_meet() && !pair.interfere() && -r.value <= tolerance;
}

}  // namespace frep::ugf
