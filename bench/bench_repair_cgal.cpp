// The same-run baseline for `frep repair`: CGAL 5.5's own repair calls on each mesh,
// timed stage by stage, one TSV line per mesh.
//   build/bench/bench_repair_cgal [--time-limit S] [--memory-limit MB] [--no-extras] [--no-header]
//                                 [-o DIR [--stl]] MESH...
//
// Each mesh is read with frep's reader (read_mesh: as stored, STL corners not welded) into a
// polygon soup of exact points (Epeck), then (CGAL::Polygon_mesh_processing, "PMP"):
//   repair_soup       repair_polygon_soup (merges duplicate points, removes combinatorially
//                     degenerate and duplicate polygons, ...)
//   orient_soup       orient_polygon_soup (duplicates non-manifold vertices; false when it had to)
//   soup_to_mesh      polygon_soup_to_polygon_mesh into a CGAL::Surface_mesh<Epeck::Point_3>
//   remove_degenerate remove_degenerate_faces (zero-area faces with distinct corners, which
//                     repair_polygon_soup keeps and autorefine asserts on) *
//   autorefine        PMP::experimental::autorefine_and_remove_self_intersections (corefinement.h)
//   self_check        does_self_intersect on the result
//   orient_volume     orient_to_bound_a_volume, when the result is closed and does not
//                     self-intersect (orient_polygon_soup makes orientations consistent, not
//                     outward) *
// * CGAL's best effort beyond the four calls of the bare path; --no-extras skips them.
// The outcome is "ok" (returned true, not empty, closed, no self-intersections), "returned false",
// "empty result" (everything removed), "not closed", "self-intersecting", "not a polygon mesh"
// (the oriented soup still is not one: CGAL's precondition of polygon_soup_to_polygon_mesh),
// "exception" (CGAL assertions and errors throw CGAL::Failure_exception; the message says where),
// "timeout" or "crashed" (the stage it was in is named). Every mesh runs in a forked child under
// alarm() and an address-space limit, so one hanging or exploding mesh does not stop the run.
// With -o DIR the result is written as DIR/NAME.cgal.obj (coordinates rounded to doubles, %.17g),
// or with --stl as DIR/NAME.cgal.stl (binary STL: rounded to floats), untimed, for `frep check`.
//
// CGAL's assertions are kept on (NDEBUG is undefined for this file, as CGAL is usually measured
// with them): an inconsistent state then becomes an exception with its place instead of a
// crash or a silently wrong mesh. Build with -DFREP_CGAL_NO_ASSERTIONS to time CGAL without them.
//
// Columns: seconds per stage; cgal_s = the CGAL calls (the stages but load); total_s = the child's
// whole work (reading and the conversion to exact points included, comparable to a `frep repair`
// process);
// s_per_1k_tri = cgal_s per 1000 input triangles; degenerate_removed = faces remove_degenerate
// took away; peak_MB = the child's peak resident memory.
#ifndef FREP_CGAL_NO_ASSERTIONS
#undef NDEBUG
#endif

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/assertions_behaviour.h>
#include <CGAL/exceptions.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include "frep/mesh/mesh_io.hpp"

namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using K = CGAL::Exact_predicates_exact_constructions_kernel;
using Point = K::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;

enum Stage {
  kLoad, kRepairSoup, kOrientSoup, kSoupToMesh, kRemoveDegenerate, kAutorefine, kSelfCheck, kOrientVolume,
  kWrite, kStages
};
const char* const kStageNames[kStages] = {"load",          "repair_soup", "orient_soup", "soup_to_mesh",
                                          "remove_degenerate", "autorefine", "self_check", "orient_volume",
                                          "write"};

// What the child reports, in memory shared with the parent: still readable after a timeout or
// a crash, so the parent can say which stage it was in and what the earlier stages took.
struct Report {
  int stage = -1;               // stage running or last started
  double stage_start = 0;       // when it started (steady clock, shared by parent and child)
  double child_start = 0;       // when the child started
  double seconds[kStages];      // -1: not finished
  long triangles = -1;          // as read
  long soup_polygons = -1;      // after repair_polygon_soup
  long degenerate_removed = -1; // faces remove_degenerate_faces took away
  long out_triangles = -1;      // after autorefine
  int orient_ok = -1;           // orient_polygon_soup's result (0: it duplicated vertices)
  int closed_in = -1;           // the mesh given to autorefine is closed
  int closed_out = -1;          // the result is closed
  int self_intersecting = -1;   // does_self_intersect on the result
  double child_seconds = -1;    // the whole child's work (-1: it did not finish)
  char outcome[64];
  char message[1024];
};

