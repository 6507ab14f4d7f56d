// The expression graph: an arena of hash-consed nodes (building the same subexpression twice
// yields the same node), with constant folding and exact algebraic identities at construction.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "frep/expr/opcode.hpp"

namespace frep {

using NodeId = std::uint32_t;
inline constexpr NodeId kNoNode = 0xFFFFFFFFu;

// One node: 16 bytes. Leaves have a == b == kNoNode; unary ops have b == kNoNode.
struct Node {
  Op op;
  NodeId a;
  NodeId b;
  float value;  // only for Op::Const
};
static_assert(sizeof(Node) == 16, "docs/engine.md states 16 bytes per node");

class Expr;

// Owns every node. Node ids are indices, and a node's arguments always have smaller ids, so the
// arena is already in topological order. Memory: 16 bytes per node plus the hash index (4 bytes
// per slot, at most half full): 24 to 32 bytes per node.
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
  // Any op by arity (leaves other than Const take no arguments).
  NodeId make(Op op, NodeId a = kNoNode, NodeId b = kNoNode, float value = 0.0f);

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
  NodeId intern(const Node& n);
  void grow_index();

  std::vector<Node> nodes_;
  std::vector<NodeId> index_;  // open addressing, kNoNode = empty
};

// Nodes reachable from `root`, in increasing id order (so arguments come first). Iterative.
std::vector<NodeId> reachable_nodes(const Graph& g, NodeId root);

}  // namespace frep
