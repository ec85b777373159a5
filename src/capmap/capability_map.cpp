#include "fvx/capmap/capability_map.hpp"

#include <algorithm>
#include <cmath>

#include "fvx/capmap/sample_shards.hpp"
#include "fvx/core/error.hpp"
#include "fvx/core/pose.hpp"

namespace fvx::capmap {

ArmConfig arm_config_of(const CapabilityHeader& h) {
  ArmConfig config{h.base_link, h.tip_link};
  const auto& m = h.mount_xyz_rpy;  // metres and radians
  config.T_tip_sensor = pose_from_xyz_rpy(m[0], m[1], m[2], m[3], m[4], m[5]);
  config.viewing_axis_sensor = h.viewing_axis;
  return config;
}

DirectionSet::DirectionSet(int count) {
  FVX_ASSERT(count >= 1, "a direction set needs directions");
  const double golden_angle = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / count;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = i * golden_angle;
    directions_.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
    radial_.push_back(std::sqrt(directions_.back().x() * directions_.back().x() + directions_.back().y() * directions_.back().y()));
  }
}

int DirectionSet::nearest(const Eigen::Vector3d& d) const {
  int best = 0;
  double best_dot = -2.0;
  for (int i = 0; i < size(); ++i) {
    const double dot = directions_[std::size_t(i)].dot(d);
    if (dot > best_dot) best_dot = dot, best = i;
  }
  return best;
}

int DirectionSet::nearest_banded(const Eigen::Vector3d& d, int hint) const {
  // z falls with the index (z_i = 1 − (2i + 1)/N); start at the index whose z is nearest d's
  // and walk both ways while the best dot the direction's polar angle allows,
  // cos(θᵢ − θ) = zᵢ·z + rᵢ·r, can still reach the best found (ties: the lower index, as in
  // nearest()). The bound falls monotonically away from θ, so each walk stops for good; a
  // hint near the answer narrows the band from the start.
  const int n = size();
  const double r = std::sqrt(std::max(0.0, 1.0 - d.z() * d.z()));
  const int start = std::clamp(int(std::lround(((1.0 - d.z()) * n - 1.0) / 2.0)), 0, n - 1);
  int best = -1;
  double best_dot = -2.0;
  const auto consider = [&](int i) {
    const double dot = directions_[std::size_t(i)].dot(d);
    if (dot > best_dot || (dot == best_dot && i < best)) best_dot = dot, best = i;
  };
  const auto bound = [&](int i) {  // + a margin for rounding
    return directions_[std::size_t(i)].z() * d.z() + radial_[std::size_t(i)] * r + 1e-12;
  };
  if (hint >= 0 && hint < n) consider(hint);
  consider(start);
  for (int step : {-1, 1})
    for (int i = start + step; i >= 0 && i < n && bound(i) >= best_dot; i += step) consider(i);
  return best;
}

std::vector<int> DirectionSet::within(const Eigen::Vector3d& d, double angle_rad) const {
  std::vector<int> out;
  const double min_dot = std::cos(angle_rad);
  for (int i = 0; i < size(); ++i)
    if (directions_[std::size_t(i)].dot(d) >= min_dot) out.push_back(i);
  return out;
}

double DirectionSet::mean_spacing_rad() const { return std::sqrt(4.0 * M_PI / size()); }

CapabilityMap::CapabilityMap(CapabilityHeader header) : header_(std::move(header)), directions_(header_.directions) {
  FVX_ASSERT(header_.voxel_m > 0.0, "voxel size");
  FVX_ASSERT(header_.shard_count >= 1 && header_.shard_index < header_.shard_count, "shard");
}

std::int64_t CapabilityMap::voxel_of(const Eigen::Vector3d& p) const {
  std::int64_t index = 0, stride = 1;
  for (int a = 0; a < 3; ++a) {
    const double c = std::floor((p[a] - header_.origin_m[a]) / header_.voxel_m);
    if (!(c >= 0.0) || c >= double(header_.dims[std::size_t(a)])) return -1;
    index += std::int64_t(c) * stride;
    stride *= std::int64_t(header_.dims[std::size_t(a)]);
  }
  return index;
}

