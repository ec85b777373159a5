#include <algorithm>
#include <cmath>

#include "fvx/core/error.hpp"
#include "fvx/map/sort_keys.hpp"
#include "tree.hpp"

namespace fvx::map {

const char* to_string(VoxelState state) {
  switch (state) {
    case VoxelState::Unknown: return "unknown";
    case VoxelState::Free: return "free";
    case VoxelState::Occupied: return "occupied";
  }
  return "?";
}

const char* to_string(RayOutcome outcome) {
  switch (outcome) {
    case RayOutcome::Hit: return "hit";
    case RayOutcome::Unknown: return "unknown";
    case RayOutcome::MaxRange: return "max_range";
    case RayOutcome::OutOfBounds: return "out_of_bounds";
  }
  return "?";
}

std::vector<std::string> SensorModel::validate() const {
  std::vector<std::string> problems;
  auto in_unit = [](double p) { return p > 0.0 && p < 1.0; };
  if (!in_unit(prob_hit) || prob_hit <= 0.5) problems.push_back("prob_hit must be in (0.5, 1)");
  if (!in_unit(prob_miss) || prob_miss >= 0.5) problems.push_back("prob_miss must be in (0, 0.5)");
  if (!in_unit(clamp_min) || !in_unit(clamp_max) || clamp_min >= clamp_max)
    problems.push_back("clamping bounds must satisfy 0 < clamp_min < clamp_max < 1");
  if (!in_unit(occupancy_threshold)) problems.push_back("occupancy_threshold must be in (0, 1)");
  return problems;
}

OccupancyMap::OccupancyMap(double resolution_m, const SensorModel& model) {
  FVX_ASSERT(resolution_m > 0.0 && std::isfinite(resolution_m),
             "resolution " + std::to_string(resolution_m));
  throw_if_problems("sensor model", model.validate());
  impl_ = std::make_unique<Impl>(resolution_m);
  auto& tree = impl_->tree;
  tree.setProbHit(model.prob_hit);
  tree.setProbMiss(model.prob_miss);
  tree.setClampingThresMin(model.clamp_min);
  tree.setClampingThresMax(model.clamp_max);
  tree.setOccupancyThres(model.occupancy_threshold);
}

OccupancyMap::~OccupancyMap() = default;
OccupancyMap::OccupancyMap(OccupancyMap&&) noexcept = default;
OccupancyMap& OccupancyMap::operator=(OccupancyMap&&) noexcept = default;

double OccupancyMap::resolution_m() const { return impl_->tree.getResolution(); }

SensorModel OccupancyMap::sensor_model() const {
  const auto& tree = impl_->tree;
  SensorModel model;
  model.prob_hit = tree.getProbHit();
  model.prob_miss = tree.getProbMiss();
  model.clamp_min = tree.getClampingThresMin();
  model.clamp_max = tree.getClampingThresMax();
  model.occupancy_threshold = tree.getOccupancyThres();
  return model;
}

IntegrationCounts counts(const Integration& integration) {
  IntegrationCounts c;
  c.changed_cells = integration.changes.size();
  for (const Change& change : integration.changes) {
    c.became_free += change.after == VoxelState::Free;
    c.became_occupied += change.after == VoxelState::Occupied;
  }
  c.points_beyond_range = integration.points_beyond_range;
  c.points_out_of_map = integration.points_out_of_map;
  c.free_updates = integration.free_updates;
  c.occupied_updates = integration.occupied_updates;
  return c;
}

std::optional<VoxelKey> OccupancyMap::key_of(const Eigen::Vector3d& p_world) const {
  octomap::OcTreeKey key;
  if (!p_world.allFinite() ||
      !impl_->tree.coordToKeyChecked(p_world.x(), p_world.y(), p_world.z(), key))
    return std::nullopt;
  return to_voxel_key(key);
}

Eigen::Vector3d OccupancyMap::center_of(const VoxelKey& key) const {
  const auto& tree = impl_->tree;
  return {tree.keyToCoord(key.x), tree.keyToCoord(key.y), tree.keyToCoord(key.z)};
}

VoxelState OccupancyMap::state(const VoxelKey& key) const {
  return state_of(impl_->tree, impl_->tree.search(to_octree_key(key)));
}

std::optional<double> OccupancyMap::probability(const VoxelKey& key) const {
  const octomap::OcTreeNode* node = impl_->tree.search(to_octree_key(key));
  if (!node) return std::nullopt;
  return node->getOccupancy();
}

void OccupancyMap::set_state(const VoxelKey& key, VoxelState state) {
  auto& tree = impl_->tree;
  const octomap::OcTreeKey k = to_octree_key(key);
  if (state == VoxelState::Unknown)
    tree.deleteNode(k);
  else
    tree.setNodeValue(k, state == VoxelState::Occupied ? tree.getClampingThresMaxLog() : tree.getClampingThresMinLog());
}

RayCast OccupancyMap::cast_ray(const RayQuery& query) const {
  FVX_ASSERT(query.direction_world.allFinite() && query.direction_world.norm() > 1e-12,
             "ray direction must be finite and non-zero");
  FVX_ASSERT(!(query.max_range_m < 0.0), "max range " + std::to_string(query.max_range_m));
  RayCast cast;
  const auto origin_key = key_of(query.origin_world);
  if (!origin_key) return cast;  // OutOfBounds at distance 0

  const double R = resolution_m();
  const Eigen::Vector3d dir = query.direction_world.normalized();
  const Eigen::Vector3d cell_center = center_of(*origin_key);
  int key[3] = {origin_key->x, origin_key->y, origin_key->z};
  int step[3];
  double t_max[3], t_delta[3];
  for (int i = 0; i < 3; ++i) {
    step[i] = dir[i] > 0 ? 1 : (dir[i] < 0 ? -1 : 0);
    if (step[i] == 0) {
      t_max[i] = t_delta[i] = std::numeric_limits<double>::infinity();
    } else {
      const double border = cell_center[i] + 0.5 * R * step[i];
      t_max[i] = (border - query.origin_world[i]) / dir[i];
      t_delta[i] = R / std::abs(dir[i]);
    }
  }

  double t = 0.0;
  while (true) {
    cast.key = {std::uint16_t(key[0]), std::uint16_t(key[1]), std::uint16_t(key[2])};
    cast.distance_m = t;
    const VoxelState s = state(cast.key);
    if (s == VoxelState::Occupied) {
      cast.outcome = RayOutcome::Hit;
      return cast;
    }
    if (s == VoxelState::Unknown && !query.pass_unknown) {
      cast.outcome = RayOutcome::Unknown;
      return cast;
    }
    const int axis = t_max[0] < t_max[1] ? (t_max[0] < t_max[2] ? 0 : 2) : (t_max[1] < t_max[2] ? 1 : 2);
    t = t_max[axis];
    if (t > query.max_range_m) {
      cast.outcome = RayOutcome::MaxRange;
      cast.distance_m = query.max_range_m;
      return cast;
    }
    key[axis] += step[axis];
    t_max[axis] += t_delta[axis];
    if (key[axis] < 0 || key[axis] > 0xFFFF) {
      cast.outcome = RayOutcome::OutOfBounds;
      cast.distance_m = t;
      return cast;
    }
  }
}

std::vector<Eigen::Vector3f> OccupancyMap::occupied_centers() const {
  const auto& tree = impl_->tree;
  std::vector<VoxelKey> keys;
  const unsigned max_depth = tree.getTreeDepth();
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    // A pruned leaf at depth d covers 2^(16−d) finest cells per axis, starting at the key
    // with the low bits cleared.
    const unsigned span = 1u << (max_depth - it.getDepth());
    const octomap::OcTreeKey k = it.getKey();
    const unsigned mask = ~(span - 1u);
    const unsigned x0 = k[0] & mask, y0 = k[1] & mask, z0 = k[2] & mask;
    for (unsigned dz = 0; dz < span; ++dz)
      for (unsigned dy = 0; dy < span; ++dy)
        for (unsigned dx = 0; dx < span; ++dx)
          keys.push_back({std::uint16_t(x0 + dx), std::uint16_t(y0 + dy), std::uint16_t(z0 + dz)});
  }
  sort_keys(keys);
  std::vector<Eigen::Vector3f> centers;
  centers.reserve(keys.size());
  for (const auto& k : keys) centers.push_back(center_of(k).cast<float>());
  return centers;
}

