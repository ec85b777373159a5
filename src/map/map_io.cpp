// Reading and writing maps as OctoMap files (.bt, .ot).
#include <octomap/AbstractOcTree.h>
#include <octomap/ColorOcTree.h>
#include <octomap/OcTreeStamped.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "fvx/core/atomic_file.hpp"
#include "fvx/core/capture_stderr.hpp"
#include "fvx/core/error.hpp"
#include "octree_stream.hpp"
#include "tree.hpp"

namespace fvx::map {
namespace {

/// OctoMap reports problems (and chatter such as " done.") with fprintf(stderr) and
/// std::cerr: what it said while it read or wrote becomes part of fvx's one-line error.
std::string octomap_said(CaptureStderr& capture) {
  const std::string t = capture.text();
  return t.empty() ? "" : " (OctoMap: " + t + ")";
}

void require_map_extension(const std::string& path) {
  const std::string ext = lowercase_extension(path);
  if (ext != ".bt" && ext != ".ot")
    throw FileError(path, "unknown map format '" + ext + "'; expected .bt or .ot");
}

}  // namespace

OccupancyMap OccupancyMap::load(const std::string& path) {
  require_map_extension(path);
  require_readable_file(path);
  std::ifstream in(path, std::ios::binary);
  CaptureStderr capture;
  const bool binary = lowercase_extension(path) == ".bt";

  std::string first_line;
  std::getline(in, first_line);
  in.seekg(0);
  if (first_line.rfind(binary ? "# Octomap OcTree binary file" : "# Octomap OcTree file", 0) != 0)
    throw FileError(path, binary ? "not an OctoMap binary (.bt) file" + octomap_said(capture) : "not an OctoMap .ot file");
  const OctreeHeader header = check_octree_stream(path, binary);

  if (binary) {
    Tree probe(0.1);
    // readBinary needs the resolution from the header; read into a probe tree, then move.
    if (!probe.readBinary(in) || in.bad() || (in.fail() && !in.eof()))
      throw FileError(path, "truncated or corrupt .bt file" + octomap_said(capture));
    if (in.fail()) throw FileError(path, "truncated .bt file" + octomap_said(capture));
    OccupancyMap map(probe.getResolution());
    map.impl_->tree.swapContent(probe);
    map.impl_->tree.check_inner_nodes();
    return map;
  }

  if (header.id == "OcTree") {
    // Read into the map's own tree, as AbstractOcTree::read would into an OcTree (the same
    // header, data only when the size is not 0): building OctoMap's tree and copying it node
    // by node took a third of loading a large .ot.
    OccupancyMap map(header.resolution_m);
    in.seekg(std::streamoff(header.data_at));
    if (header.size > 0) map.impl_->tree.readData(in);
    if (in.fail()) throw FileError(path, "truncated .ot file" + octomap_said(capture));
    map.impl_->tree.check_inner_nodes();
    return map;
  }
  std::unique_ptr<octomap::AbstractOcTree> tree(octomap::AbstractOcTree::read(in));
  if (!tree) throw FileError(path, "not a readable OctoMap .ot file" + octomap_said(capture));
  if (in.fail()) throw FileError(path, "truncated .ot file" + octomap_said(capture));
  OccupancyMap map(tree->getResolution());
  auto& mine = map.impl_->tree;
  if (auto* plain = dynamic_cast<octomap::OcTree*>(tree.get())) {
    mine.copy_from(*plain);
    mine.setProbHit(plain->getProbHit());
    mine.setProbMiss(plain->getProbMiss());
    mine.setClampingThresMin(plain->getClampingThresMin());
    mine.setClampingThresMax(plain->getClampingThresMax());
    mine.setOccupancyThres(plain->getOccupancyThres());
  } else if (auto* color = dynamic_cast<octomap::ColorOcTree*>(tree.get())) {
    mine.copy_from(*color);
  } else if (auto* stamped = dynamic_cast<octomap::OcTreeStamped*>(tree.get())) {
    mine.copy_from(*stamped);
  } else {
    throw FileError(path, "holds an OctoMap '" + tree->getTreeType() +
                              "', which is not an occupancy tree fvx can read");
  }
  mine.check_inner_nodes();
  return map;
}

void OccupancyMap::save(const std::string& path) const {
  require_map_extension(path);
  const bool binary = lowercase_extension(path) == ".bt";
  write_file_atomically(path, [&](std::ostream& out) {
    CaptureStderr capture;
    errno = 0;  // what a failed write leaves here says why (write_failure)
    bool ok;
    if (binary) {
      // writeBinary thresholds and prunes the tree it writes; do that on a copy so the map
      // keeps its probabilities.
      octomap::OcTree copy(impl_->tree);
      ok = copy.writeBinary(out);
    } else {
      ok = impl_->tree.write(out);
    }
    if (!ok || !out) throw FileError(path, "cannot write the map" + write_failure(errno) + octomap_said(capture));
  });
}

}  // namespace fvx::map
