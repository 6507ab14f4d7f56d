// frep dataset: signed-distance training data for a folder of meshes, on local worker processes or
// a Dask cluster. The scheduling is Dask's, in the Python module frep.dataset: this command checks
// its options, finds a Python with Dask and that module, and runs `python -m frep.dataset`, with
// FREP_CLI naming this very program so that the workers run the same frep.
#include <fcntl.h>
#include <fmt/core.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"

extern char** environ;

namespace frep::cli {
namespace {

namespace fs = std::filesystem;

// Runs argv (PATH searched) and waits: its exit code, 128 + N if killed by signal N, -1 if it
// could not start. Output passes through.
int run_child(const std::vector<std::string>& argv, bool quiet_output = false) {
  std::vector<char*> args;
  for (const std::string& s : argv) args.push_back(const_cast<char*>(s.c_str()));
  args.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  if (quiet_output) {
    posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
  }
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, args[0], &fa, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) return -1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// The first Python that can import dask.distributed: $FREP_PYTHON, the one the build was configured
// with, the system's, then python3 on PATH (which may be a separate install without Dask).
std::optional<std::string> find_python() {
  std::vector<std::string> candidates;
  if (const char* e = std::getenv("FREP_PYTHON"); e && *e) candidates.emplace_back(e);
#ifdef FREP_PYTHON_EXECUTABLE
  candidates.emplace_back(FREP_PYTHON_EXECUTABLE);
#endif
  candidates.emplace_back("/usr/bin/python3");
  candidates.emplace_back("python3");
  for (const std::string& py : candidates) {
    if (py.find('/') != std::string::npos && !fs::exists(py)) continue;
    if (run_child({py, "-c", "import distributed"}, true) == 0) return py;
  }
  return std::nullopt;
}

// The folder holding the package frep/ with dataset.py: $FREP_PYTHONPATH, the build's or the
// install's python folder, else <folder of this program>/python (the build tree's layout).
std::optional<std::string> find_package_dir(const fs::path& self) {
  std::vector<std::string> candidates;
  if (const char* e = std::getenv("FREP_PYTHONPATH"); e && *e) candidates.emplace_back(e);
#ifdef FREP_PYTHON_BUILD_DIR
  candidates.emplace_back(FREP_PYTHON_BUILD_DIR);
#endif
#ifdef FREP_PYTHON_INSTALL_DIR
  candidates.emplace_back(FREP_PYTHON_INSTALL_DIR);
#endif
  if (!self.empty()) candidates.push_back((self.parent_path() / "python").string());
  for (const std::string& dir : candidates) {
    std::error_code ec;
    if (fs::exists(fs::path(dir) / "frep" / "dataset.py", ec)) return dir;
  }
  return std::nullopt;
}

}  // namespace

void register_dataset(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "dataset",
      "Sample every mesh of a folder (or a list file) into DST: grids and points of exact signed distances "
      "(as frep sample writes them) and DST/manifest.jsonl, one JSON line per mesh. Runs on N local worker "
      "processes or a Dask cluster; reruns skip meshes already done. Exit 0 all ok, 1 some failed, 2 usage");
  struct Args {
    std::string src, dst, normalize = "unit-cube", bounds, scheduler;
    int grid = 0, workers = 1;
    std::size_t points = 0, near = 0;
    std::optional<double> sigma, truncate, timeout;
    std::uint64_t seed = 0;
    bool repair = false, retry_failed = false, quiet = false;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("SRC", a->src,
                  "Folder searched recursively for .stl .obj .ply .off, or a text file listing meshes (one path "
                  "per line, relative to its folder; blank lines and # comments skipped)")
      ->required();
  cmd->add_option("-o,--output", a->dst, "Output folder, on a path all workers share")->required();
  auto* grid = cmd->add_option("--grid", a->grid, "Dense N x N x N grid per mesh: grid.npy")->check(CLI::Range(2, 4096));
  cmd->add_option("--points", a->points, "N points uniform in the bounds: points.npy, rows (x, y, z, d)")
      ->check(whole_non_negative());
  auto* near = cmd->add_option("--near-surface", a->near, "N points near the surface: near_surface.npy")
                   ->check(whole_non_negative());
  auto* sigma = cmd->add_option("--sigma", a->sigma, "Deviation of the noise of --near-surface (normalized units)")
                    ->check(finite_non_negative());
  near->needs(sigma);
  sigma->needs(near);
  cmd->add_option("--truncate", a->truncate, "With --grid: distances clamped to [-D, D]")
      ->type_name("D")
      ->check(finite_number(true))
      ->needs(grid);
  cmd->add_option("--normalize", a->normalize,
                  "'unit-cube' (default: the mesh's box centred at the origin, its longest side 1; bounds "
                  "[-0.55,0.55]^3), 'unit-sphere' (the box's centre at the origin, the farthest vertex at distance "
                  "1; bounds [-1.1,1.1]^3) or 'none'; original = normalized / scale + offset (in the manifest)")
      ->check(CLI::IsMember({"unit-cube", "unit-sphere", "none"}));
  cmd->add_option("--bounds", a->bounds, "x0,y0,z0,x1,y1,z1: the sampling box (default: by --normalize)");
  cmd->add_option("--seed", a->seed, "Seed of the points (near-surface points use seed + 1)")
      ->check(whole_non_negative());
  cmd->add_flag("--repair", a->repair, "Repair meshes that are not valid solids first (as frep repair does)");
  cmd->add_option("--timeout", a->timeout, "Stop a mesh after S seconds and record it as failed")
      ->type_name("S")
      ->check(finite_number(true));
  auto* workers =
      cmd->add_option("--workers", a->workers, "Local worker processes, one mesh at a time each (default 1)")
          ->check(CLI::Range(1, 1024));
  cmd->add_option("--scheduler", a->scheduler, "Run on the workers of this Dask scheduler (tcp://HOST:PORT)")
      ->excludes(workers);
  cmd->add_flag("--retry-failed", a->retry_failed, "Retry the meshes that failed in an earlier run");
  cmd->add_flag("--quiet,-q", a->quiet, "No progress bar");
  cmd->callback([a] {
    if (a->grid == 0 && a->points == 0 && a->near == 0)
      throw CLI::ValidationError("frep dataset", "give --grid N, --points N or --near-surface N --sigma S");
    std::error_code ec;
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    const std::optional<std::string> py = find_python();
    if (!py) {
      std::fprintf(stderr,
                   "frep: error: frep dataset needs Python 3 with Dask distributed: install python3-distributed "
                   "(Debian, Ubuntu) or `pip install distributed`, or name a Python that has it in FREP_PYTHON\n");
      std::exit(1);
    }
    const std::optional<std::string> pkg = find_package_dir(self);
    if (!pkg) {
      std::fprintf(stderr,
                   "frep: error: frep dataset needs the frep Python package (frep/dataset.py), which was not found: "
                   "name the folder that holds it in FREP_PYTHONPATH\n");
      std::exit(1);
    }
    std::vector<std::string> argv = {*py, "-m", "frep.dataset", a->src, "-o", a->dst, "--normalize", a->normalize,
                                     "--seed", std::to_string(a->seed)};
    auto add = [&argv](const char* name, const std::string& v) {
      argv.emplace_back(name);
      argv.push_back(v);
    };
    if (a->grid) add("--grid", std::to_string(a->grid));
    if (a->points) add("--points", std::to_string(a->points));
    if (a->near) add("--near-surface", std::to_string(a->near));
    if (a->sigma) add("--sigma", fmt::format("{:.17g}", *a->sigma));
    if (a->truncate) add("--truncate", fmt::format("{:.17g}", *a->truncate));
    if (a->timeout) add("--timeout", fmt::format("{:.17g}", *a->timeout));
    if (!a->bounds.empty()) add("--bounds", a->bounds);
    if (!a->scheduler.empty()) add("--scheduler", a->scheduler);
    else add("--workers", std::to_string(a->workers));
    if (a->repair) argv.emplace_back("--repair");
    if (a->retry_failed) argv.emplace_back("--retry-failed");
    if (a->quiet) argv.emplace_back("--quiet");
    // The module finds its package through PYTHONPATH (the package dir first), and the workers run this frep.
    const char* old = std::getenv("PYTHONPATH");
    const std::string path = *pkg + (old && *old ? std::string(":") + old : std::string());
    ::setenv("PYTHONPATH", path.c_str(), 1);
    if (!self.empty()) ::setenv("FREP_CLI", self.c_str(), 1);
    ::setenv("FREP_DATASET_PROG", "frep dataset", 1);
    const int rc = run_child(argv);
    if (rc < 0) {
      std::fprintf(stderr, "frep: error: could not run %s\n", py->c_str());
      std::exit(1);
    }
    std::fflush(stdout);
    std::exit(rc);
  });
}

}  // namespace frep::cli
