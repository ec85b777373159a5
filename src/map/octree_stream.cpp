#include "octree_stream.hpp"

#include <cstdint>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

#include "fvx/core/error.hpp"

namespace fvx::map {
namespace {

constexpr int kTreeDepth = 16;  // OctoMap's key depth: nodes at depth 16 are leaves

using Header = OctreeHeader;

/// The header up to "data", read token by token as OctoMap's AbstractOcTree::readHeader reads
/// it, so that the walk starts where OctoMap will: a line-based reading took "res 0.4data" for
/// a res line and started elsewhere (a fuzzed .bt then made OctoMap recurse past the stack).
Header read_header(const std::string& path, const std::string& bytes) {
  Header h;
  std::istringstream in(bytes);
  const auto skip_line = [&] {
    for (int c = 0; in.good() && c != '\n';) c = in.get();
  };
  bool res = false;
  std::string token;
  while (in.good()) {
    in >> token;  // as OctoMap: a failed read leaves the last token
    if (token == "data") {
      skip_line();
      if (h.id.empty() || !res) throw FileError(path, "corrupt OctoMap header: no id or res before data");
      if (h.id == "1") h.id = "OcTree";  // OctoMap's deprecated id
      const std::streamoff at = in.tellg();  // -1 when the data line was the file's last
      h.data_at = at < 0 ? bytes.size() : std::size_t(at);
      return h;
    }
    if (token.compare(0, 1, "#") == 0) {
      skip_line();
    } else if (token == "id") {
      in >> h.id;
    } else if (token == "res") {
      double value = 0.0;
      in >> value;
      res = value > 0.0;
      h.resolution_m = value;
    } else if (token == "size") {
      unsigned value = 0;
      in >> value;
      h.size = value;
    } else {
      skip_line();  // OctoMap warns and skips a keyword it does not know
    }
  }
  throw FileError(path, "corrupt OctoMap header: no data line");
}

/// Bytes per node of an .ot tree type: its value (log-odds float) and what the type adds.
std::size_t node_bytes(const std::string& path, const std::string& id) {
  if (id == "OcTree") return 4;
  if (id == "ColorOcTree") return 4 + 3;
  if (id == "OcTreeStamped") return 4 + 4;
  throw FileError(path, "holds an OctoMap '" + id + "', which is not an occupancy tree fvx can read");
}

[[noreturn]] void ends_early(const std::string& path) {
  throw FileError(path, "truncated or corrupt OctoMap data: it ends inside the tree");
}

/// A pre-order walk with an explicit stack (no recursion to overflow): `read_node(depth)`
/// consumes one node and returns how many children follow it, each with its subtree.
template <typename ReadNode>
void walk(ReadNode read_node) {
  std::vector<std::pair<int, int>> stack = {{0, 1}};  // (depth, nodes still to read at it)
  while (!stack.empty()) {
    if (stack.back().second == 0) {
      stack.pop_back();
      continue;
    }
    --stack.back().second;
    const int depth = stack.back().first;
    if (const int children = read_node(depth)) stack.push_back({depth + 1, children});
  }
}

/// .ot: each node is its value, a child mask, then its children in order.
std::size_t walk_full(const std::string& path, const std::string& bytes, std::size_t at, std::size_t value_bytes,
                      long long& nodes) {
  walk([&](int depth) {
    if (at + value_bytes + 1 > bytes.size()) ends_early(path);
    const auto mask = std::uint8_t(bytes[at + value_bytes]);
    at += value_bytes + 1;
    ++nodes;
    if (mask && depth >= kTreeDepth) throw FileError(path, "corrupt OctoMap data: a node below depth 16");
    return __builtin_popcount(mask);
  });
  return at;
}

/// .bt: each inner node is 2 bytes of 2-bit child codes (01 and 10 leaves, 11 an inner node
/// whose codes follow, 00 none).
std::size_t walk_binary(const std::string& path, const std::string& bytes, std::size_t at, long long& nodes) {
  walk([&](int depth) {
    if (at + 2 > bytes.size()) ends_early(path);
    const unsigned codes = unsigned(std::uint8_t(bytes[at])) | unsigned(std::uint8_t(bytes[at + 1])) << 8;
    at += 2;
    ++nodes;
    int inner = 0;
    for (int i = 0; i < 8; ++i) {
      const unsigned code = codes >> (2 * i) & 3u;
      nodes += code == 1 || code == 2;
      inner += code == 3;
    }
    if (inner && depth + 1 >= kTreeDepth) throw FileError(path, "corrupt OctoMap data: a node below depth 16");
    return inner;
  });
  return at;
}

}  // namespace

OctreeHeader check_octree_stream(const std::string& path, bool binary) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  const Header h = read_header(path, bytes);
  const std::size_t value_bytes = binary ? 0 : node_bytes(path, h.id);
  if (h.size == 0) return h;  // OctoMap reads no data for an empty tree
  long long nodes = 0;
  std::size_t end = 0;
  if (binary) {
    end = walk_binary(path, bytes, h.data_at, nodes);
  } else {
    end = walk_full(path, bytes, h.data_at, value_bytes, nodes);
    if (nodes != h.size)
      throw FileError(path, "corrupt OctoMap data: " + std::to_string(nodes) + " nodes, the header says " +
                                std::to_string(h.size));
  }
  if (end != bytes.size())
    throw FileError(path, "corrupt OctoMap data: " + std::to_string(bytes.size() - end) +
                              " bytes after the last node of the tree");
  return h;
}

}  // namespace fvx::map
