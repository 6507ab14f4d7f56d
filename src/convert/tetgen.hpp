// Tetrahedralization by the separate TetGen program (AGPL: run as a child process, never linked),
// private to the converter. TetGen crashes on some inputs; every failure becomes an InputError.
//
// The process model (what a program that calls convert_mesh with SignMode::Tetrahedra gets):
// - Files. A scratch directory frep-tetgen-<6 random characters> (mkdtemp) is made under $TMPDIR
//   (else /tmp) with the surface as in.smesh; TetGen writes in.1.node and in.1.ele there, and
//   its stdout and stderr go to tetgen.log there (no pipes, so nothing can fill up and stall;
//   the log's tail is quoted in error messages). The directory is removed when tetrahedralize
//   returns or throws.
// - Starting. The calling thread fork()s; the child, using only async-signal-safe calls (the
//   program may have other threads), puts itself in a process group of its own, asks for SIGKILL
//   when its parent dies (PR_SET_PDEATHSIG: a program killed outright takes TetGen with it), takes
//   back the caller's signal mask, changes to the scratch directory, redirects stdout and stderr
//   and execvp()s the program (looked up in PATH if it has no slash; a relative path with a slash
//   is made absolute first). Exit 125: the parent was already gone; 126: no scratch directory;
//   127: the program could not be run (reported as not found). Stdin, the environment and every descriptor the program has not
//   marked close-on-exec are inherited, as with any fork and exec. Signal handlers are reset by
//   the exec; signals the program ignores stay ignored in TetGen.
// - Signals. The library installs no handler and, unless the program has called
//   install_interrupt_cleanup() (frep/util/atomic_file.hpp), blocks nothing. If it has, the
//   calling thread holds SIGINT, SIGTERM, SIGHUP and SIGQUIT back from just before the fork until
//   the child's group and scratch directory are registered with those handlers (a few system
//   calls), so that a Ctrl-C at any moment kills the group, reaps it and removes the directory.
//   That registration has one slot per process: with conversions running in several threads at
//   once, only the latest is cleaned up on a signal. Without the handlers, a program killed by a
//   signal leaves the scratch directory behind (TetGen itself still dies, by PDEATHSIG). Being in
//   its own group, TetGen does not receive the terminal's Ctrl-C directly.
// - Waiting, timeout, reaping. The calling thread polls waitpid(pid, WNOHANG), sleeping 2 ms
//   growing to 50 ms between polls (EINTR is retried). At the deadline the whole group (TetGen and
//   anything it started, e.g. a wrapper script's children) is sent SIGKILL and the child is
//   reaped. Only that pid is ever waited for, never waitpid(-1), so the program's other children
//   are untouched; but a program that sets SIGCHLD to SIG_IGN or reaps every child itself takes
//   TetGen's status away, and the conversion then fails ("lost TetGen").
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "frep/mesh/mesh.hpp"

namespace frep::convert_detail {

struct Tetrahedralization {
  std::vector<Vec3> points;                        // the mesh's vertices first, then TetGen's interior points
  std::vector<std::array<std::uint32_t, 4>> tets;  // oriented: d lies on the right-hand normal side of abc
};

// Runs `tetgen -pYQ` on the welded closed mesh (its surface preserved, no points added on it)
// with a time limit, and checks that the tetrahedra's boundary is exactly the mesh's triangles.
Tetrahedralization tetrahedralize(const TriMesh& welded, const std::string& program, double timeout_seconds);

}  // namespace frep::convert_detail
