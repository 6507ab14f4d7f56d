#include "frep/io/vm.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <algorithm>
#include <vector>

#include "frep/error.hpp"
#include "frep/expr/copy.hpp"
#include "frep/util/atomic_file.hpp"
#include "frep/io/field_comments.hpp"
#include "frep/util/parse_number.hpp"
#include "frep/util/text_scan.hpp"

namespace frep {
namespace {

struct Line {
  std::string_view id;
  Op op;
  std::uint32_t args[2] = {0, 0};  // indices into the line table, resolved in pass two
  std::string_view arg_names[2];
  float value = 0;
  std::uint64_t line_no = 0;
};

using detail::is_space;
using detail::quoted;

float parse_number(std::string_view tok, const std::string& name, std::uint64_t line_no) {
  float v = 0;
  if (!parse_real(tok, v)) throw InputError(name, line_no, "bad number " + quoted(tok));
  return v;  // overflow gives +-inf, as Fidget's reader does
}

// Ids to line indices: open addressing over the lines' own id strings (no per-id allocation,
// which matters for files with millions of lines).
class IdTable {
 public:
  explicit IdTable(std::size_t expected) {
    std::size_t cap = 16;
    while (cap < expected * 2) cap *= 2;
    slots_.assign(cap, kEmpty);
  }
  // Returns the index already stored under `id`, or stores `index` and returns it.
  std::uint32_t insert(std::string_view id, std::uint32_t index, const std::vector<Line>& lines) {
    if ((count_ + 1) * 2 > slots_.size()) grow(lines);
    std::size_t slot = hash(id) & (slots_.size() - 1);
    while (slots_[slot] != kEmpty) {
      if (lines[slots_[slot]].id == id) return slots_[slot];
      slot = (slot + 1) & (slots_.size() - 1);
    }
    slots_[slot] = index;
    ++count_;
    return index;
  }
  std::uint32_t find(std::string_view id, const std::vector<Line>& lines) const {
    std::size_t slot = hash(id) & (slots_.size() - 1);
    while (slots_[slot] != kEmpty) {
      if (lines[slots_[slot]].id == id) return slots_[slot];
      slot = (slot + 1) & (slots_.size() - 1);
    }
    return kEmpty;
  }
  static constexpr std::uint32_t kEmpty = 0xFFFFFFFFu;

