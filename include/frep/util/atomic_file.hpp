// Writes output files atomically: a temporary file beside the target, then rename, so a failure
// never leaves a half-written file under the requested name.
#pragma once

#include <functional>
#include <ostream>
#include <string>
#include <string_view>

namespace frep {

// Calls `produce` with a stream to the temporary file, flushes, fsyncs and renames it to `path`.
// Throws InputError naming `path` if it cannot be written; the temporary file is removed. A
// symbolic link is followed (the file it names is replaced, the link stays); a device, pipe or
// socket (/dev/null) is written in place. A replaced file keeps its permissions.
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& produce);
void write_file_atomically(const std::string& path, std::string_view bytes);

// Makes SIGINT, SIGTERM and SIGHUP remove the temporary file being written before the process
// dies as the signal would (for programs: an interrupted conversion leaves no 150 MB leftover),
// and what set_signal_cleanup registered.
void remove_temporary_files_on_signals();

// Registers a scratch directory (its files, not subdirectories, are removed, then it) and a child
// process group (killed) for the signal handler above; one of each at a time. An empty path or
// a group of 0 clears them.
void set_signal_cleanup(const std::string& scratch_dir, int child_group);

// Checks, before long work, that `path` could be written: its directory exists and is writable.
// Throws InputError naming `path` otherwise.
void check_output_directory(const std::string& path);

// Reads a whole file; throws InputError naming it if it cannot be read.
std::string read_file(const std::string& path);

}  // namespace frep