void set_text(char* dst, std::size_t size, const std::string& text) {
  std::snprintf(dst, size, "%s", text.c_str());
  for (char* p = dst; *p; ++p)
    if (*p == '\t' || *p == '\n' || *p == '\r') *p = ' ';  // one TSV line per mesh
}

double now() {
  using C = std::chrono::steady_clock;
  return std::chrono::duration<double>(C::now().time_since_epoch()).count();
}

// The child: the whole repair path on one file, filling `r` as it goes.
void run_one(const std::string& path, const std::string& out_dir, const std::string& out_ext, bool extras,
             Report& r) {
  auto begin = [&](Stage s) {
    r.stage = s;
    r.stage_start = now();
  };
  auto end = [&](Stage s) { r.seconds[s] = now() - r.stage_start; };

  begin(kLoad);
  const frep::TriMesh tri = frep::read_mesh(path);
  r.triangles = static_cast<long>(tri.num_triangles());
  std::vector<Point> points;
  points.reserve(tri.num_vertices());
  for (const frep::Vec3& v : tri.vertices) points.emplace_back(v.x, v.y, v.z);
  std::vector<std::vector<std::size_t>> polygons;
  polygons.reserve(tri.num_triangles());
  for (const frep::Triangle& t : tri.triangles) polygons.push_back({t[0], t[1], t[2]});
  end(kLoad);

  begin(kRepairSoup);
  PMP::repair_polygon_soup(points, polygons);
  r.soup_polygons = static_cast<long>(polygons.size());
  end(kRepairSoup);

  begin(kOrientSoup);
  r.orient_ok = PMP::orient_polygon_soup(points, polygons) ? 1 : 0;
  end(kOrientSoup);

  begin(kSoupToMesh);
  Mesh mesh;
  const bool is_mesh = PMP::is_polygon_soup_a_polygon_mesh(polygons);
  if (is_mesh) PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);
  end(kSoupToMesh);
  if (!is_mesh) {
    set_text(r.outcome, sizeof r.outcome, "not a polygon mesh");
    set_text(r.message, sizeof r.message, "the oriented soup is not a valid polygon mesh");
    return;
  }

  if (extras) {
    begin(kRemoveDegenerate);
    const std::size_t before = mesh.number_of_faces();
    PMP::remove_degenerate_faces(mesh);
    mesh.collect_garbage();  // autorefine indexes faces 0..n-1
    r.degenerate_removed = static_cast<long>(before - mesh.number_of_faces());
    end(kRemoveDegenerate);
  }
  r.closed_in = CGAL::is_closed(mesh) ? 1 : 0;

  begin(kAutorefine);
  const bool fixed = PMP::experimental::autorefine_and_remove_self_intersections(mesh);
  r.out_triangles = static_cast<long>(mesh.number_of_faces());
  end(kAutorefine);

  begin(kSelfCheck);
  r.self_intersecting = PMP::does_self_intersect(mesh) ? 1 : 0;
  end(kSelfCheck);
  r.closed_out = CGAL::is_closed(mesh) ? 1 : 0;

  if (extras && r.closed_out && !r.self_intersecting && r.out_triangles > 0) {
    begin(kOrientVolume);
    PMP::orient_to_bound_a_volume(mesh);
    end(kOrientVolume);
  }

  if (!fixed)
    set_text(r.outcome, sizeof r.outcome, "returned false");
  else if (r.out_triangles == 0)
    set_text(r.outcome, sizeof r.outcome, "empty result");
  else if (!r.closed_out)
    set_text(r.outcome, sizeof r.outcome, "not closed");
  else if (r.self_intersecting)
    set_text(r.outcome, sizeof r.outcome, "self-intersecting");
  else
    set_text(r.outcome, sizeof r.outcome, "ok");

  // The result in doubles, for `frep check` (not timed): rounding the exact points may itself
  // create crossings, which is what a user writing the file gets. A failure here is a note, not
  // the outcome.
  if (!out_dir.empty() && r.out_triangles > 0) try {
    begin(kWrite);
    frep::TriMesh out;
    std::vector<std::uint32_t> index(mesh.number_of_vertices() + mesh.number_of_removed_vertices());
    for (Mesh::Vertex_index v : mesh.vertices()) {
      const Point& p = mesh.point(v);
      index[v] = static_cast<std::uint32_t>(out.vertices.size());
      out.vertices.push_back({CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())});
    }
    for (Mesh::Face_index f : mesh.faces()) {
      std::vector<std::uint32_t> corners;
      for (Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) corners.push_back(index[v]);
      for (std::size_t k = 1; k + 1 < corners.size(); ++k) out.add_triangle(corners[0], corners[k], corners[k + 1]);
    }
    const std::string name = std::filesystem::path(path).stem().string() + ".cgal." + out_ext;
    frep::write_mesh((std::filesystem::path(out_dir) / name).string(), out);
    end(kWrite);
  } catch (const std::exception& e) {
    set_text(r.message, sizeof r.message, std::string("writing the result: ") + e.what());
  }
}

