#include "frep/util/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "frep/error.hpp"
#include "util/interrupt_cleanup.hpp"

namespace frep {

namespace {

// The temporary file being written, for the signal handler (one write at a time per process;
// the handler reads it without locks, as async-signal-safe code must).
char g_temporary[4096];
std::atomic<bool> g_writing{false};

// A child's scratch directory and process group (set_signal_cleanup).
char g_scratch[4096];
std::atomic<bool> g_has_scratch{false};
std::atomic<int> g_child_group{0};

// Whether the program asked for the handlers (install_interrupt_cleanup).
std::atomic<bool> g_installed{false};

// Removes the files of a directory with system calls only (async-signal-safe: no allocation, no
// locks). Removing while reading may skip entries on some file systems: callers read again.
void remove_flat_directory(const char* dir) {
  const int fd = ::open(dir, O_RDONLY | O_DIRECTORY);
  if (fd >= 0) {
    alignas(8) char buf[4096];
    for (long n; (n = ::syscall(SYS_getdents64, fd, buf, sizeof buf)) > 0;)
      for (long off = 0; off < n;) {
        // struct linux_dirent64: d_ino (8), d_off (8), d_reclen (2), d_type (1), d_name.
        unsigned short reclen;
        std::memcpy(&reclen, buf + off + 16, sizeof reclen);
        const char* name = buf + off + 19;
        if (!(name[0] == '.' && (name[1] == 0 || (name[1] == '.' && name[2] == 0)))) ::unlinkat(fd, name, 0);
        off += reclen;
      }
    ::close(fd);
  }
}

void remove_and_die(int sig) {
  if (g_writing.load()) ::unlink(g_temporary);
  if (const int group = g_child_group.load(); group > 0) {
    ::kill(-group, SIGKILL);
    ::waitpid(group, nullptr, 0);  // dead before its directory goes: it writes no more files there
  }
  if (g_has_scratch.load())
    for (int pass = 0; pass < 3 && ::rmdir(g_scratch) != 0; ++pass) remove_flat_directory(g_scratch);
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

// What `path` names once symbolic links are followed (a dangling link names its target), so that
// writing through a link replaces the file it points to and keeps the link.
std::filesystem::path resolve_links(const std::string& path) {
  namespace fs = std::filesystem;
  fs::path p = path;
  std::error_code ec;
  for (int hops = 0; hops < 40 && fs::is_symlink(p, ec); ++hops) {
    const fs::path to = fs::read_symlink(p, ec);
    if (ec) break;
    p = to.is_absolute() ? to : p.parent_path() / to;
  }
  return p;
}

}  // namespace

void install_interrupt_cleanup() {
  g_installed = true;  // first: a fork that sees it holds the signals back, needed or not
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) {
    // A signal ignored from the start (nohup, a shell's background job) stays ignored.
    struct sigaction old {};
    if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
    std::signal(sig, remove_and_die);
  }
}

bool interrupt_cleanup_installed() { return g_installed.load(); }

void set_signal_cleanup(const std::string& scratch_dir, int child_group) {
  g_has_scratch = false;
  if (!scratch_dir.empty() && scratch_dir.size() < sizeof g_scratch) {
    std::memcpy(g_scratch, scratch_dir.c_str(), scratch_dir.size() + 1);
    g_has_scratch = true;
  }
  g_child_group = child_group;
}

bool is_device(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISCHR(st.st_mode);
}

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& produce) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw InputError(path, 0, "cannot write: it is a directory");
  const fs::path target = resolve_links(path);
  const fs::file_status st = fs::status(target, ec);
  if (fs::exists(st) && !fs::is_regular_file(st)) {
    // A device, pipe or socket (/dev/null, /dev/stdout): written in place, since renaming a file
    // over it would replace it (for everyone, when it is /dev/null and we are root).
    std::ofstream out(target, std::ios::binary);
    if (!out) throw InputError(path, 0, std::string("cannot open for writing: ") + std::strerror(errno));
    produce(out);
    out.flush();
    if (!out) throw InputError(path, 0, "write failed");
    return;
  }
  std::random_device rd;
  // Beside the target (a rename within one file system), named after it; a long name is cut so
  // that the temporary one still fits a file name (255 bytes on Linux file systems).
  const std::string suffix = ".tmp" + std::to_string(::getpid()) + "." + std::to_string(rd() % 1000000);
  std::string base = target.filename().string();
  if (base.size() + suffix.size() > 255) base.resize(255 - suffix.size());
  const std::string tmp = (target.parent_path() / (base + suffix)).string();
  // Registered for the signal handler while it exists (unless another write already is).
  struct Tracked {
    bool on;
    explicit Tracked(const std::string& t) : on(t.size() < sizeof g_temporary && !g_writing.load()) {
      if (!on) return;
      std::memcpy(g_temporary, t.c_str(), t.size() + 1);
      g_writing.store(true);
    }
    ~Tracked() {
      if (on) g_writing.store(false);
    }
  } tracked(tmp);
  try {
    {
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      if (!out) throw InputError(path, 0, std::string("cannot open for writing: ") + std::strerror(errno));
      produce(out);
      out.flush();
      if (!out) throw InputError(path, 0, "write failed (disk full?)");
    }
    // A file that is replaced keeps its permissions.
    if (fs::exists(st)) fs::permissions(tmp, st.permissions(), ec);
    int fd = ::open(tmp.c_str(), O_RDONLY);
    if (fd >= 0) {
      ::fsync(fd);
      ::close(fd);
    }
    if (std::rename(tmp.c_str(), target.c_str()) != 0)
      throw InputError(path, 0, std::string("cannot rename temporary file: ") + std::strerror(errno));
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
}

void write_file_atomically(const std::string& path, std::string_view bytes) {
  write_file_atomically(path, [&](std::ostream& out) { out.write(bytes.data(), static_cast<std::streamsize>(bytes.size())); });
}

std::string read_file(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw InputError(path, 0, "is a directory, not a file");
  // Devices such as /dev/zero never end: only regular files are read whole.
  if (fs::exists(path, ec) && !fs::is_regular_file(path, ec)) throw InputError(path, 0, "is not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, std::string("cannot open: ") + std::strerror(errno));
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError(path, 0, "read error");
  return std::move(ss).str();
}

void check_output_directory(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty() && !std::filesystem::is_directory(parent, ec))
    throw InputError(path, 0, "cannot write: directory " + parent.string() + " does not exist");
  if (::access(parent.empty() ? "." : parent.c_str(), W_OK) != 0)
    throw InputError(path, 0, "cannot write: directory " + (parent.empty() ? std::string(".") : parent.string()) +
                                  " is not writable");
}

}  // namespace frep
