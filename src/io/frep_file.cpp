// The .frep binary format (see frep/io/frep_file.hpp for the layout).
#include "frep/io/frep_file.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <cstdint>
#include <cstring>

#include "frep/error.hpp"
#include "frep/expr/copy.hpp"
#include "frep/util/atomic_file.hpp"

namespace frep {
namespace {

constexpr std::uint32_t kVersion = 2;          // what files without oracles are written as
constexpr std::uint32_t kOracleVersion = 3;    // files holding oracle records
constexpr std::size_t kHeaderV1 = 8 + 4 + 4 + 8 + 8;
constexpr std::size_t kHeader = kHeaderV1 + 7 * 8;  // + Lipschitz bound and box

// CRC-32 (reflected polynomial 0xEDB88320, as zlib's crc32), four table lookups per word.
const std::array<std::array<std::uint32_t, 256>, 4>& crc_tables() {
  static const auto tables = [] {
    std::array<std::array<std::uint32_t, 256>, 4> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[0][i] = c;
    }
    for (std::uint32_t i = 0; i < 256; ++i)
      for (int s = 1; s < 4; ++s) t[static_cast<std::size_t>(s)][i] = (t[static_cast<std::size_t>(s) - 1][i] >> 8) ^ t[0][t[static_cast<std::size_t>(s) - 1][i] & 0xff];
    return t;
  }();
  return tables;
}

std::uint32_t crc32(std::string_view data) {
  const auto& t = crc_tables();
  std::uint32_t c = 0xFFFFFFFFu;
  const auto* p = reinterpret_cast<const unsigned char*>(data.data());
  std::size_t n = data.size();
  for (; n >= 4; n -= 4, p += 4) {
    c ^= static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 | static_cast<std::uint32_t>(p[2]) << 16 |
         static_cast<std::uint32_t>(p[3]) << 24;
    c = t[3][c & 0xff] ^ t[2][(c >> 8) & 0xff] ^ t[1][(c >> 16) & 0xff] ^ t[0][c >> 24];
  }
  for (; n > 0; --n, ++p) c = t[0][(c ^ *p) & 0xff] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

template <class T>
void put(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));  // x86-64 and every target we build for is little-endian
  out.append(b, sizeof(T));
}
void put_varint(std::string& out, std::uint64_t v) {
  while (v >= 0x80) {
    out.push_back(static_cast<char>((v & 0x7f) | 0x80));
    v >>= 7;
  }
  out.push_back(static_cast<char>(v));
}

template <class T>
T get(std::string_view b, std::size_t at) {
  T v;
  std::memcpy(&v, b.data() + at, sizeof(T));
  return v;
}

}  // namespace

bool is_frep_file(std::string_view bytes) { return bytes.substr(0, kFrepMagic.size()) == kFrepMagic; }

