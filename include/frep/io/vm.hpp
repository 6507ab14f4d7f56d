// Fidget's `.vm` text format: one `<id> <opcode> [args]` per line, `#` comments, blank lines
// allowed, any token as an id, the last line is the root.
#pragma once

#include <ostream>
#include <string>
#include <string_view>

#include "frep/expr/model.hpp"

namespace frep {

// Parses `.vm` text. `name` appears in error messages (InputError with the line number) for
// unknown opcodes, wrong argument counts, undefined or duplicate ids, bad numbers, cycles and
// empty input. Lines may appear in any order as long as there is no cycle.
Model parse_vm(std::string_view text, const std::string& name = "");
Model read_vm(const std::string& path);

// Writes the part of `g` reachable from `root` as `.vm`, root last. Only Fidget's opcodes are
// used: `recip x` is written as `div 1 x`, which Fidget's reader understands. `info` (what else is known of the field) goes into leading `frep:` comments.
void write_vm(std::ostream& out, const Graph& g, NodeId root, const FieldInfo& info = {});
// Writes atomically to `path`.
void save_vm(const std::string& path, const Graph& g, NodeId root, const FieldInfo& info = {});

}  // namespace frep
