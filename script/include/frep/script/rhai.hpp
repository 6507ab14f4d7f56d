// Rhai scripts as Fidget writes them: `x`, `y` and `z` are symbolic, arithmetic on them builds
// the expression, and the script's last value (or what it passes to `draw`) is the shape.
// The supported subset, the builtins, the limits and the differences from Fidget are in
// docs/rhai.md.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <string_view>

#include "frep/expr/model.hpp"

namespace frep {

struct RhaiOptions {
  // Evaluation steps (one per statement, expression node, loop iteration and call) before the
  // script is stopped as a runaway. 0 = the default, 10^8 plus 16 per byte of script: far above
  // what real models take (straight-line code takes at most about one step per byte), while an
  // endless loop stops within seconds. Fidget's own engine stops at 50,000.
  std::uint64_t max_steps = 0;
  // Most nodes the graph may hold before the script is stopped. 0 = the default, one node per
  // 400 bytes of the machine's memory (60 million on 24 GB): a script whose expression keeps
  // doubling (a remap of itself in a loop) stops with a message instead of exhausting memory.
  std::uint64_t max_nodes = 0;
  // Loads the mesh file a script names in `mesh("part.stl")` (a path relative to the script's
  // folder, or absolute) as an oracle: its exact signed distance. Unset: mesh() is an error.
  // load_field sets it (frep/convert/mesh_oracle.hpp); the same file loads once per script.
  std::function<std::shared_ptr<const Oracle>(const std::string& path)> load_mesh;
};

// Runs a script and returns the shape. `name` appears in error messages: InputError with the
// line, and "column N:" at the start of the message, for syntax errors, type errors, unknown
// names, failed `throw`s, runaway scripts and nesting beyond the documented limits.
Model parse_rhai(std::string_view text, const std::string& name = "", const RhaiOptions& options = {});
Model read_rhai(const std::string& path, const RhaiOptions& options = {});

// Writes the part of `g` reachable from `root` as a script that Fidget evaluates and that
// parse_rhai reads back to a graph evaluating bit for bit the same: only Fidget's functions and
// operators (`recip a` is written `1.0 / a`, `mod` as `%`), constants with %.9g (exact in f32),
// a `let` for every node used more than once and wherever a line would grow too long or too
// deep; the last line is the shape. `info` (what else is known of the field) goes into leading `frep:` comments.
void write_rhai(std::ostream& out, const Graph& g, NodeId root, const FieldInfo& info = {});
// Writes atomically to `path`.
void save_rhai(const std::string& path, const Graph& g, NodeId root, const FieldInfo& info = {});

}  // namespace frep
