#pragma once
// Private to the map stage: the OctoMap tree behind OccupancyMap.
#include <octomap/OcTree.h>

#include <algorithm>

#include "fvx/map/occupancy_map.hpp"

namespace fvx::map {

/// OcTree with access to its root, so that trees of other node types (ColorOcTree,
/// OcTreeStamped) can be copied into it node by node when loaded.
class Tree : public octomap::OcTree {
 public:
  explicit Tree(double resolution_m) : octomap::OcTree(resolution_m) {}

  /// OctoMap's updateNode(key, hit) (non-lazy), also returning the node found before the
  /// update (search()'s result): the same early abort at the clamping bounds, the same
  /// expansion, creation and pruning, and the same values, in one descent where search() +
  /// updateNode() descended three times. On the way back up OctoMap prunes what became
  /// collapsible and sets every other node to the max of its children, up to the root; once
  /// a node that existed is neither pruned nor changed in value, nothing above it changes
  /// either, so the update stops there. That needs every inner node to hold the max of its
  /// children before the update, which OctoMap's own updates keep; a loaded tree is checked
  /// (check_inner_nodes), and one that fails takes OctoMap's recursion instead.
  ///
  /// `last` is the path of the previous update_cell of the same pass: the descent starts below
  /// the deepest node the two keys share (free cells come in key order, so most share all but
  /// the last level or two; descending from the root was three quarters of update_cell's time
  /// on a real scan). Only update_cell may change the tree while one `UpdatePath` is in use.
  struct UpdatePath {
    octomap::OcTreeNode* node[17];
    octomap::OcTreeKey key;
    int valid = -1;  ///< node[0 … valid] are the nodes of key's path (−1: none yet)
  };
  std::pair<const octomap::OcTreeNode*, const octomap::OcTreeNode*> update_cell(
      const octomap::OcTreeKey& key, bool hit, float& log_odds_before, UpdatePath& last) {
    const float update = hit ? prob_hit_log : prob_miss_log;
    octomap::OcTreeNode** path = last.node;
    bool created[17] = {};
    unsigned found = 0;  // the depth where search() stops
    octomap::OcTreeNode* leaf = nullptr;  // search()'s answer
    if (root) {
      path[0] = root;
      found = descend(key, path, last.valid < 0 ? 0u : shared_depth(key, last.key, unsigned(last.valid)));
      last.valid = int(found);
      leaf = found_node(path, found);
    }
    last.key = key;
    if (leaf) log_odds_before = leaf->getLogOdds();
    if (leaf && ((update >= 0 && leaf->getLogOdds() >= clamping_thres_max) ||
                 (update <= 0 && leaf->getLogOdds() <= clamping_thres_min)))
      return {leaf, leaf};
    if (!root) {
      root = new octomap::OcTreeNode();
      ++tree_size;
      path[0] = root;
      created[0] = true;
    }
    if (!inner_max_) {
      last.valid = -1;  // OctoMap's recursion may prune anywhere on the way
      return {leaf, updateNodeRecurs(root, created[0], key, 0, update, false)};
    }
    for (unsigned d = found; d < tree_depth; ++d) {  // updateNodeRecurs's way down from there
      const unsigned pos = octomap::computeChildIdx(key, int(tree_depth - 1 - d));
      if (!nodeChildExists(path[d], pos)) {
        if (!nodeHasChildren(path[d]) && !created[d]) {
          expandNode(path[d]);
        } else {
          createNodeChild(path[d], pos);
          created[d + 1] = true;
        }
      }
      path[d + 1] = getNodeChild(path[d], pos);
    }
    updateNodeLogOdds(path[tree_depth], update);
    return {leaf, update_ancestors(path, created, last.valid)};
  }

  /// How deep the path of `before` (known down to depth `reached`) is also `key`'s: the node
  /// at depth d follows bits depth − 1 … depth − d of each coordinate, so the paths share every
  /// node above the highest bit in which the keys differ (update_cell, StateReader).
  unsigned shared_depth(const octomap::OcTreeKey& key, const octomap::OcTreeKey& before, unsigned reached) const {
    const unsigned diff = unsigned(key[0] ^ before[0]) | unsigned(key[1] ^ before[1]) | unsigned(key[2] ^ before[2]);
    if (diff == 0) return reached;
    const unsigned highest = 31u - unsigned(__builtin_clz(diff));
    return std::min(tree_depth - 1 - highest, reached);
  }

