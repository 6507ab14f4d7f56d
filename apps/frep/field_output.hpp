// The output of the commands that transform a field (frep offset, frep shell): a mesh of the
// result (dual contouring over a known region) or the result's expression, by the file name.
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "frep/convert/convert.hpp"
#include "frep/eval/tape.hpp"
#include "frep/model/field.hpp"
#include "frep/expr/graph.hpp"
#include "frep/math/vec.hpp"
#include "input.hpp"

namespace frep::cli {

struct FieldOutputOptions {
  int resolution = 128;        // cells across the longest side of the region
  std::vector<double> bounds;  // x0,y0,z0,x1,y1,z1 given on the command line, or empty
  int threads = 0;
  bool quiet = false;
  bool repair = false;  // --repair: repair a broken input mesh first
  double lipschitz = -1;       // --lipschitz, or < 0 if not given; commands resolve it with lipschitz_of
  std::string units = "mm";    // --units: a .3mf output's length unit
  std::string max_error = kDefaultMaxError;  // --max-error: flat, a bound (model units, or Nc cells), or 0
};

// Adds --resolution, --bounds, --threads, --quiet, --repair, --lipschitz, --units and --max-error, stored in `o` (which must outlive parsing).
void add_field_output_options(CLI::App* cmd, const std::shared_ptr<FieldOutputOptions>& o);
// Checks what CLI11 cannot (finite, non-empty bounds); throws CLI::ValidationError.
void check_field_output_options(const FieldOutputOptions& o);

// Help text for the -o option.
inline constexpr const char* kFieldOutputHelp =
    "Output: a mesh (.stl, .obj, .ply, .3mf; meshed by dual contouring, closed and manifold) or the expression "
    "(.vm, .rhai, .frep); written atomically";

// True for a mesh file name (.stl, .obj, .ply); otherwise the output is the expression.
bool is_mesh_output(const std::string& path);

// Fails (InputError naming the file) before any long work if the name has no supported
// extension, its directory cannot be written, or it is the input (check_output).
void check_field_output(const std::string& path, const std::string& input);

// A box holding the input's inside: `bounds` if given, else the one the input carries
// (FieldInfo::bounds: a mesh's bounding box), else found by interval search of the tape.
// InputError naming `input` if the field is unbounded or empty.
Box3 input_region(const std::string& input, const FieldInfo& info, const Tape& tape, const FieldOutputOptions& o);

// The facts of an operation's result: its own (the Field rules), or, where those leave the box
// unknown but the input had one, the input's box grown by `reach` if interval arithmetic proves
// the result positive around it (checked_bounds). `tape` is compiled for that check, or for a
// mesh output, and only then.
FieldInfo output_facts(const Field& result, const Model& input, double reach, bool mesh_out, std::optional<Tape>& tape);

// Writes the field `root` of `g` to `path`: as an expression, or meshed by dual contouring with
// `region` as the known box of its inside (one extra cell on every side), or over the given
// --bounds exactly (cut and capped there). InputError naming `input` when the result is empty.
// Expressions keep `info` (what is known of the result).
// `tape`, when given, is root's compiled tape (not compiled again).
void write_field_output(const std::string& input, const std::string& path, const Graph& g, NodeId root,
                        const Box3& region, const FieldOutputOptions& o, const FieldInfo& info,
                        const Tape* tape = nullptr);

}  // namespace frep::cli
