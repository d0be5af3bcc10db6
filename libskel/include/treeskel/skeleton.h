/// @file skeleton.h
/// The curve skeleton: a tree of nodes that carry a position, a radius and the input points they
/// stand for.
#pragma once

#include <Eigen/Core>
#include <boost/graph/adjacency_list.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace treeskel {

/// One skeleton node (vertex bundle of the skeleton graph).
struct SkeletonNode {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< local frame, like PointCloud::positions
  double radius = 0.0;                                 ///< branch radius at this node (input units)
  std::vector<std::uint32_t> points;  ///< indices of the input points this node stands for
};

/// Edge bundle (no data yet; kept for future per-edge attributes).
struct SkeletonEdge {};

/// Undirected graph of the skeleton. `vecS` storage: node ids are 0..n-1.
using SkeletonGraph =
    boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS, SkeletonNode, SkeletonEdge>;
using NodeId = SkeletonGraph::vertex_descriptor;

/// Why input points were left out of the skeleton.
struct LeftOut {
  std::size_t small_clusters = 0;   ///< points of isolated clusters smaller than the noise threshold
  std::size_t far_parts = 0;        ///< points of large parts farther than the bridging distance
  std::size_t outliers = 0;         ///< stray points far outside the cloud's bulk (OctreeOptions)
  std::size_t total() const { return small_clusters + far_parts + outliers; }
};

/// A curve skeleton with its root. Invariants (checked by `validate`): the graph is a tree (connected
/// and acyclic), and every input point is listed by exactly one node or in `noise_points`.
struct Skeleton {
  SkeletonGraph graph;
  NodeId root = 0;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  ///< world = node position + offset
  std::vector<std::uint32_t> noise_points;          ///< input points assigned to no node
  LeftOut left_out;                                  ///< how many points were left out, by reason

  Skeleton() = default;
  Skeleton(const Skeleton&) = default;
  Skeleton& operator=(const Skeleton&) = default;
  /// Moves take the graph in constant time (`swap_graphs`); the skeleton moved from is left empty.
  Skeleton(Skeleton&& other) noexcept;
  Skeleton& operator=(Skeleton&& other) noexcept;
  /// Exchanges every member with `other` (a member added above needs adding here).
  void swap(Skeleton& other) noexcept;

  std::size_t node_count() const { return boost::num_vertices(graph); }
  std::size_t edge_count() const { return boost::num_edges(graph); }
  SkeletonNode& operator[](NodeId v) { return graph[v]; }
  const SkeletonNode& operator[](NodeId v) const { return graph[v]; }
};

/// Exchanges the nodes and edges of two graphs in constant time. Boost 1.74's adjacency_list declares
/// a copy constructor and copy assignment and so has no move (a graph "moved" is copied node by node,
/// every node's point list with it), and its swap() makes three copies; this swaps its two containers,
/// whose edge iterators stay valid.
void swap_graphs(SkeletonGraph& a, SkeletonGraph& b) noexcept;

/// Adds a node and returns its id.
NodeId add_node(Skeleton& skeleton, const SkeletonNode& node);

/// Moves the skeleton's local frame so that the box of its nodes starts at the origin: the positions
/// lose the box's minimum corner and `offset` gains it (world positions are unchanged). A skeleton
/// read at georeferenced coordinates is then swept in small numbers, as a cloud's is.
void recentre_offset(Skeleton& skeleton);

/// Number of nodes of degree >= 3 (the paper's bifurcation points).
std::size_t count_branch_points(const SkeletonGraph& graph);
/// Number of nodes of degree 1 (the paper's twig endpoints). A lone node counts as no endpoint.
std::size_t count_endpoints(const SkeletonGraph& graph);

/// True iff the graph is connected and acyclic (an empty graph is not a tree).
bool is_tree(const SkeletonGraph& graph);

/// Number of connected components.
std::size_t count_components(const SkeletonGraph& graph);

/// Parent of every node when the tree is hung from `root` (the root's parent is itself).
/// @pre `is_tree(graph)`.
std::vector<NodeId> parents_from_root(const SkeletonGraph& graph, NodeId root);

/// Nodes in breadth-first order from `root`.
std::vector<NodeId> bfs_order(const SkeletonGraph& graph, NodeId root);

/// Checks the invariants against a cloud of `point_count` points. Returns an empty string when they
/// hold, otherwise a sentence naming the first violation.
std::string validate(const Skeleton& skeleton, std::size_t point_count);

/// Total edge length.
double total_length(const SkeletonGraph& graph);

/// Rebuilds the graph keeping only the nodes with `keep[v]`, renumbered in order; edges between kept
/// nodes are kept. Returns the new id of every old node (or -1 for dropped nodes).
std::vector<std::int64_t> compact_nodes(Skeleton& skeleton, const std::vector<bool>& keep);

}  // namespace treeskel