namespace {

/// The leaf under a leaf iterator (of either kind): its lowest finest cell, span and state.
template <typename Iterator>
Leaf leaf_at(const octomap::OcTree& tree, const Iterator& it) {
  const std::uint32_t span = 1u << (tree.getTreeDepth() - it.getDepth());
  const octomap::OcTreeKey k = it.getKey();
  const std::uint32_t mask = ~(span - 1u);
  return {{std::uint16_t(k[0] & mask), std::uint16_t(k[1] & mask), std::uint16_t(k[2] & mask)},
          span,
          tree.isNodeOccupied(*it) ? VoxelState::Occupied : VoxelState::Free};
}

}  // namespace

std::vector<Leaf> OccupancyMap::leaves() const {
  const auto& tree = impl_->tree;
  std::vector<Leaf> out;
  out.reserve(tree.getNumLeafNodes());
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) out.push_back(leaf_at(tree, it));
  return out;
}

std::vector<Leaf> OccupancyMap::leaves(const VoxelKey& lo, const VoxelKey& hi) const {
  const auto& tree = impl_->tree;
  std::vector<Leaf> out;
  const octomap::OcTreeKey min(lo.x, lo.y, lo.z), max(hi.x, hi.y, hi.z);
  // OctoMap's bbx iterator tests a node's overlap with its upper bound one cell too far
  // (centre + half span, OcTreeIterator.hxx), so it also yields a leaf that ends just below
  // lo; keep only the leaves that hold a cell of the box.
  const auto reaches = [&](const Leaf& l) {
    const std::uint32_t a[3] = {l.min_key.x, l.min_key.y, l.min_key.z}, b[3] = {lo.x, lo.y, lo.z};
    for (int d = 0; d < 3; ++d)
      if (a[d] + l.size_cells <= b[d]) return false;
    return true;
  };
  for (auto it = tree.begin_leafs_bbx(min, max), end = tree.end_leafs_bbx(); it != end; ++it) {
    const Leaf leaf = leaf_at(tree, it);
    if (reaches(leaf)) out.push_back(leaf);
  }
  return out;
}

