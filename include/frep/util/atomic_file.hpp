// Writes output files atomically: a temporary file beside the target, then rename, so a failure
// never leaves a half-written file under the requested name. Also reads whole files.
//
// The library has no process-wide side effects of its own: it installs no signal handler and
// blocks no signal. A program that wants an interrupted run (Ctrl-C) to leave no temporary file,
// scratch directory or child process behind asks for it with install_interrupt_cleanup(), as the
// frep command does.
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

// True when `path` names an existing character device (stat follows links: /dev/null, or
// /dev/stdout on a terminal). Writers that choose a format from the extension use a default format
// there instead of refusing the name (save_image: PNG, write_mesh: binary STL, save_expression:
// .frep), and the file is written in place.
bool is_device(const std::string& path);

// Opt-in, for programs (never called by the library itself): installs handlers for SIGINT,
// SIGTERM, SIGHUP and SIGQUIT that remove the temporary file being written (so an interrupted
// conversion leaves no 150 MB leftover), kill the TetGen child process group and remove its
// scratch directory if a conversion is running one, then restore the default action and raise
// the signal again, so that the process dies as the signal would have made it. A signal that is
// ignored when this is called (nohup, a shell's background job) stays ignored. The handlers
// replace any the program had for these signals; call it once, early in main. Until it is
// called, the TetGen runner also blocks no signals around its fork (frep/convert/convert.hpp).
void install_interrupt_cleanup();

// Checks, before long work, that `path` could be written: its directory exists and is writable.
// Throws InputError naming `path` otherwise.
void check_output_directory(const std::string& path);

// Reads a whole file; throws InputError naming it if it cannot be read.
std::string read_file(const std::string& path);

}  // namespace frep
