#include "treeskel/skeleton.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <deque>

namespace treeskel {

NodeId add_node(Skeleton& skeleton, const SkeletonNode& node) {
  return boost::add_vertex(node, skeleton.graph);
}

void recentre_offset(Skeleton& skeleton) {
  if (skeleton.node_count() == 0) return;
  Eigen::AlignedBox3d box;
  for (NodeId v = 0; v < skeleton.node_count(); ++v) box.extend(skeleton[v].position);
  const Eigen::Vector3d shift = box.min();
  for (NodeId v = 0; v < skeleton.node_count(); ++v) skeleton[v].position -= shift;
  skeleton.offset += shift;
}

std::size_t count_branch_points(const SkeletonGraph& graph) {
  std::size_t n = 0;
  for (auto v : boost::make_iterator_range(boost::vertices(graph)))
    if (boost::degree(v, graph) >= 3) ++n;
  return n;
}

std::size_t count_endpoints(const SkeletonGraph& graph) {
  std::size_t n = 0;
  for (auto v : boost::make_iterator_range(boost::vertices(graph)))
    if (boost::degree(v, graph) == 1) ++n;
  return n;
}

std::size_t count_components(const SkeletonGraph& graph) {
  const std::size_t n = boost::num_vertices(graph);
  std::vector<bool> seen(n, false);
  std::size_t components = 0;
  std::vector<NodeId> stack;
  for (NodeId s = 0; s < n; ++s) {
    if (seen[s]) continue;
    ++components;
    seen[s] = true;
    stack.push_back(s);
    while (!stack.empty()) {
      const NodeId v = stack.back();
      stack.pop_back();
      for (auto w : boost::make_iterator_range(boost::adjacent_vertices(v, graph)))
        if (!seen[w]) {
          seen[w] = true;
          stack.push_back(w);
        }
    }
  }
  return components;
}

bool is_tree(const SkeletonGraph& graph) {
  const std::size_t n = boost::num_vertices(graph);
  if (n == 0) return false;
  // Self loops and parallel edges make a multigraph with as many edges as a tree but a cycle.
  for (auto e : boost::make_iterator_range(boost::edges(graph)))
    if (boost::source(e, graph) == boost::target(e, graph)) return false;
  return boost::num_edges(graph) == n - 1 && count_components(graph) == 1;
}

std::vector<NodeId> bfs_order(const SkeletonGraph& graph, NodeId root) {
  const std::size_t n = boost::num_vertices(graph);
  std::vector<NodeId> order;
  if (root >= n) return order;
  order.reserve(n);
  std::vector<bool> seen(n, false);
  seen[root] = true;
  order.push_back(root);
  for (std::size_t i = 0; i < order.size(); ++i)
    for (auto w : boost::make_iterator_range(boost::adjacent_vertices(order[i], graph)))
      if (!seen[w]) {
        seen[w] = true;
        order.push_back(w);
      }
  return order;
}

std::vector<NodeId> parents_from_root(const SkeletonGraph& graph, NodeId root) {
  const std::size_t n = boost::num_vertices(graph);
  std::vector<NodeId> parent(n, root);
  std::vector<bool> seen(n, false);
  if (root >= n) return parent;
  seen[root] = true;
  std::deque<NodeId> queue{root};
  while (!queue.empty()) {
    const NodeId v = queue.front();
    queue.pop_front();
    for (auto w : boost::make_iterator_range(boost::adjacent_vertices(v, graph)))
      if (!seen[w]) {
        seen[w] = true;
        parent[w] = v;
        queue.push_back(w);
      }
  }
  return parent;
}

std::string validate(const Skeleton& skeleton, std::size_t point_count) {
  const auto& g = skeleton.graph;
  if (boost::num_vertices(g) == 0) return "the skeleton has no node";
  if (skeleton.root >= boost::num_vertices(g)) return "the root is not a node of the skeleton";
  if (count_components(g) != 1) return "the skeleton is not connected";
  if (!is_tree(g)) return "the skeleton has a cycle";
  std::vector<int> owners(point_count, 0);
  auto claim = [&](std::uint32_t i) -> bool {
    if (i >= point_count) return false;
    ++owners[i];
    return true;
  };
  for (auto v : boost::make_iterator_range(boost::vertices(g)))
    for (auto i : g[v].points)
      if (!claim(i)) return "node " + std::to_string(v) + " lists point " + std::to_string(i) + " of " +
                            std::to_string(point_count);
  for (auto i : skeleton.noise_points)
    if (!claim(i)) return "noise lists point " + std::to_string(i) + " of " + std::to_string(point_count);
  for (std::size_t i = 0; i < point_count; ++i)
    if (owners[i] != 1)
      return "point " + std::to_string(i) + " is claimed " + std::to_string(owners[i]) + " times";
  return {};
}

double total_length(const SkeletonGraph& graph) {
  double length = 0.0;
  for (auto e : boost::make_iterator_range(boost::edges(graph)))
    length += (graph[boost::source(e, graph)].position - graph[boost::target(e, graph)].position).norm();
  return length;
}

void swap_graphs(SkeletonGraph& a, SkeletonGraph& b) noexcept {
  a.m_vertices.swap(b.m_vertices);
  a.m_edges.swap(b.m_edges);
}

Skeleton::Skeleton(Skeleton&& other) noexcept { swap(other); }

Skeleton& Skeleton::operator=(Skeleton&& other) noexcept {
  Skeleton taken(std::move(other));  // leaves `other` empty; this skeleton's old contents go with `taken`
  swap(taken);
  return *this;
}

void Skeleton::swap(Skeleton& other) noexcept {
  swap_graphs(graph, other.graph);
  std::swap(root, other.root);
  std::swap(offset, other.offset);
  noise_points.swap(other.noise_points);
  std::swap(left_out, other.left_out);
}

std::vector<std::int64_t> compact_nodes(Skeleton& skeleton, const std::vector<bool>& keep) {
  auto& old = skeleton.graph;
  const std::size_t n = boost::num_vertices(old);
  std::vector<std::int64_t> remap(n, -1);
  std::size_t kept = 0;
  for (NodeId v = 0; v < n; ++v)
    if (keep[v]) remap[v] = static_cast<std::int64_t>(kept++);
  SkeletonGraph fresh(kept);
  for (NodeId v = 0; v < n; ++v)
    if (keep[v]) fresh[static_cast<NodeId>(remap[v])] = std::move(old[v]);  // the old graph is dropped below
  for (auto e : boost::make_iterator_range(boost::edges(old))) {
    const auto a = remap[boost::source(e, old)], b = remap[boost::target(e, old)];
    if (a >= 0 && b >= 0) boost::add_edge(static_cast<NodeId>(a), static_cast<NodeId>(b), fresh);
  }
  swap_graphs(skeleton.graph, fresh);  // the old graph goes with `fresh`
  if (skeleton.root < n && remap[skeleton.root] >= 0) skeleton.root = static_cast<NodeId>(remap[skeleton.root]);
  return remap;
}

}  // namespace treeskel