Eigen::Vector3d CapabilityMap::center_of(std::int64_t voxel) const {
  const std::int64_t nx = header_.dims[0], ny = header_.dims[1];
  const Eigen::Vector3d cell(double(voxel % nx), double(voxel / nx % ny), double(voxel / (nx * ny)));
  return header_.origin_m + (cell.array() + 0.5).matrix() * header_.voxel_m;
}

void CapabilityMap::set(std::int64_t voxel, int direction) {
  FVX_ASSERT(voxel >= 0 && direction >= 0 && direction < directions_.size(), "bit out of range");
  auto& words = voxels_[voxel];
  if (words.empty()) words.assign(std::size_t((directions_.size() + 63) / 64), 0);
  words[std::size_t(direction / 64)] |= std::uint64_t(1) << (direction % 64);
}

void CapabilityMap::set_words(std::int64_t voxel, const std::uint64_t* words) {
  FVX_ASSERT(voxel >= 0, "voxel out of range");
  auto& mine = voxels_[voxel];
  if (mine.empty()) mine.assign(std::size_t((directions_.size() + 63) / 64), 0);
  for (std::size_t w = 0; w < mine.size(); ++w) mine[w] |= words[w];
}

void CapabilityMap::set_turn_witnesses(std::vector<TurnWitness> witnesses, double max_steps) {
  FVX_ASSERT(header_.layout == "turn", "witnesses of a turn layout");
  const DirectionSet relative(header_.turn.relative_directions);
  std::vector<std::pair<std::uint64_t, std::size_t>> order;
  for (std::size_t i = 0; i < witnesses.size(); ++i) order.emplace_back(turn_cell(header_.turn, relative, witnesses[i]), i);
  std::sort(order.begin(), order.end());
  turn_witnesses_.clear();
  for (const auto& entry : order) turn_witnesses_.push_back(witnesses[entry.second]);
  voxels_.clear();
  expand_turn_witnesses(header_.turn, turn_witnesses_, *this, max_steps);
}

bool CapabilityMap::reachable(std::int64_t voxel, int direction) const {
  const auto it = voxels_.find(voxel);
  return it != voxels_.end() && (it->second[std::size_t(direction / 64)] >> (direction % 64) & 1u);
}

bool CapabilityMap::reachable(const Eigen::Vector3d& p, const Eigen::Vector3d& d) const {
  const std::int64_t v = voxel_of(p);
  return v >= 0 && reachable(v, directions_.nearest(d));
}

std::vector<int> CapabilityMap::reachable_directions(const Eigen::Vector3d& p) const {
  std::vector<int> out;
  const auto it = voxels_.find(voxel_of(p));
  if (it == voxels_.end()) return out;
  for (int i = 0; i < directions_.size(); ++i)
    if (it->second[std::size_t(i / 64)] >> (i % 64) & 1u) out.push_back(i);
  return out;
}

Eigen::AlignedBox3d CapabilityMap::reachable_box_base() const {
  Eigen::AlignedBox3d box;
  const Eigen::Vector3d half = Eigen::Vector3d::Constant(0.5 * header_.voxel_m);
  for (const auto& [voxel, words] : voxels_)
    if (std::any_of(words.begin(), words.end(), [](std::uint64_t w) { return w != 0; })) {
      box.extend(center_of(voxel) - half);
      box.extend(center_of(voxel) + half);
    }
  return box;
}

std::vector<Eigen::Vector3d> CapabilityMap::reachable_directions(const Eigen::Isometry3d& T_world_base,
                                                                const Eigen::Vector3d& p_world) const {
  std::vector<Eigen::Vector3d> out;
  for (int i : reachable_directions(T_world_base.inverse() * p_world)) out.push_back(T_world_base.linear() * directions_[i]);
  return out;
}

double CapabilityMap::reachability_index(const Eigen::Vector3d& p) const {
  const auto it = voxels_.find(voxel_of(p));
  if (it == voxels_.end()) return 0.0;
  int reachable = 0;  // pruning asks this of every cell with utility: count bits, build nothing
  for (const std::uint64_t word : it->second) reachable += __builtin_popcountll(word);
  return 100.0 * double(reachable) / directions_.size();
}

namespace {

bool same_turn(const TurnFrame& a, const TurnFrame& b) {
  return a.point_base == b.point_base && a.axis_base == b.axis_base && a.x_base == b.x_base &&
         a.lower_rad == b.lower_rad && a.upper_rad == b.upper_rad && a.cell_m == b.cell_m &&
         a.relative_directions == b.relative_directions;
}

}  // namespace

