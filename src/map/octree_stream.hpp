#pragma once
// Walks the node stream of a .bt or .ot file the way OctoMap reads it, without building a tree,
// before OctoMap reads it: OctoMap's readers recurse without a depth or node limit, so one
// flipped bit in a child mask made it read garbage for seconds into gigabytes (or overflow the
// stack). Here an explicit stack, depth ≤ 16, and the stream must end with the last node.
#include <string>

namespace fvx::map {

/// FileError naming what is wrong: a header without id/res/data, a tree type fvx does not read
/// (.ot), a node below depth 16, a node count other than the header's size (.ot), or data that
/// ends before the last node or goes on after it.
void check_octree_stream(const std::string& path, bool binary);

}  // namespace fvx::map
