// frep's own binary expression format (.frep): compact and fast to load, versioned, and
// checksummed so that a truncated or corrupted file is a clear error rather than a wrong field.
//
// Layout (little-endian):
//   8 bytes  magic "FREPexpr"
//   u32      format version (3 when the file holds oracles, else 2; versions 1 and 2 read too)
//   u32      flags: bits 0-1 FieldInfo::growth (0 unknown, 1 box, 2 distance), others 0
//   u64      node count n (nodes in topological order: arguments before their users)
//   u64      root: index of the expression's value among the nodes
//   f64      the field's Lipschitz bound (FieldInfo::lipschitz; 0: unknown)          [version 2]
//   6 f64    the box holding its inside, x0 y0 z0 x1 y1 z1 (FieldInfo::bounds; all NaN: unknown)
//   [version 3] u32 oracle count k, then k records, each a u64 byte length and the bytes the
//            codec that wrote them reads back (a mesh: its triangles and its closed form)
//   n nodes  u8 opcode id (the frozen ids of frep/expr/opcode.hpp); then for `const` a f32
//            value; for each argument, a LEB128 varint: this node's index minus the argument's;
//            for an oracle (id 32, version 3), a varint: its index among the records
//   u32      CRC-32 (ISO-HDLC, as zlib) of every byte before it
// Files without oracles hold only Fidget's opcodes and convert losslessly to .vm and back.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "frep/expr/model.hpp"

namespace frep {

inline constexpr std::string_view kFrepMagic = "FREPexpr";

// True if the bytes start like a .frep file.
bool is_frep_file(std::string_view bytes);

// How oracles are kept in .frep files: each as a record its owner writes and reads back (mesh
// oracles: frep/convert/mesh_oracle.hpp). Without a codec, or for an oracle it cannot encode,
// files hold the closed form of the whole expression (Oracle::closed_form) instead.
struct FrepOracleCodec {
  // The record of an oracle, or nullopt if this codec cannot keep it.
  std::function<std::optional<std::string>(const Oracle&)> encode;
  // The oracle a record stands for; `file` names the file for errors. Throws InputError for a
  // bad record.
  std::function<std::shared_ptr<const Oracle>(std::string_view record, const std::string& file)> decode;
};

// The part of `g` reachable from `root`, serialized, with what else is known of the field.
std::string serialize_frep(const Graph& g, NodeId root, const FieldInfo& info = {}, const FrepOracleCodec* codec = nullptr);
// Writes atomically.
void save_frep(const std::string& path, const Graph& g, NodeId root, const FieldInfo& info = {},
               const FrepOracleCodec* codec = nullptr);

// Parses .frep bytes; throws InputError naming `name` and the byte offset for a wrong magic, an
// unsupported version, a truncated file, a checksum mismatch or an invalid node, and for a file
// holding oracles when no codec is given.
Model parse_frep(std::string_view bytes, const std::string& name = "", const FrepOracleCodec* codec = nullptr);
Model read_frep(const std::string& path, const FrepOracleCodec* codec = nullptr);

}  // namespace frep
