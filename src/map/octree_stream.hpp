#pragma once
// Walks the node stream of a .bt or .ot file the way OctoMap reads it, without building a tree,
// before OctoMap reads it: OctoMap's readers recurse without a depth or node limit, so one
// flipped bit in a child mask made it read garbage for seconds into gigabytes (or overflow the
// stack). Here an explicit stack, depth ≤ 16, and the stream must end with the last node.
#include <string>

namespace fvx::map {

/// What the header says, as OctoMap's AbstractOcTree::readHeader reads it.
struct OctreeHeader {
  std::string id;  ///< the tree type ("OcTree" also for OctoMap's deprecated id "1")
  long long size = 0;  ///< nodes (.ot: held to it); 0, also without a size line, reads no data, as OctoMap
  double resolution_m = 0.0;
  std::size_t data_at = 0;  ///< the byte where the node data starts
};

/// FileError naming what is wrong: a header without id/res/data, a tree type fvx does not read
/// (.ot), a node below depth 16, a node count other than the header's size (.ot), or data that
/// ends before the last node or goes on after it. Returns the header.
OctreeHeader check_octree_stream(const std::string& path, bool binary);

}  // namespace fvx::map
