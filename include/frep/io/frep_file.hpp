// frep's own binary expression format (.frep): compact and fast to load, versioned, and
// checksummed so that a truncated or corrupted file is a clear error rather than a wrong field.
//
// Layout (little-endian):
//   8 bytes  magic "FREPexpr"
//   u32      format version (2; version 1 files, without the field information below, read too)
//   u32      flags (0)
//   u64      node count n (nodes in topological order: arguments before their users)
//   u64      root: index of the expression's value among the nodes
//   f64      the field's Lipschitz bound (FieldInfo::lipschitz; 0: unknown)          [version 2]
//   6 f64    the box holding its inside, x0 y0 z0 x1 y1 z1 (FieldInfo::bounds; all NaN: unknown)
//   n nodes  u8 opcode id (the frozen ids of frep/expr/opcode.hpp); then for `const` a f32
//            value; for each argument, a LEB128 varint: this node's index minus the argument's
//   u32      CRC-32 (ISO-HDLC, as zlib) of every byte before it
// Only Fidget's opcodes appear (the graph has no others), so a .frep file converts losslessly to
// .vm and back.
#pragma once

#include <string>
#include <string_view>

#include "frep/expr/model.hpp"

namespace frep {

inline constexpr std::string_view kFrepMagic = "FREPexpr";

// True if the bytes start like a .frep file.
bool is_frep_file(std::string_view bytes);

// The part of `g` reachable from `root`, serialized, with what else is known of the field.
std::string serialize_frep(const Graph& g, NodeId root, const FieldInfo& info = {});
// Writes atomically.
void save_frep(const std::string& path, const Graph& g, NodeId root, const FieldInfo& info = {});

// Parses .frep bytes; throws InputError naming `name` and the byte offset for a wrong magic, an
// unsupported version, a truncated file, a checksum mismatch or an invalid node.
Model parse_frep(std::string_view bytes, const std::string& name = "");
Model read_frep(const std::string& path);

}  // namespace frep