std::string serialize_frep(const Graph& g, NodeId root, const FieldInfo& info, const FrepOracleCodec* codec) {
  const std::vector<NodeId> order = reachable_nodes(g, root);
  // Records of the oracles, in order of first use; any the codec cannot keep means the closed form.
  std::vector<std::string> records;
  std::vector<std::uint32_t> record_of(g.oracles().size(), UINT32_MAX);
  for (NodeId id : order) {
    const Node& n = g.node(id);
    if (n.op != Op::Oracle || record_of[oracle_index(n.value)] != UINT32_MAX) continue;
    std::optional<std::string> r;
    if (codec && codec->encode) r = codec->encode(g.oracle_of(n));
    if (!r) {
      const Model m = expand_oracles(g, root);
      return serialize_frep(*m.graph, m.root, info);
    }
    record_of[oracle_index(n.value)] = static_cast<std::uint32_t>(records.size());
    records.push_back(std::move(*r));
  }
  std::vector<std::uint64_t> index(static_cast<std::size_t>(root) + 1, 0);
  for (std::size_t i = 0; i < order.size(); ++i) index[order[i]] = i;
  std::string out;
  out.reserve(kHeader + order.size() * 4 + 4);
  out.append(kFrepMagic);
  put<std::uint32_t>(out, records.empty() ? kVersion : kOracleVersion);
  put<std::uint32_t>(out, info.bounds.empty() ? 0u : static_cast<std::uint32_t>(info.growth));  // flags: FieldInfo::growth
  put<std::uint64_t>(out, order.size());
  put<std::uint64_t>(out, order.size() - 1);  // the root is last in topological order
  put<double>(out, info.lipschitz > 0 ? info.lipschitz : 0.0);
  const double unknown = std::numeric_limits<double>::quiet_NaN();
  for (const Vec3* v : {&info.bounds.lo, &info.bounds.hi})
    for (int a = 0; a < 3; ++a) put<double>(out, info.bounds.empty() ? unknown : (*v)[a]);
  if (!records.empty()) {
    put<std::uint32_t>(out, static_cast<std::uint32_t>(records.size()));
    for (const std::string& r : records) {
      put<std::uint64_t>(out, r.size());
      out += r;
    }
  }
  for (std::size_t i = 0; i < order.size(); ++i) {
    const Node& n = g.node(order[i]);
    out.push_back(static_cast<char>(n.op));
    if (n.op == Op::Const) put<float>(out, n.value);
    if (n.op == Op::Oracle) put_varint(out, record_of[oracle_index(n.value)]);
    const int ar = op_arity(n.op);
    if (ar >= 1) put_varint(out, i - index[n.a]);
    if (ar >= 2) put_varint(out, i - index[n.b]);
  }
  put<std::uint32_t>(out, crc32(out));
  return out;
}

void save_frep(const std::string& path, const Graph& g, NodeId root, const FieldInfo& info, const FrepOracleCodec* codec) {
  write_file_atomically(path, serialize_frep(g, root, info, codec));
}