Stats OccupancyMap::stats() const {
  const auto& tree = impl_->tree;
  Stats s;
  s.resolution_m = tree.getResolution();
  s.nodes = tree.size();
  Eigen::AlignedBox3d box;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    const double size = it.getSize();
    const double volume = size * size * size;
    if (tree.isNodeOccupied(*it)) {
      ++s.occupied_leaves;
      s.occupied_volume_m3 += volume;
    } else {
      ++s.free_leaves;
      s.free_volume_m3 += volume;
    }
    const octomap::point3d c = it.getCoordinate();
    const Eigen::Vector3d center(c.x(), c.y(), c.z());
    box.extend(center - Eigen::Vector3d::Constant(size / 2));
    box.extend(center + Eigen::Vector3d::Constant(size / 2));
  }
  s.empty = box.isEmpty();
  if (!s.empty) {
    s.known_min_m = box.min();
    s.known_max_m = box.max();
  }
  return s;
}

std::vector<VoxelKey> keys_within(const OccupancyMap& map, std::vector<VoxelKey> keys,
                                  const Eigen::AlignedBox3d& bounds_m) {
  keys.erase(std::remove_if(keys.begin(), keys.end(),
                            [&](const VoxelKey& k) { return !bounds_m.contains(map.center_of(k)); }),
             keys.end());
  return keys;
}

}  // namespace fvx::map