 private:
  static std::size_t hash(std::string_view s) {
    std::uint64_t h = 1469598103934665603ull;  // FNV-1a, then a final mix
    for (char c : s) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
    h ^= h >> 32;
    return static_cast<std::size_t>(h * 0x9E3779B97F4A7C15ull >> 16);
  }
  void grow(const std::vector<Line>& lines) {
    std::vector<std::uint32_t> old;
    old.swap(slots_);
    slots_.assign(old.size() * 2, kEmpty);
    for (std::uint32_t idx : old) {
      if (idx == kEmpty) continue;
      std::size_t slot = hash(lines[idx].id) & (slots_.size() - 1);
      while (slots_[slot] != kEmpty) slot = (slot + 1) & (slots_.size() - 1);
      slots_[slot] = idx;
    }
  }
  std::vector<std::uint32_t> slots_;
  std::size_t count_ = 0;
};

}  // namespace

Model parse_vm(std::string_view text, const std::string& name) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // UTF-8 byte order mark (editors on Windows)
  std::vector<Line> lines;
  const std::size_t expected = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
  lines.reserve(expected);
  IdTable ids(expected);
  std::uint64_t line_no = 0;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    std::string_view raw = text.substr(pos, eol - pos);
    pos = eol + 1;
    ++line_no;
    if (std::size_t hash = raw.find('#'); hash != std::string_view::npos) raw = raw.substr(0, hash);
    std::string_view tok[5];
    int n = 0;
    std::size_t i = 0;
    while (i < raw.size()) {
      while (i < raw.size() && is_space(raw[i])) ++i;
      if (i >= raw.size()) break;
      std::size_t j = i;
      while (j < raw.size() && !is_space(raw[j])) ++j;
      if (n == 5) throw InputError(name, line_no, "too many tokens");
      tok[n++] = raw.substr(i, j - i);
      i = j;
    }
    if (n == 0) continue;
    if (n == 1) throw InputError(name, line_no, "expected `<id> <opcode> [args]`, got only " + quoted(tok[0]));
    auto op = op_from_name(tok[1]);
    if (!op) throw InputError(name, line_no, "unknown opcode " + quoted(tok[1]));
    Line l;
    l.id = tok[0];
    l.op = *op;
    l.line_no = line_no;
    const int want = (*op == Op::Const) ? 1 : op_arity(*op);
    if (n - 2 != want)
      throw InputError(name, line_no,
                       std::string(op_name(*op)) + " takes " + std::to_string(want) + " argument" +
                           (want == 1 ? "" : "s") + ", got " + std::to_string(n - 2));
    if (*op == Op::Const) {
      l.value = parse_number(tok[2], name, line_no);
    } else {
      for (int k = 0; k < want; ++k) l.arg_names[k] = tok[2 + k];
    }
    lines.push_back(l);
    const std::uint32_t index = static_cast<std::uint32_t>(lines.size() - 1);
    const std::uint32_t first = ids.insert(l.id, index, lines);
    if (first != index)
      throw InputError(name, line_no, "id " + quoted(l.id) + " is defined twice (first on line " +
                                          std::to_string(lines[first].line_no) + ")");
  }
  if (lines.empty()) throw InputError(name, 0, "no expression: the file has no instruction lines");

  // Pass two: resolve argument names.
  for (Line& l : lines) {
    for (int k = 0; k < op_arity(l.op); ++k) {
      const std::uint32_t idx = ids.find(l.arg_names[k], lines);
      if (idx == IdTable::kEmpty) throw InputError(name, l.line_no, "undefined id " + quoted(l.arg_names[k]));
      l.args[k] = idx;
    }
  }

  // Pass three: build nodes in dependency order by depth-first search with an explicit stack
  // (no recursion, so a million-deep chain is fine). A node is "on the path" from when it is
  // pushed until it is built; meeting such a node again is a cycle.
  Model model;
  Graph& g = *model.graph;
  g.reserve(lines.size());
  constexpr NodeId kUnvisited = kNoNode, kOnPath = kNoNode - 1;
  std::vector<NodeId> built(lines.size(), kUnvisited);
  struct Frame {
    std::uint32_t line;
    int next_arg;
  };
  std::vector<Frame> stack;
  for (std::uint32_t start = 0; start < lines.size(); ++start) {
    if (built[start] != kUnvisited) continue;
    stack.push_back({start, 0});
    built[start] = kOnPath;
    while (!stack.empty()) {
      Frame& f = stack.back();
      const Line& l = lines[f.line];
      const int ar = op_arity(l.op);
      if (f.next_arg < ar) {
        const std::uint32_t arg = l.args[f.next_arg++];
        if (built[arg] == kOnPath)
          throw InputError(name, l.line_no, "cycle: " + quoted(l.id) + " depends on itself through " + quoted(lines[arg].id));
        if (built[arg] == kUnvisited) {
          built[arg] = kOnPath;
          stack.push_back({arg, 0});  // invalidates f
        }
        continue;
      }
      built[f.line] = g.make(l.op, ar > 0 ? built[l.args[0]] : kNoNode, ar > 1 ? built[l.args[1]] : kNoNode, l.value);
      stack.pop_back();
    }
  }
  model.root = built.back();
  model.info = detail::leading_field_info(text, "#", name);
  return model;
}

Model read_vm(const std::string& path) { return parse_vm(read_file(path), path); }

void write_vm(std::ostream& out, const Graph& g, NodeId root, const FieldInfo& info) {
  if (has_oracles(g, root)) {
    const Model m = expand_oracles(g, root);
    return write_vm(out, *m.graph, m.root, info);
  }
  const std::vector<NodeId> order = reachable_nodes(g, root);
  out << detail::field_info_comments(info, "#");
  char buf[64];
  std::vector<std::uint32_t> index(root + 1, 0);
  for (std::uint32_t i = 0; i < order.size(); ++i) index[order[i]] = i;
  bool has_recip = false;
  for (NodeId id : order) has_recip |= g.node(id).op == Op::Recip;
  if (has_recip) out << "_one const 1\n";  // not a hex id, so it cannot collide
  for (std::uint32_t i = 0; i < order.size(); ++i) {
    const Node& n = g.node(order[i]);
    out << '_' << std::hex << i << std::dec << ' ';
    switch (op_arity(n.op)) {
      case 0:
        out << op_name(n.op);
        if (n.op == Op::Const) {
          std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(n.value));
          out << ' ' << buf;
        }
        break;
      case 1:
        if (n.op == Op::Recip) out << "div _one _" << std::hex << index[n.a] << std::dec;
        else out << op_name(n.op) << " _" << std::hex << index[n.a] << std::dec;
        break;
      default:
        out << op_name(n.op) << " _" << std::hex << index[n.a] << " _" << index[n.b] << std::dec;
    }
    out << '\n';
  }
}

void save_vm(const std::string& path, const Graph& g, NodeId root, const FieldInfo& info) {
  write_file_atomically(path, [&](std::ostream& out) { write_vm(out, g, root, info); });
}

}  // namespace frep
