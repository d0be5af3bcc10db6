#include "treeskel/modeling/chains.h"

#include "treeskel/error.h"

namespace treeskel::modeling {

ChainTree build_chains(const Skeleton& skeleton) {
  const auto& g = skeleton.graph;
  const std::size_t n = boost::num_vertices(g);
  if (n == 0) throw InputError("the skeleton is empty");
  if (!is_tree(g)) throw InputError("the skeleton is not a tree (it has a cycle or several components)");
  if (skeleton.root >= n) throw InputError("the skeleton's root is not one of its nodes");

  ChainTree t;
  t.parent = parents_from_root(g, skeleton.root);
  t.children.assign(n, {});
  const auto order = bfs_order(g, skeleton.root);
  for (NodeId v : order)
    if (v != skeleton.root) t.children[t.parent[v]].push_back(v);
  t.chain_of.assign(n, -1);

  // Chains in breadth-first order of their first node, so parents come before children.
  std::vector<std::ptrdiff_t> ending_at(n, -1);
  for (NodeId v : order) {
    const auto& kids = t.children[v];
    if (kids.empty()) continue;
    const bool starts_chains = v == skeleton.root || kids.size() >= 2;
    if (!starts_chains) continue;
    for (NodeId first : kids) {
      Chain chain;
      chain.nodes = {v, first};
      NodeId w = first;
      while (t.children[w].size() == 1) {
        w = t.children[w].front();
        chain.nodes.push_back(w);
      }
      chain.parent = ending_at[v];
      const std::size_t id = t.chains.size();
      if (chain.parent >= 0) t.chains[static_cast<std::size_t>(chain.parent)].children.push_back(id);
      for (std::size_t i = 1; i < chain.nodes.size(); ++i) t.chain_of[chain.nodes[i]] = static_cast<std::ptrdiff_t>(id);
      ending_at[chain.nodes.back()] = static_cast<std::ptrdiff_t>(id);
      t.chains.push_back(std::move(chain));
    }
  }
  return t;
}

double chain_length(const Skeleton& skeleton, const Chain& chain) {
  double length = 0.0;
  for (std::size_t i = 1; i < chain.nodes.size(); ++i)
    length += (skeleton[chain.nodes[i]].position - skeleton[chain.nodes[i - 1]].position).norm();
  return length;
}

}  // namespace treeskel::modeling
