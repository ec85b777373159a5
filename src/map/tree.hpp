#pragma once
// Private to the map stage: the OctoMap tree behind OccupancyMap.
#include <octomap/OcTree.h>

#include "fvx/map/occupancy_map.hpp"

namespace fvx::map {

/// OcTree with access to its root, so that trees of other node types (ColorOcTree,
/// OcTreeStamped) can be copied into it node by node when loaded.
class Tree : public octomap::OcTree {
 public:
  explicit Tree(double resolution_m) : octomap::OcTree(resolution_m) {}

  /// OctoMap's updateNode(key, hit) (non-lazy), also returning the node found before the
  /// update: the same early abort at the clamping bounds and the same recursion, with one
  /// search shared by both, where search() + updateNode() would descend three times.
  std::pair<const octomap::OcTreeNode*, const octomap::OcTreeNode*> update_cell(
      const octomap::OcTreeKey& key, bool hit, float& log_odds_before) {
    const float update = hit ? prob_hit_log : prob_miss_log;
    octomap::OcTreeNode* leaf = search(key);
    if (leaf) log_odds_before = leaf->getLogOdds();
    if (leaf && ((update >= 0 && leaf->getLogOdds() >= clamping_thres_max) ||
                 (update <= 0 && leaf->getLogOdds() <= clamping_thres_min)))
      return {leaf, leaf};
    bool created_root = false;
    if (!root) {
      root = new octomap::OcTreeNode();
      ++tree_size;
      created_root = true;
    }
    return {leaf, updateNodeRecurs(root, created_root, key, 0, update, false)};
  }

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
