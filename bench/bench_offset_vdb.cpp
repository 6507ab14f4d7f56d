// The OpenVDB pipeline that frep offset and frep shell are measured against, and the error measure
// both are judged by (bench/offset_vs_openvdb.sh runs them side by side):
//
//   bench_offset_vdb offset MESH DIST RES OUT.stl
//       OpenVDB's offset of MESH by DIST > 0 at frep offset's voxel size for -r RES: the signed
//       distance in a band just wide enough (meshToSignedDistanceField, DIST / voxel + 3 voxels
//       outside, 3 inside), then volumeToMesh at isovalue DIST. Prints the seconds it took.
//   bench_offset_vdb shell MESH THICK RES OUT.stl
//       The same for frep shell's wall of THICK inside the surface: the band covers
//       [-THICK - 3 voxels, 3 voxels], the values become |d + THICK/2| - THICK/2, and volumeToMesh
//       meshes 0 (both walls).
//   bench_offset_vdb error MESH (offset DIST | shell THICK) OUT.stl
//       How far OUT's vertices are from the exact surface they stand for, by MESH's exact signed
//       distance d (frep's MeshDistance): |d - DIST| for an offset, min(|d|, |d + THICK|) for a
//       shell. Prints the mean and the largest, relative to the voxel size too when RES is given.
//
// The voxel size is frep's: the region meshed is the mesh's box grown by DIST (offset; the
// mesh's box for a shell), RES cells across its longest side.
// Build: cmake -DFREP_BUILD_BENCH=ON (needs libopenvdb-dev); bench/offset_vs_openvdb.sh builds it.
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "frep/mesh/mesh_distance.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/weld.hpp"

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

// frep's cell size for -r res over the mesh's box grown by `grow`.
double voxel_size(const frep::Box3& box, double grow, int res) {
  const frep::Vec3 s = box.size();
  return (std::max({s.x, s.y, s.z}) + 2 * grow) / res;
}

int usage(const char* argv0) {
  std::fprintf(stderr,
               "usage: %s offset MESH DIST RES OUT.stl\n"
               "       %s shell MESH THICK RES OUT.stl\n"
               "       %s error MESH (offset DIST | shell THICK) OUT.stl [RES]\n",
               argv0, argv0, argv0);
  return 2;
}

int run_vdb(bool shell, const std::string& path, double amount, int res, const std::string& out) {
  openvdb::initialize();
  const frep::TriMesh mesh = frep::read_mesh(path);
  const double t0 = now();
  const frep::Box3 box = frep::bounding_box(mesh);
  const double h = voxel_size(box, shell ? 0.0 : amount, res);
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> tris;
  std::vector<openvdb::Vec4I> quads;
  points.reserve(mesh.vertices.size());
  for (const frep::Vec3& v : mesh.vertices)
    points.emplace_back(static_cast<float>(v.x / h), static_cast<float>(v.y / h), static_cast<float>(v.z / h));
  for (const frep::Triangle& t : mesh.triangles) tris.emplace_back(t[0], t[1], t[2]);
  const auto xform = openvdb::math::Transform::createLinearTransform(h);
  // Index-space points with a transform of voxel size h: distances come out in world units.
  const auto index_xform = openvdb::math::Transform::createLinearTransform(1.0);
  const float band = 3;
  const float a = static_cast<float>(amount / h);
  openvdb::FloatGrid::Ptr grid =
      shell ? openvdb::tools::meshToSignedDistanceField<openvdb::FloatGrid>(*index_xform, points, tris, quads, band, a + band)
            : openvdb::tools::meshToSignedDistanceField<openvdb::FloatGrid>(*index_xform, points, tris, quads, a + band, band);
  // Values are in voxels (index space); the transform places volumeToMesh's points in the world.
  grid->setTransform(xform);
  double iso = shell ? 0.0 : a;
  if (shell) {
    const float half = a / 2;
    // Every value, tiles too: the inside's inactive tiles hold -background, which must become
    // positive (inside the solid but outside the wall).
    for (auto it = grid->beginValueAll(); it; ++it) it.setValue(std::fabs(it.getValue() + half) - half);
  }
  std::vector<openvdb::Vec3s> vp;
  std::vector<openvdb::Vec3I> vt;
  std::vector<openvdb::Vec4I> vq;
  openvdb::tools::volumeToMesh(*grid, vp, vt, vq, iso);
  const double t1 = now();
  frep::TriMesh m;
  for (const auto& p : vp) m.vertices.push_back({p.x(), p.y(), p.z()});
  // volumeToMesh's faces wind the other way from frep's (outward) convention: flipped.
  for (const auto& t : vt) m.triangles.push_back({t.x(), t.z(), t.y()});
  for (const auto& q : vq) {
    m.triangles.push_back({q.x(), q.z(), q.y()});
    m.triangles.push_back({q.x(), q.w(), q.z()});
  }
  frep::write_mesh(out, m);
  std::printf("openvdb %s: %.3f s (voxel %.6g, %zu active voxels, %zu triangles)\n", shell ? "shell" : "offset", t1 - t0, h,
              static_cast<std::size_t>(grid->activeVoxelCount()), m.triangles.size());
  return 0;
}

int run_error(const std::string& path, bool shell, double amount, const std::string& out, int res) {
  const frep::TriMesh mesh = frep::read_mesh(path);
  const frep::MeshDistance d(mesh);
  const frep::TriMesh result = frep::read_mesh(out);
  const frep::TriMesh welded = frep::weld(result, {}).mesh;
  std::vector<double> x, y, z;
  for (const frep::Vec3& v : welded.vertices) x.push_back(v.x), y.push_back(v.y), z.push_back(v.z);
  std::vector<double> sd(x.size());
  d.signed_distance(x.data(), y.data(), z.data(), sd.data(), x.size(), frep::SignMethod::Pseudonormal);
  double sum = 0, worst = 0;
  for (double s : sd) {
    const double e = shell ? std::min(std::fabs(s), std::fabs(s + amount)) : std::fabs(s - amount);
    sum += e;
    worst = std::max(worst, e);
  }
  const double mean = sd.empty() ? NAN : sum / static_cast<double>(sd.size());
  std::printf("error %s: mean %.4g, max %.4g over %zu vertices", out.c_str(), mean, worst, sd.size());
  if (res > 0) {
    const double h = voxel_size(frep::bounding_box(mesh), shell ? 0.0 : amount, res);
    std::printf(" (mean %.4f, max %.3f voxels)", mean / h, worst / h);
  }
  std::printf("\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage(argv[0]);
  const std::string mode = argv[1];
  try {
    if ((mode == "offset" || mode == "shell") && argc == 6)
      return run_vdb(mode == "shell", argv[2], std::atof(argv[3]), std::atoi(argv[4]), argv[5]);
    if (mode == "error" && (argc == 6 || argc == 7))
      return run_error(argv[2], std::string(argv[3]) == "shell", std::atof(argv[4]), argv[5], argc == 7 ? std::atoi(argv[6]) : 0);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_offset_vdb: %s\n", e.what());
    return 1;
  }
  return usage(argv[0]);
}
