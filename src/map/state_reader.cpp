#include "tree.hpp"

namespace fvx::map {

StateReader::StateReader(const OccupancyMap& map) : impl_(*map.impl_) {}

VoxelState StateReader::operator()(const VoxelKey& key) {
  const Tree& tree = impl_.tree;
  if (!tree.getRoot()) return VoxelState::Unknown;
  unsigned from = 0;  // the deepest node of the last path that is this key's too
  if (reached_ >= 0) {
    if (key == last_) return last_state_;
    from = tree.shared_depth(to_octree_key(key), to_octree_key(last_), unsigned(reached_));
  } else {
    path_[0] = tree.getRoot();
  }
  last_ = key;
  reached_ = int(tree.descend(to_octree_key(key), path_, from));
  last_state_ = state_of(tree, tree.found_node(path_, unsigned(reached_)));
  return last_state_;
}

}  // namespace fvx::map
