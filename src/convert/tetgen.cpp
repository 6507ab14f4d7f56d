// Runs TetGen in a scratch directory: writes the surface as .smesh (0-based, full precision),
// runs `tetgen -pYQ` as a child process with a deadline, reads .node and .ele back, and checks
// that the faces of the tetrahedra that lie on only one of them are exactly the input triangles.
#include "convert/tetgen.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "frep/error.hpp"
#include "frep/math/predicates.hpp"
#include "frep/util/atomic_file.hpp"
#include "util/interrupt_cleanup.hpp"
#include "frep/util/parse_number.hpp"
#include "frep/util/text_scan.hpp"

namespace frep::convert_detail {
namespace {

namespace fs = std::filesystem;

struct ScratchDir {
  fs::path path;
  ScratchDir() {
    std::string tmpl = (fs::temp_directory_path() / "frep-tetgen-XXXXXX").string();
    if (!::mkdtemp(tmpl.data())) throw InputError("", 0, std::string("cannot create a scratch directory: ") + std::strerror(errno));
    path = tmpl;
    set_signal_cleanup(path.string(), 0);  // Ctrl-C during the conversion removes it too
  }
  ~ScratchDir() {
    set_signal_cleanup("", 0);
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

std::string tail_of(const fs::path& log) {
  std::ifstream in(log);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (text.size() > 600) text = "..." + text.substr(text.size() - 600);
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  return text;
}

// Runs program with args in dir, output to log; returns after it exits or the deadline passes.
void run_tetgen(const std::string& program, const std::vector<std::string>& args, const fs::path& dir,
                const fs::path& log, double timeout, const std::string& mesh_name) {
  // The child runs in the scratch directory: a relative path with a slash (./tetgen, bin/tetgen)
  // is made absolute first; a bare name is looked up in PATH as usual.
  std::error_code ec;
  const std::string exe = program.find('/') != std::string::npos && fs::path(program).is_relative()
                              ? fs::absolute(program, ec).string()
                              : program;
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(exe.c_str()));
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  // With the program's cleanup handlers (install_interrupt_cleanup), the signals they handle wait
  // in this thread until the child's group is registered: a Ctrl-C right after the fork would
  // otherwise leave it running. Without them the set is empty: nothing is blocked.
  sigset_t cleanup_signals, before;
  sigemptyset(&cleanup_signals);
  if (interrupt_cleanup_installed())
    for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) sigaddset(&cleanup_signals, sig);
  ::pthread_sigmask(SIG_BLOCK, &cleanup_signals, &before);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int err = errno;
    ::pthread_sigmask(SIG_SETMASK, &before, nullptr);
    throw InputError(mesh_name, 0, std::string("cannot start TetGen: ") + std::strerror(err));
  }
  if (pid == 0) {
    // Child: own process group (a timeout or a signal then kills whatever it started too), own
    // directory and log; exit 127 if the program cannot be run.
    // Only async-signal-safe calls here: the parent may have other threads.
    ::setpgid(0, 0);
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);  // frep killed outright (SIGKILL, a crash): TetGen goes too
    if (::getppid() != parent) ::_exit(125);  // frep was already gone
    ::pthread_sigmask(SIG_SETMASK, &before, nullptr);
    if (::chdir(dir.c_str()) != 0) ::_exit(126);
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      ::dup2(fd, 1);
      ::dup2(fd, 2);
      ::close(fd);
    }
    ::execvp(exe.c_str(), argv.data());
    ::_exit(127);
  }
  ::setpgid(pid, pid);  // also here: whichever runs first, the group exists before it is used
  set_signal_cleanup(dir.string(), pid);
  ::pthread_sigmask(SIG_SETMASK, &before, nullptr);
  struct Forget {  // the group is gone once waited for
    fs::path dir;
    ~Forget() { set_signal_cleanup(dir.string(), 0); }
  } forget{dir};
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout);
  int status = 0;
  auto sleep = std::chrono::milliseconds(2);
  while (true) {
    const pid_t r = ::waitpid(pid, &status, WNOHANG);
    if (r == pid) break;
    if (r < 0 && errno != EINTR) throw InputError(mesh_name, 0, std::string("lost TetGen: ") + std::strerror(errno));
    if (std::chrono::steady_clock::now() > deadline) {
      ::kill(-pid, SIGKILL);  // TetGen and anything it started (a wrapper script's children)
      ::waitpid(pid, &status, 0);
      char limit[32];
      std::snprintf(limit, sizeof limit, "%g", timeout);
      throw InputError(mesh_name, 0, std::string("TetGen did not finish within ") + limit +
                                         " s (time limit; see --tetgen-timeout)");
    }
    std::this_thread::sleep_for(sleep);
    sleep = std::min(sleep * 2, std::chrono::milliseconds(50));
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 127)
    throw InputError(mesh_name, 0, "the TetGen program '" + program +
                                       "' was not found (install Debian's tetgen package, or use --sign pseudonormal)");
  if (WIFSIGNALED(status))
    throw InputError(mesh_name, 0, "TetGen crashed (signal " + std::to_string(WTERMSIG(status)) + "): " + tail_of(log));
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw InputError(mesh_name, 0, "TetGen failed (exit " + std::to_string(WEXITSTATUS(status)) + "): " + tail_of(log));
}

