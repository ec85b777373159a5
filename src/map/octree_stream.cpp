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

struct Header {
  std::string id;
  long long size = -1;  ///< nodes (.ot: held to it; .bt: only 0, an empty tree, is used)
  std::size_t data_at = 0;
};

/// The header lines up to "data" (OctoMap's own keys; comments start with '#').
Header read_header(const std::string& path, const std::string& bytes) {
  Header h;
  std::istringstream in(bytes);
  std::string line;
  bool res = false;
  for (int n = 0; n < 1000 && std::getline(in, line); ++n) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "id") words >> h.id;
    else if (key == "size") words >> h.size;
    else if (key == "res") res = true;
    else if (key == "data") {
      if (h.id.empty() || !res) throw FileError(path, "corrupt OctoMap header: no id or res before data");
      h.data_at = std::size_t(in.tellg());
      return h;
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

void check_octree_stream(const std::string& path, bool binary) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  const Header h = read_header(path, bytes);
  const std::size_t value_bytes = binary ? 0 : node_bytes(path, h.id);
  if (h.size == 0) return;  // OctoMap reads no data for an empty tree
  long long nodes = 0;
  std::size_t end = 0;
  if (binary) {
    end = walk_binary(path, bytes, h.data_at, nodes);
  } else {
    end = walk_full(path, bytes, h.data_at, value_bytes, nodes);
    if (h.size >= 0 && nodes != h.size)
      throw FileError(path, "corrupt OctoMap data: " + std::to_string(nodes) + " nodes, the header says " +
                                std::to_string(h.size));
  }
  if (end != bytes.size())
    throw FileError(path, "corrupt OctoMap data: " + std::to_string(bytes.size() - end) +
                              " bytes after the last node of the tree");
}

}  // namespace fvx::map