/// Samples shards (checked alike by merge): the bits the stop rule keeps of their union, in a
/// map whose header is the single build's.
CapabilityMap CapabilityMap::merge_sample_shards(const std::vector<CapabilityMap>& shards) {
  CapabilityHeader joined = shards.front().header_;
  joined.shard_index = 0, joined.shard_count = 1;
  joined.shard_split = "slab", joined.target_recall = 0, joined.fk_samples = 0;
  CapabilityMap out(joined);
  std::vector<const std::vector<SampleRound>*> rounds;
  for (const CapabilityMap& shard : shards) rounds.push_back(&shard.sample_rounds_);
  const std::int64_t directions = joined.directions;
  const std::size_t bits = std::size_t(joined.dims[0]) * joined.dims[1] * joined.dims[2] * std::size_t(directions);
  const CapabilityHeader& h = shards.front().header_;
  const std::vector<std::uint64_t> set = replay_sample_rounds(rounds, bits, h.target_recall, h.fk_samples);
  std::vector<std::uint64_t> words(std::size_t((directions + 63) / 64));  // one voxel's, set at once
  std::int64_t voxel = -1;
  for (std::size_t w = 0; w <= set.size(); ++w)
    for (std::uint64_t word = w < set.size() ? set[w] : 0; word || w == set.size(); word &= word - 1) {
      const std::int64_t b = w < set.size() ? std::int64_t(w * 64 + std::size_t(__builtin_ctzll(word))) : -1;
      if (voxel >= 0 && (b < 0 || b / directions != voxel)) {
        out.set_words(voxel, words.data());
        std::fill(words.begin(), words.end(), 0);
      }
      if (b < 0) break;
      voxel = b / directions;
      words[std::size_t(b % directions / 64)] |= std::uint64_t(1) << (b % directions % 64);
    }
  return out;
}

CapabilityMap CapabilityMap::merge(const std::vector<CapabilityMap>& shards) {
  if (shards.empty()) throw Error("no shards to merge");
  const CapabilityHeader& first = shards.front().header_;
  std::vector<bool> seen(first.shard_count, false);
  CapabilityHeader joined = first;
  joined.shard_index = 0;
  joined.shard_count = 1;
  CapabilityMap out(joined);
  std::vector<TurnWitness> witnesses;  // turn layout: each shard's height cells, joined
  for (const CapabilityMap& shard : shards) {
    const CapabilityHeader& b = shard.header_;
    if (first.urdf_hash != b.urdf_hash || first.base_link != b.base_link || first.tip_link != b.tip_link ||
        first.mount_xyz_rpy != b.mount_xyz_rpy || first.voxel_m != b.voxel_m || first.origin_m != b.origin_m ||
        first.dims != b.dims || first.directions != b.directions || first.seed != b.seed ||
        first.method != b.method || first.shard_count != b.shard_count ||
        first.position_tolerance_m != b.position_tolerance_m || first.angle_tolerance_rad != b.angle_tolerance_rad ||
        first.layout != b.layout || !same_turn(first.turn, b.turn) || first.shard_split != b.shard_split ||
        first.target_recall != b.target_recall || first.fk_samples != b.fk_samples)
      throw Error("the shards were not made from the same arm and settings; they cannot be merged");
    if (seen[b.shard_index]) throw Error("shard " + std::to_string(b.shard_index + 1) + " is given twice");
    seen[b.shard_index] = true;
    witnesses.insert(witnesses.end(), shard.turn_witnesses_.begin(), shard.turn_witnesses_.end());
    if (first.shard_split == "samples") continue;  // their rounds decide the bits
    for (const auto& [voxel, words] : shard.voxels_) {
      auto& mine = out.voxels_[voxel];
      if (mine.empty()) mine.assign(words.size(), 0);
      for (std::size_t w = 0; w < words.size(); ++w) mine[w] |= words[w];
    }
  }
  for (std::uint32_t i = 0; i < first.shard_count; ++i)
    if (!seen[i]) throw Error("shard " + std::to_string(i + 1) + " of " + std::to_string(first.shard_count) + " is missing");
  if (joined.layout == "turn") out.set_turn_witnesses(std::move(witnesses));
  if (joined.shard_split == "samples") return merge_sample_shards(shards);
  return out;
}

}  // namespace fvx::capmap