Model parse_frep(std::string_view b, const std::string& name, const FrepOracleCodec* codec) {
  auto fail = [&](std::size_t at, const std::string& what) -> InputError {
    return InputError(name, 0, what, at == 0 ? 1 : at);  // byte offsets are 1-based in messages' eyes
  };
  if (!is_frep_file(b)) throw fail(0, "not a .frep file (wrong magic bytes)");
  if (b.size() < kHeaderV1 + 4) throw fail(b.size(), "truncated .frep file (" + std::to_string(b.size()) + " bytes, header incomplete)");
  const auto version = get<std::uint32_t>(b, 8);
  if (version < 1 || version > kOracleVersion)
    throw fail(8, ".frep format version " + std::to_string(version) + " is not supported (this frep reads versions 1 to " +
                      std::to_string(kOracleVersion) + ")");
  const std::size_t header = version == 1 ? kHeaderV1 : kHeader;
  if (b.size() < header + 4) throw fail(b.size(), "truncated .frep file (" + std::to_string(b.size()) + " bytes, header incomplete)");
  const auto count = get<std::uint64_t>(b, 16), root = get<std::uint64_t>(b, 24);
  // Each node takes at least one byte: a count beyond the file's size is truncation or garbage.
  if (count == 0 || count > b.size()) throw fail(16, "truncated or corrupted .frep file (node count " + std::to_string(count) + ")");
  if (get<std::uint32_t>(b, b.size() - 4) != crc32(b.substr(0, b.size() - 4)))
    throw fail(b.size() - 4, "corrupted or truncated .frep file (checksum mismatch)");
  if (root >= count) throw fail(24, "root index " + std::to_string(root) + " is not a node");
  Model m;
  if (version >= 2) {
    const double lipschitz = get<double>(b, kHeaderV1);
    if (!(lipschitz >= 0) || !std::isfinite(lipschitz)) throw fail(kHeaderV1, "bad Lipschitz bound in the header");
    m.info.lipschitz = lipschitz;
    double v[6];
    int known = 0;
    for (int i = 0; i < 6; ++i) known += !std::isnan(v[i] = get<double>(b, kHeaderV1 + 8 + 8 * static_cast<std::size_t>(i)));
    const Box3 box{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}};
    if (known == 6 && std::isfinite(v[0] + v[1] + v[2] + v[3] + v[4] + v[5]) && !box.empty()) m.info.bounds = box;
    else if (known != 0) throw fail(kHeaderV1 + 8, "bad bounds in the header");
    const auto growth = get<std::uint32_t>(b, 12) & 3u;
    if (growth > static_cast<std::uint32_t>(Growth::Distance)) throw fail(12, "bad flags in the header");
    if (!m.info.bounds.empty()) m.info.growth = static_cast<Growth>(growth);
  }
  Graph& g = *m.graph;
  std::vector<NodeId> ids;
  ids.reserve(count);
  g.reserve(count);
  std::size_t at = header;
  const std::size_t end = b.size() - 4;
  auto varint = [&](std::size_t i) -> NodeId {
    std::uint64_t v = 0;
    for (int shift = 0;; shift += 7) {
      if (at >= end) throw fail(at, "truncated node " + std::to_string(i));
      if (shift > 63) throw fail(at, "bad argument of node " + std::to_string(i));
      const auto byte = static_cast<unsigned char>(b[at++]);
      v |= static_cast<std::uint64_t>(byte & 0x7f) << shift;
      if (!(byte & 0x80)) break;
    }
    if (v == 0 || v > i) throw fail(at, "node " + std::to_string(i) + " refers to a node after it");
    return ids[i - v];
  };
  // Oracle records come before the nodes that use them.
  std::vector<NodeId> record_nodes;
  if (version >= kOracleVersion) {
    if (!codec || !codec->decode)
      throw fail(at, "the file holds mesh leaves (oracles), which only frep's commands and load_field read");
    if (at + 4 > end) throw fail(at, "truncated oracle records");
    const std::uint32_t records = get<std::uint32_t>(b, at);
    at += 4;
    for (std::uint32_t k = 0; k < records; ++k) {
      if (at + 8 > end) throw fail(at, "truncated oracle record " + std::to_string(k));
      const std::uint64_t len = get<std::uint64_t>(b, at);
      at += 8;
      if (len > end - at) throw fail(at, "truncated oracle record " + std::to_string(k));
      record_nodes.push_back(g.oracle(codec->decode(b.substr(at, len), name)));
      at += len;
    }
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (at >= end) throw fail(at, "truncated: " + std::to_string(i) + " of " + std::to_string(count) + " nodes");
    const auto op_id = static_cast<unsigned char>(b[at++]);
    if (version >= kOracleVersion && op_id == static_cast<unsigned char>(Op::Oracle)) {
      std::uint64_t r = 0;
      for (int shift = 0;; shift += 7) {
        if (at >= end || shift > 63) throw fail(at, "bad oracle of node " + std::to_string(i));
        const auto byte = static_cast<unsigned char>(b[at++]);
        r |= static_cast<std::uint64_t>(byte & 0x7f) << shift;
        if (!(byte & 0x80)) break;
      }
      if (r >= record_nodes.size())
        throw fail(at, "node " + std::to_string(i) + " names oracle record " + std::to_string(r) + " of " +
                           std::to_string(record_nodes.size()));
      ids.push_back(record_nodes[r]);
      continue;
    }
    if (op_id >= kOpCount) throw fail(at - 1, "unknown opcode id " + std::to_string(op_id) + " (node " + std::to_string(i) + ")");
    const Op op = static_cast<Op>(op_id);
    float value = 0;
    if (op == Op::Const) {
      if (at + 4 > end) throw fail(at, "truncated constant");
      value = get<float>(b, at);
      at += 4;
    }
    const int ar = op_arity(op);
    const NodeId a = ar >= 1 ? varint(i) : kNoNode;
    const NodeId c = ar >= 2 ? varint(i) : kNoNode;
    ids.push_back(g.make(op, a, c, value));
  }
  if (at != end) throw fail(at, std::to_string(end - at) + " unexpected bytes after the last node");
  m.root = ids[root];
  return m;
}

Model read_frep(const std::string& path, const FrepOracleCodec* codec) { return parse_frep(read_file(path), path, codec); }

}  // namespace frep
