// The expression graph: an arena of hash-consed nodes (building the same subexpression twice
// yields the same node), with constant folding and exact algebraic identities at construction.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "frep/expr/opcode.hpp"
#include "frep/util/large_allocator.hpp"

namespace frep {

using NodeId = std::uint32_t;
inline constexpr NodeId kNoNode = 0xFFFFFFFFu;

// One node: 16 bytes. Leaves have a == b == kNoNode; unary ops have b == kNoNode.
struct Node {
  Op op;
  NodeId a;
  NodeId b;
  float value;  // Op::Const: the value; Op::Oracle: the bits of its index in Graph::oracles()
};
static_assert(sizeof(Node) == 16, "docs/engine.md states 16 bytes per node");

class Expr;
class Oracle;

// The oracles of a graph or a tape, by index.
using OracleTable = std::vector<std::shared_ptr<const Oracle>>;

// The index of an Op::Oracle node or instruction in its oracle table.
inline std::uint32_t oracle_index(float value) { return std::bit_cast<std::uint32_t>(value); }


// Owns every node. Node ids are indices, and a node's arguments always have smaller ids, so the
// arena is already in topological order. Memory: 16 bytes per node, plus two hash indexes of
// 8-byte slots (the id and half the hash): 8 bytes per node for nodes with arguments, 16 to 32
// per leaf (constants mostly); about 32 to 48 bytes per node in all (docs/engine.md).
class Graph {
 public:
  Graph();
  Graph(const Graph&) = delete;
  Graph& operator=(const Graph&) = delete;
  // Movable, but Expr handles keep pointing at the old address: move before making handles.
  Graph(Graph&&) = default;
  Graph& operator=(Graph&&) = default;

  NodeId var_x() { return intern({Op::VarX, kNoNode, kNoNode, 0.0f}); }
  NodeId var_y() { return intern({Op::VarY, kNoNode, kNoNode, 0.0f}); }
  NodeId var_z() { return intern({Op::VarZ, kNoNode, kNoNode, 0.0f}); }
  NodeId constant(float v);
  // Builds op(a) or op(a, b), folding constants and applying exact identities.
  NodeId unary(Op op, NodeId a);
  NodeId binary(Op op, NodeId a, NodeId b);
  // Any op by arity (leaves other than Const take no arguments; oracles are made by oracle()).
  NodeId make(Op op, NodeId a = kNoNode, NodeId b = kNoNode, float value = 0.0f);
  // A leaf whose value is computed by `o` (frep/expr/oracle.hpp). The same oracle object twice
  // gives the same node.
  NodeId oracle(std::shared_ptr<const Oracle> o);
  // The oracles of Op::Oracle nodes, by index (Node::value).
  const OracleTable& oracles() const { return oracles_; }
  const Oracle& oracle_of(const Node& n) const { return *oracles_[oracle_index(n.value)]; }

  // Makes room for `nodes` nodes in all, so that building that many reallocates nothing.
  void reserve(std::size_t nodes);

  const Node& node(NodeId id) const { return nodes_[id]; }
  std::size_t size() const { return nodes_.size(); }
  bool is_const(NodeId id) const { return nodes_[id].op == Op::Const; }
  std::size_t memory_bytes() const;

  // Handles for operator-overloaded construction.
  Expr x();
  Expr y();
  Expr z();
  Expr c(float v);
  Expr expr(NodeId id);

 private:
  using Index = std::vector<std::uint64_t, LargeAllocator<std::uint64_t>>;
  NodeId intern(const Node& n);
  // Rebuilds both indexes with room for `capacity` nodes and `spread_slots` (a power of two)
  // slots for the rest.
  void rebuild(std::size_t capacity, std::size_t spread_slots);
  void rehash_spread(std::size_t slots);
  bool place_near(const Node& n, std::uint64_t entry);
  void place_spread(std::uint64_t hash, std::uint64_t entry);

  std::vector<Node, LargeAllocator<Node>> nodes_;
  OracleTable oracles_;
  // Slots hold the hash's upper half << 32 | id; all ones is empty. A node with arguments lives
  // within a few slots of slot (its newest argument's id) in `near_`, unless that window is
  // full: graphs are built bottom up, so that memory is usually in cache, where a hashed slot
  // would be a cache miss per node. Leaves and overflows go in `spread_`, plain open addressing
  // at most half full.
  Index near_;
  Index spread_;
  std::size_t capacity_ = 0;  // nodes `near_` has room for
  std::size_t spread_count_ = 0;
};

// Nodes reachable from `root`, in increasing id order (so arguments come first). Iterative.
std::vector<NodeId> reachable_nodes(const Graph& g, NodeId root);

}  // namespace frep