// Reads the numbers of a TetGen output file (comments after '#').
std::vector<double> numbers(const fs::path& path, const std::string& mesh_name) {
  std::string text;
  try {
    text = read_file(path.string());
  } catch (const InputError&) {
    throw InputError(mesh_name, 0, "TetGen wrote no " + path.filename().string());
  }
  std::vector<double> v;
  detail::LineCursor lines(text);
  std::string_view line;
  while (lines.next(line)) {
    if (const auto h = line.find('#'); h != std::string_view::npos) line = line.substr(0, h);
    detail::TokenSplitter tok(line);
    std::string_view t;
    while (tok.next(t)) {
      double d;
      if (!parse_real(t, d))
        throw InputError(mesh_name, 0, "unreadable TetGen output " + path.filename().string() + " line " +
                                           std::to_string(lines.line_no()));
      v.push_back(d);
    }
  }
  return v;
}

}  // namespace

Tetrahedralization tetrahedralize(const TriMesh& m, const std::string& program, double timeout) {
  const ScratchDir dir;
  {
    std::ofstream out(dir.path / "in.smesh");
    char buf[128];
    out << m.vertices.size() << " 3 0 0\n";
    for (std::size_t i = 0; i < m.vertices.size(); ++i) {
      std::snprintf(buf, sizeof buf, "%zu %.17g %.17g %.17g\n", i, m.vertices[i].x, m.vertices[i].y, m.vertices[i].z);
      out << buf;
    }
    std::size_t usable = 0;
    for (const Triangle& t : m.triangles) usable += t[0] != t[1] && t[1] != t[2] && t[0] != t[2];
    out << usable << " 0\n";
    for (const Triangle& t : m.triangles)
      if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
    out << "0\n0\n";
    if (!out) throw InputError(m.name, 0, "cannot write TetGen's input in " + dir.path.string());
  }
  run_tetgen(program, {"-pYQ", "in.smesh"}, dir.path, dir.path / "tetgen.log", timeout, m.name);

  Tetrahedralization r;
  const std::vector<double> node = numbers(dir.path / "in.1.node", m.name);
  if (node.size() < 4 || node[1] != 3) throw InputError(m.name, 0, "TetGen's .node file is malformed");
  const auto np = static_cast<std::size_t>(node[0]);
  const std::size_t attrs = static_cast<std::size_t>(node[2]), marks = static_cast<std::size_t>(node[3]);
  const std::size_t stride = 4 + attrs + marks;
  if (np < m.vertices.size() || node.size() < 4 + np * stride) throw InputError(m.name, 0, "TetGen's .node file is truncated");
  r.points = m.vertices;  // exact input coordinates (TetGen keeps the input points first, in order)
  for (std::size_t i = m.vertices.size(); i < np; ++i) {
    const double* p = &node[4 + i * stride + 1];
    r.points.push_back({p[0], p[1], p[2]});
  }
  const std::vector<double> ele = numbers(dir.path / "in.1.ele", m.name);
  if (ele.size() < 3 || ele[1] != 4) throw InputError(m.name, 0, "TetGen's .ele file is malformed (expected 4-node tetrahedra)");
  const auto nt = static_cast<std::size_t>(ele[0]);
  const std::size_t estride = 5 + static_cast<std::size_t>(ele[2]);
  if (ele.size() < 3 + nt * estride) throw InputError(m.name, 0, "TetGen's .ele file is truncated");
  r.tets.reserve(nt);
  for (std::size_t i = 0; i < nt; ++i) {
    std::array<std::uint32_t, 4> t;
    for (int k = 0; k < 4; ++k) {
      const double v = ele[3 + i * estride + 1 + static_cast<std::size_t>(k)];
      if (!(v >= 0 && v < static_cast<double>(r.points.size()))) throw InputError(m.name, 0, "TetGen's .ele refers to a missing point");
      t[static_cast<std::size_t>(k)] = static_cast<std::uint32_t>(v);
    }
    // Orient every tetrahedron the same way: d on the positive side of abc.
    if (exact::orient3d(r.points[t[0]], r.points[t[1]], r.points[t[2]], r.points[t[3]]) < 0) std::swap(t[0], t[1]);
    r.tets.push_back(t);
  }

  // The surface must be unchanged: the faces on exactly one tetrahedron are the input triangles.
  using Key = std::array<std::uint32_t, 3>;
  std::vector<Key> faces;
  faces.reserve(4 * r.tets.size());
  for (const auto& t : r.tets)
    for (int k = 0; k < 4; ++k) {
      Key f{t[(k + 1) % 4], t[(k + 2) % 4], t[(k + 3) % 4]};
      std::sort(f.begin(), f.end());
      faces.push_back(f);
    }
  std::sort(faces.begin(), faces.end());
  std::vector<Key> boundary;
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i;
    while (j < faces.size() && faces[j] == faces[i]) ++j;
    if (j - i == 1) boundary.push_back(faces[i]);
    i = j;
  }
  std::vector<Key> input;
  for (const Triangle& t : m.triangles)
    if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) {
      Key f{t[0], t[1], t[2]};
      std::sort(f.begin(), f.end());
      input.push_back(f);
    }
  std::sort(input.begin(), input.end());
  if (boundary != input) {
    std::vector<Key> diff;
    std::set_symmetric_difference(boundary.begin(), boundary.end(), input.begin(), input.end(), std::back_inserter(diff));
    throw InputError(m.name, 0, "TetGen changed the surface: " + std::to_string(diff.size()) +
                                    " boundary faces of its tetrahedra differ from the mesh's triangles");
  }
  return r;
}

}  // namespace frep::convert_detail