  /// OcTreeBaseImpl::search's descent for `key` from path[from] (the node at depth `from`):
  /// fills path[from + 1 …] and returns the depth where it stops, tree_depth or that of a
  /// node without the child `key` needs. `Node`: OcTreeNode or const OcTreeNode.
  template <typename Node>
  unsigned descend(const octomap::OcTreeKey& key, Node** path, unsigned from) const {
    unsigned d = from;
    for (; d < tree_depth; ++d) {
      const unsigned pos = octomap::computeChildIdx(key, int(tree_depth - 1 - d));
      if (!nodeChildExists(path[d], pos)) break;
      // The const accessor of a const method; the nodes are the caller's to change or not.
      path[d + 1] = const_cast<Node*>(getNodeChild(path[d], pos));
    }
    return d;
  }

  /// search()'s answer where descend() stopped at `depth`: the node at the finest depth; a
  /// node without children above it (a pruned leaf holds the cell); none where the node has
  /// other children (the cell is unknown).
  template <typename Node>
  Node* found_node(Node* const* path, unsigned depth) const {
    return depth == tree_depth || !nodeHasChildren(path[depth]) ? path[depth] : nullptr;
  }

  /// Whether every inner node holds the max of its children's log-odds (update_cell's early
  /// stop relies on it); remembered for update_cell.
  void check_inner_nodes() { inner_max_ = !root || holds_max(root); }
  bool inner_nodes_hold_max() const { return inner_max_; }

  /// Copies the structure and log-odds of any occupancy tree of the same resolution.
  template <typename SourceTree>
  void copy_from(const SourceTree& source) {
    clear();
    if (!source.getRoot()) return;
    root = new octomap::OcTreeNode();
    ++tree_size;
    root->setLogOdds(source.getRoot()->getLogOdds());
    copy_children(source, source.getRoot(), root);
    size_changed = true;
  }

 private:
  /// update_cell's way up from the updated leaf path[tree_depth]: returns the node that holds
  /// the cell afterwards (the highest node pruned into one leaf, or the leaf). `valid`: how
  /// deep the path's nodes still exist (a pruned node's children are deleted).
  octomap::OcTreeNode* update_ancestors(octomap::OcTreeNode* const* path, const bool* created, int& valid) {
    octomap::OcTreeNode* result = path[tree_depth];
    valid = int(tree_depth);
    for (int d = int(tree_depth) - 1; d >= 0; --d) {
      octomap::OcTreeNode* node = path[d];
      if (pruneNode(node)) {
        result = node;
        valid = d;
        continue;
      }
      const float before = node->getLogOdds();
      node->updateOccupancyChildren();
      if (!created[d] && node->getLogOdds() == before) break;  // the nodes above hold their max already
    }
    return result;
  }

  bool holds_max(const octomap::OcTreeNode* node) const {
    if (!nodeHasChildren(node)) return true;
    if (node->getLogOdds() != node->getMaxChildLogOdds()) return false;
    for (unsigned i = 0; i < 8; ++i)
      if (nodeChildExists(node, i) && !holds_max(getNodeChild(node, i))) return false;
    return true;
  }

  bool inner_max_ = true;  ///< every inner node holds the max of its children (an empty tree does)

  template <typename SourceTree, typename SourceNode>
  void copy_children(const SourceTree& source, const SourceNode* from, octomap::OcTreeNode* to) {
    for (unsigned i = 0; i < 8; ++i) {
      if (!source.nodeChildExists(from, i)) continue;
      const SourceNode* child = source.getNodeChild(from, i);
      octomap::OcTreeNode* copy = createNodeChild(to, i);
      copy->setLogOdds(child->getLogOdds());
      copy_children(source, child, copy);
    }
  }
};

struct OccupancyMap::Impl {
  explicit Impl(double resolution_m) : tree(resolution_m) {}
  Tree tree;
};

inline VoxelKey to_voxel_key(const octomap::OcTreeKey& k) { return {k[0], k[1], k[2]}; }
inline octomap::OcTreeKey to_octree_key(const VoxelKey& k) { return octomap::OcTreeKey(k.x, k.y, k.z); }

inline VoxelState state_of(const octomap::OcTree& tree, const octomap::OcTreeNode* node) {
  if (!node) return VoxelState::Unknown;
  return tree.isNodeOccupied(node) ? VoxelState::Occupied : VoxelState::Free;
}

/// The state a log-odds value stands for (the before-state of an updated node, whose value
/// the update has already changed).
inline VoxelState state_of_log_odds(const octomap::OcTree& tree, float log_odds) {
  return log_odds >= tree.getOccupancyThresLog() ? VoxelState::Occupied : VoxelState::Free;
}

}  // namespace fvx::map
