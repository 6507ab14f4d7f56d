#include "frep/expr/graph.hpp"


#include <bit>
#include <cstdlib>
#include <new>
#include <cstring>

#include "frep/error.hpp"
#include "frep/expr/expr.hpp"
#include "frep/expr/oracle.hpp"
#include "frep/expr/semantics.hpp"

namespace frep {
namespace {

std::uint64_t hash_node(const Node& n) {
  std::uint64_t h = static_cast<std::uint64_t>(n.op) * 0x9E3779B97F4A7C15ull;
  h ^= (static_cast<std::uint64_t>(n.a) << 32 | n.b) * 0xC2B2AE3D27D4EB4Full;
  h ^= static_cast<std::uint64_t>(std::bit_cast<std::uint32_t>(n.value)) * 0x165667B19E3779F9ull;
  h ^= h >> 29;
  h *= 0xBF58476D1CE4E5B9ull;
  h ^= h >> 32;
  return h;
}

bool same_node(const Node& x, const Node& y) {
  return x.op == y.op && x.a == y.a && x.b == y.b &&
         std::bit_cast<std::uint32_t>(x.value) == std::bit_cast<std::uint32_t>(y.value);
}

bool is_bits(float v, float want) {
  return std::bit_cast<std::uint32_t>(v) == std::bit_cast<std::uint32_t>(want);
}

}  // namespace

namespace {
constexpr std::uint64_t kEmptySlot = ~std::uint64_t(0);
}  // namespace


namespace {
// A node's window in `near_` starts at slot kSpacing * (its newest argument's id) and is kWindow
// slots (128 bytes) wide. One slot per id is enough: about a quarter of the nodes are
// leaves, which live in `spread_`, and windows overlap, so only nodes that are the newest
// argument of many others overflow (4,000 of armadillo's 6.6 million).
constexpr std::size_t kWindow = 16;
constexpr std::size_t kSpacing = 1;
constexpr std::uint64_t kTagMask = 0xFFFFFFFF00000000ull;

NodeId newest_argument(const Node& n) { return n.b == kNoNode ? n.a : std::max(n.a, n.b); }
}  // namespace

Graph::Graph() { rebuild(1024, 64); }

std::size_t Graph::memory_bytes() const {
  return nodes_.capacity() * sizeof(Node) + (near_.capacity() + spread_.capacity()) * sizeof(std::uint64_t);
}

// Where a lookup would look: the first empty slot of the node's window, if any. So a node in
// `spread_` always has a full window, which stays full (nothing is ever removed), and a lookup
// that meets an empty slot in the window knows the node is in neither index.
bool Graph::place_near(const Node& n, std::uint64_t entry) {
  const std::size_t home = kSpacing * std::size_t(newest_argument(n));
  for (std::size_t slot = home; slot < home + kWindow; ++slot)
    if (near_[slot] == kEmptySlot) {
      near_[slot] = entry;
      return true;
    }
  return false;
}

void Graph::place_spread(std::uint64_t hash, std::uint64_t entry) {
  const std::size_t mask = spread_.size() - 1;
  std::size_t slot = hash & mask;
  while (spread_[slot] != kEmptySlot) slot = (slot + 1) & mask;
  spread_[slot] = entry;
}

void Graph::rebuild(std::size_t capacity, std::size_t spread_slots) {
  Index(kSpacing * capacity + kWindow, kEmptySlot).swap(near_);
  Index(spread_slots, kEmptySlot).swap(spread_);
  capacity_ = capacity;
  spread_count_ = 0;
  // In id order, as intern placed them, so each node lands where a lookup looks.
  for (NodeId id = 0; id < nodes_.size(); ++id) {
    const Node& n = nodes_[id];
    const std::uint64_t h = hash_node(n);
    if (n.a != kNoNode && place_near(n, (h & kTagMask) | id)) continue;
    place_spread(h, (h & kTagMask) | id);
    ++spread_count_;
  }
}

void Graph::rehash_spread(std::size_t slots) {
  Index old(slots, kEmptySlot);
  old.swap(spread_);
  for (std::uint64_t s : old)
    if (s != kEmptySlot) place_spread(hash_node(nodes_[static_cast<NodeId>(s)]), s);
}

void Graph::reserve(std::size_t nodes) {
  nodes_.reserve(nodes);
  // Room in `spread_` for leaves and overflows up to half the nodes.
  std::size_t slots = spread_.size();
  while ((std::max(spread_count_, nodes / 2) + 1) * 2 > slots) slots *= 2;
  if (nodes > capacity_) {
    rebuild(nodes, slots);
  } else if (slots > spread_.size()) {
    rehash_spread(slots);
  }
}

NodeId Graph::intern(const Node& n) {
  if (nodes_.size() + 1 > capacity_) rebuild(2 * capacity_, spread_.size());
  const std::uint64_t h = hash_node(n);
  const std::uint64_t tag = h & kTagMask;
  const NodeId id = static_cast<NodeId>(nodes_.size());
  // The tag rejects most mismatches without touching the node.
  const auto same = [&](std::uint64_t s) { return (s & kTagMask) == tag && same_node(nodes_[static_cast<NodeId>(s)], n); };
  const auto add = [&](std::uint64_t& slot) {
    if (nodes_.size() >= kNoNode - 1) throw std::length_error("frep::Graph: too many nodes");
    nodes_.push_back(n);
    slot = tag | id;
    return id;
  };
  if (n.a != kNoNode) {
    const std::size_t home = kSpacing * std::size_t(newest_argument(n));
    for (std::size_t slot = home; slot < home + kWindow; ++slot) {
      const std::uint64_t s = near_[slot];
      if (s == kEmptySlot) return add(near_[slot]);
      if (same(s)) return static_cast<NodeId>(s);
    }
  }
  if ((spread_count_ + 1) * 2 > spread_.size()) rehash_spread(spread_.size() * 2);
  const std::size_t mask = spread_.size() - 1;
  std::size_t slot = h & mask;
  for (std::uint64_t s; (s = spread_[slot]) != kEmptySlot; slot = (slot + 1) & mask)
    if (same(s)) return static_cast<NodeId>(s);
  ++spread_count_;
  return add(spread_[slot]);
}

NodeId Graph::constant(float v) { return intern({Op::Const, kNoNode, kNoNode, v}); }

NodeId Graph::unary(Op op, NodeId a) {
  FREP_ASSERT(op_arity(op) == 1, std::string(op_name(op)) + " is not unary");
  FREP_ASSERT(a < nodes_.size(), "argument id out of range");
  const Node& na = nodes_[a];
  if (na.op == Op::Const) return constant(op_eval<float>(op, na.value, 0.0f));
  switch (op) {
    case Op::Neg:
      if (na.op == Op::Neg) return na.a;  // -(-x) = x
      break;
    case Op::Abs:
      if (na.op == Op::Abs) return a;                            // ||x|| = |x|
      if (na.op == Op::Neg) return unary(Op::Abs, na.a);         // |-x| = |x|
      break;
    case Op::Square:
      if (na.op == Op::Neg || na.op == Op::Abs) return unary(Op::Square, na.a);  // (-x)^2 = x^2
      break;
    default:
      break;
  }
  return intern({op, a, kNoNode, 0.0f});
}

NodeId Graph::binary(Op op, NodeId a, NodeId b) {
  FREP_ASSERT(op_arity(op) == 2, std::string(op_name(op)) + " is not binary");
  FREP_ASSERT(a < nodes_.size() && b < nodes_.size(), "argument id out of range");
  const Node na = nodes_[a];
  const Node nb = nodes_[b];
  const bool ca = na.op == Op::Const, cb = nb.op == Op::Const;
  if (ca && cb) return constant(op_eval<float>(op, na.value, nb.value));
  // Every identity below is exact in f32, bit for bit, NaN and signed zero included.
  switch (op) {
    case Op::Add:
      if (cb && is_bits(nb.value, -0.0f)) return a;
      if (ca && is_bits(na.value, -0.0f)) return b;
      if (nb.op == Op::Neg) return binary(Op::Sub, a, nb.a);  // a + (-b) = a - b
      break;
    case Op::Sub:
      if (cb && is_bits(nb.value, 0.0f)) return a;
      if (ca && is_bits(na.value, -0.0f)) return unary(Op::Neg, b);
      if (nb.op == Op::Neg) return binary(Op::Add, a, nb.a);  // a - (-b) = a + b
      break;
    case Op::Mul:
      if (cb && nb.value == 1.0f) return a;
      if (ca && na.value == 1.0f) return b;
      if (cb && nb.value == -1.0f) return unary(Op::Neg, a);
      if (ca && na.value == -1.0f) return unary(Op::Neg, b);
      if (a == b) return unary(Op::Square, a);
      break;
    case Op::Div:
      if (cb && nb.value == 1.0f) return a;
      if (ca && na.value == 1.0f) return unary(Op::Recip, b);
      break;
    case Op::Min:
    case Op::Max:
      if (a == b) return a;
      break;
    case Op::And:  // a == 0 ? a : b
      if (ca) return na.value == 0.0f ? a : b;
      break;
    case Op::Or:  // a != 0 ? a : b
      if (ca) return na.value != 0.0f ? a : b;
      break;
    default:
      break;
  }
  // Canonical order for add and mul, which are commutative bit for bit, so a+b and b+a are one
  // node. Not for min and max: they return their second argument on a tie, and -0 == +0 is a
  // tie whose sign a later division can see.
  if ((op == Op::Add || op == Op::Mul) && a > b) std::swap(a, b);
  return intern({op, a, b, 0.0f});
}

NodeId Graph::oracle(std::shared_ptr<const Oracle> o) {
  FREP_ASSERT(o != nullptr, "null oracle");
  std::uint32_t index = 0;
  while (index < oracles_.size() && oracles_[index] != o) ++index;  // a graph holds a few oracles
  if (index == oracles_.size()) oracles_.push_back(std::move(o));
  return intern({Op::Oracle, kNoNode, kNoNode, std::bit_cast<float>(index)});
}

NodeId Graph::make(Op op, NodeId a, NodeId b, float value) {
  FREP_ASSERT(op != Op::Oracle, "oracle nodes are made by Graph::oracle");
  switch (op_arity(op)) {
    case 0:
      if (op == Op::Const) return constant(value);
      return intern({op, kNoNode, kNoNode, 0.0f});
    case 1:
      return unary(op, a);
    default:
      return binary(op, a, b);
  }
}

Expr Graph::x() { return Expr(*this, var_x()); }
Expr Graph::y() { return Expr(*this, var_y()); }
Expr Graph::z() { return Expr(*this, var_z()); }
Expr Graph::c(float v) { return Expr(*this, constant(v)); }
Expr Graph::expr(NodeId id) {
  FREP_ASSERT(id < nodes_.size(), "node id out of range");
  return Expr(*this, id);
}

std::vector<NodeId> reachable_nodes(const Graph& g, NodeId root) {
  FREP_ASSERT(root < g.size(), "root id out of range");
  // Arguments always have smaller ids than their users, so one backward sweep marks everything.
  std::vector<std::uint8_t> live(root + 1, 0);
  live[root] = 1;
  std::size_t count = 0;
  for (NodeId id = root + 1; id-- > 0;) {
    if (!live[id]) continue;
    ++count;
    const Node& n = g.node(id);
    if (n.a != kNoNode) live[n.a] = 1;
    if (n.b != kNoNode) live[n.b] = 1;
  }
  std::vector<NodeId> out;
  out.reserve(count);
  for (NodeId id = 0; id <= root; ++id)
    if (live[id]) out.push_back(id);
  return out;
}

}  // namespace frep
