#include <algorithm>

#include "tree.hpp"

namespace fvx::map {

StateReader::StateReader(const OccupancyMap& map) : impl_(*map.impl_) {}

VoxelState StateReader::operator()(const VoxelKey& key) {
  const Tree& tree = impl_.tree;
  if (!tree.getRoot()) return VoxelState::Unknown;
  const int depth = int(tree.getTreeDepth());
  int from = 0;  // the deepest node of the last path that is this key's too
  if (reached_ >= 0) {
    const unsigned diff = unsigned(key.x ^ last_.x) | unsigned(key.y ^ last_.y) | unsigned(key.z ^ last_.z);
    if (diff == 0) return last_state_;
    // The node at depth d follows bits depth − 1 … depth − d of each coordinate: shared down
    // to the depth above the highest bit in which the keys differ.
    const int highest = 31 - __builtin_clz(diff);
    from = std::min(depth - 1 - highest, reached_);
  } else {
    path_[0] = tree.getRoot();
  }
  last_ = key;
  reached_ = int(tree.descend(to_octree_key(key), path_, unsigned(from)));
  last_state_ = state_of(tree, tree.found_node(path_, unsigned(reached_)));
  return last_state_;
}

}  // namespace fvx::map
