// The input of every command that works on a field: an expression file, or a mesh converted on
// the way in (with a line on stderr saying so, since a big mesh takes a moment).
#pragma once

#include <CLI/CLI.hpp>
#include <initializer_list>
#include <string>

#include "frep/mesh/mesh_io.hpp"

#include "frep/convert/convert.hpp"
#include "frep/expr/model.hpp"
#include "frep/contour/mesh_options.hpp"
#include "frep/mesh/mesh.hpp"
#include "frep/util/atomic_file.hpp"

namespace frep::cli {

// An expression file, or a mesh converted on the fly (saying so on stderr unless `quiet`; reading
// warnings are printed either way). `stats`, when given, receives the conversion's figures
// (triangles = 0 for an expression file).
// With `repair`, a mesh that is not a valid solid is repaired first (make_solid), saying so on stderr.
Model load_input(const std::string& path, bool quiet = false, ConvertStats* stats = nullptr, bool repair = false);

// --repair: the commands that read meshes repair broken ones first instead of refusing them.
void add_repair_option(CLI::App* cmd, bool& value);
// Adds --units (3MF output's length unit, default mm), checked against length_unit_from_name.
void add_units_option(CLI::App* cmd, std::string& value);
// Writes a mesh output with the --units given. A .3mf keeps six decimals of each coordinate: the
// mesh as stored is checked first, and refused (InputError naming the file) if the rounding broke
// a valid solid, with the advice to write in smaller units.
void write_mesh_output(const std::string& path, const TriMesh& mesh, const std::string& units);
// `mesh`, repaired if `repair` (saying so on stderr unless quiet): for commands that read meshes themselves.
// `summary`, when given, receives what the repair did (repair_summary) if it ran.
TriMesh repaired_if_asked(TriMesh mesh, bool repair, bool quiet, std::string* summary = nullptr);

// The box of a --bounds x0,y0,z0,x1,y1,z1 option (six values, as CLI11 checked); throws
// CLI::ValidationError unless they are finite and x0 < x1, y0 < y1, z0 < z1.
Box3 bounds_option(const std::vector<double>& values);

// --lipschitz L: lets a command that subdivides space (render, mesh, offset, shell) assume
// |f(p) - f(q)| <= L |p - q| (see FieldInfo::lipschitz). `value` stays negative unless given.
void add_lipschitz_option(CLI::App* cmd, double& value);

// --max-error: `flat` (the default) merges flat regions only (MeshOptions::merge_flat: the surface
// keeps its points, for at most half the meshing's time again); E (model units) or Nc (N cells)
// simplifies within that bound (MeshOptions::max_error; several times the meshing's time, so
// asked for); 0 keeps the uniform mesh of the grid. `apply_max_error` puts a checked value in the
// options.
inline constexpr const char* kDefaultMaxError = "flat";
void add_max_error_option(CLI::App* cmd, std::string& value);
void apply_max_error(const std::string& value, MeshOptions& o);
// The bound to use: the option's value if given, else the model's own (1 for a converted mesh or
// a file frep convert wrote; 0, unknown, for other files).
inline double lipschitz_of(const Model& m, double option) { return option >= 0 ? option : m.info.lipschitz; }

// A warning on stderr when dual contouring could not untangle some vertices (MeshStats::unresolved):
// the mesh is still closed and manifold, but its triangles cross there.
void warn_unresolved(std::size_t unresolved);

// A note on stderr (unless quiet) when `m` does not say it is a distance field (FieldInfo
// lipschitz 1): offsets and shells are at the given distance only on signed distances.
void note_if_not_a_distance(const char* command, const std::string& input, const Model& m, bool quiet);

// The mesher's notes on stdout (unless quiet): a grid shifted because corners were exactly on
// the surface, or because vertices could not be untangled.
void print_mesh_notes(const MeshStats& st);

// Prints what a mesh reader tolerated (TriMesh::warnings) as "frep: warning: PATH: ..." lines.
void print_read_warnings(const std::string& path, const std::vector<std::string>& warnings);

// Before any work: `output` can be written (its directory exists and is writable) and is not one of
// the input files (writing it would replace the input). Throws InputError naming the output.
// Commands that choose the output format from the extension accept a device instead (is_device,
// frep/util/atomic_file.hpp: /dev/null) and write their default format to it in place: render PNG,
// mesh / offset / shell / repair binary STL, convert .frep, sample .npy.
void check_output(const std::string& output, std::initializer_list<std::string> inputs);

// read_mesh, then print_read_warnings: how commands read the meshes they are given.
TriMesh read_mesh_noting(const std::string& path);

// Help text for such an input argument.
inline constexpr const char* kFieldInputHelp =
    "Expression (.vm, .rhai, .frep) or closed mesh (.stl, .obj, .ply, .off; converted first, as by frep convert)";

}  // namespace frep::cli