std::string fmt_seconds(double s) {
  if (s < 0) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", s);
  return buf;
}

std::string fmt_flag(int v) { return v < 0 ? "-" : v ? "yes" : "no"; }

int usage(const char* argv0) {
  std::fprintf(stderr,
               "usage: %s [--time-limit S (120)] [--memory-limit MB (8192, 0: none)] [--no-extras] "
               "[--no-header] [-o DIR (write NAME.cgal.obj) [--stl (NAME.cgal.stl)]] MESH...\n",
               argv0);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  unsigned time_limit = 120;
  long memory_limit_mb = 8192;
  bool header = true;
  bool extras = true;
  std::string out_dir;
  std::string out_ext = "obj";
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--time-limit" && i + 1 < argc)
      time_limit = static_cast<unsigned>(std::strtoul(argv[++i], nullptr, 10));
    else if (a == "--memory-limit" && i + 1 < argc)
      memory_limit_mb = std::strtol(argv[++i], nullptr, 10);
    else if (a == "--no-extras")
      extras = false;
    else if (a == "--stl")
      out_ext = "stl";
    else if (a == "--no-header")
      header = false;
    else if (a == "-o" && i + 1 < argc)
      out_dir = argv[++i];
    else if (a == "-h" || a == "--help" || (!a.empty() && a[0] == '-'))
      return usage(argv[0]);
    else
      files.push_back(a);
  }
  if (files.empty()) return usage(argv[0]);
  CGAL::set_error_behaviour(CGAL::THROW_EXCEPTION);
  CGAL::set_warning_behaviour(CGAL::CONTINUE);

  auto* r = static_cast<Report*>(
      mmap(nullptr, sizeof(Report), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0));
  if (r == MAP_FAILED) {
    std::perror("mmap");
    return 1;
  }
  if (header) {
    std::printf("file\ttriangles\toutcome");
    for (int s = 0; s < kStages - 1; ++s) std::printf("\t%s_s", kStageNames[s]);
    std::printf("\tcgal_s\ttotal_s\ts_per_1k_tri\tsoup_polygons\torient_ok\tdegenerate_removed\tclosed_in"
                "\tout_triangles\tclosed_out\tself_intersecting\tpeak_MB\tmessage\n");
  }
  std::fflush(stdout);
  int failures = 0;
  for (const std::string& path : files) {
    new (r) Report{};
    for (double& s : r->seconds) s = -1;
    std::fflush(stdout);
    std::fflush(stderr);
    const double t_start = now();
    const pid_t pid = fork();
    if (pid < 0) {
      std::perror("fork");
      return 1;
    }
    if (pid == 0) {
      if (memory_limit_mb > 0) {
        const rlimit lim{static_cast<rlim_t>(memory_limit_mb) << 20, static_cast<rlim_t>(memory_limit_mb) << 20};
        setrlimit(RLIMIT_AS, &lim);
      }
      if (time_limit > 0) alarm(time_limit);
      r->child_start = now();
      try {
        run_one(path, out_dir, out_ext, extras, *r);
        r->child_seconds = now() - r->child_start;
      } catch (const CGAL::Failure_exception& e) {
        set_text(r->outcome, sizeof r->outcome, "exception");
        set_text(r->message, sizeof r->message,
                 std::string("in ") + kStageNames[r->stage] + ": " + e.what());
      } catch (const std::exception& e) {
        set_text(r->outcome, sizeof r->outcome, "exception");
        set_text(r->message, sizeof r->message, std::string("in ") + kStageNames[r->stage] + ": " + e.what());
      } catch (...) {
        set_text(r->outcome, sizeof r->outcome, "exception");
        set_text(r->message, sizeof r->message, std::string("in ") + kStageNames[r->stage] + ": unknown exception");
      }
      if (r->child_seconds < 0) {  // the stage that threw: its time until then
        r->seconds[r->stage] = now() - r->stage_start;
        r->child_seconds = now() - r->child_start;
      }
      std::fflush(stdout);
      _exit(0);
    }
    int status = 0;
    rusage ru{};
    wait4(pid, &status, 0, &ru);
    const double wall = now() - t_start;
    const int stage = r->stage;
    const bool finished = r->child_seconds >= 0;
    if (!finished && stage >= 0) r->seconds[stage] = now() - r->stage_start;  // until the limit or crash
    const std::string in_stage = stage >= 0 ? kStageNames[stage] : "startup";
    if (WIFSIGNALED(status) && WTERMSIG(status) == SIGALRM) {
      set_text(r->outcome, sizeof r->outcome, "timeout");
      set_text(r->message, sizeof r->message,
               "in " + in_stage + " after the " + std::to_string(time_limit) + " s limit");
    } else if (WIFSIGNALED(status)) {
      set_text(r->outcome, sizeof r->outcome, "crashed");
      set_text(r->message, sizeof r->message,
               "in " + in_stage + ": signal " + std::to_string(WTERMSIG(status)) + " (" +
                   strsignal(WTERMSIG(status)) + ")" +
                   (memory_limit_mb > 0 ? ", memory limit " + std::to_string(memory_limit_mb) + " MB" : ""));
    } else if (r->outcome[0] == '\0') {
      set_text(r->outcome, sizeof r->outcome, "crashed");
      set_text(r->message, sizeof r->message, "in " + in_stage + ": exit status " + std::to_string(WEXITSTATUS(status)));
    }
    if (std::strcmp(r->outcome, "ok") != 0) ++failures;
    double cgal = 0;
    bool any = false;
    for (int s = kRepairSoup; s <= kOrientVolume; ++s)
      if (r->seconds[s] >= 0) cgal += r->seconds[s], any = true;
    const double total = finished ? r->child_seconds : wall;
    std::printf("%s\t%ld\t%s", path.c_str(), r->triangles, r->outcome);
    for (int s = 0; s < kStages - 1; ++s) std::printf("\t%s", fmt_seconds(r->seconds[s]).c_str());
    std::printf("\t%s\t%s", any ? fmt_seconds(cgal).c_str() : "-", fmt_seconds(total).c_str());
    if (any && r->triangles > 0 && finished)
      std::printf("\t%.4f", cgal / (static_cast<double>(r->triangles) / 1000.0));
    else
      std::printf("\t-");
    std::printf("\t%ld\t%s\t%ld\t%s\t%ld\t%s\t%s\t%.0f\t%s\n", r->soup_polygons, fmt_flag(r->orient_ok).c_str(),
                r->degenerate_removed, fmt_flag(r->closed_in).c_str(), r->out_triangles, fmt_flag(r->closed_out).c_str(),
                fmt_flag(r->self_intersecting).c_str(), static_cast<double>(ru.ru_maxrss) / 1024.0,
                r->message[0] ? r->message : "-");
    std::fflush(stdout);
  }
  munmap(r, sizeof(Report));
  return failures == 0 ? 0 : 3;
}
