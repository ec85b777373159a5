#pragma once
/// \file
/// Stage `capmap`, part 2: the capability map (Zacharias, Borst, Hirzinger, IROS 2007) and
/// its file. A voxel grid around the arm base; in each voxel N viewing directions on a
/// golden-angle spiral; a bit per direction says whether some configuration puts the sensor
/// in the voxel with its viewing axis in the direction's cell (fk-witness, the default) or
/// whether IK reaches the voxel centre looking along it (the IK methods), roll free
/// (ARCHITECTURE.md §3). A 5-DOF arm reaches only an arc of directions at
/// each point, so the bitset is the data; the reachability index is 100 · reachable / N.
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "fvx/capmap/arm.hpp"
#include "fvx/capmap/turn_layout.hpp"

namespace fvx::capmap {

/// N unit directions on a golden-angle spiral: d_i = (r cos φ_i, r sin φ_i, z_i) with
/// z_i = 1 − (2i + 1)/N, r = sqrt(1 − z_i²), φ_i = i · π(3 − √5).
class DirectionSet {
 public:
  explicit DirectionSet(int count);
  int size() const { return int(directions_.size()); }
  const Eigen::Vector3d& operator[](int i) const { return directions_[std::size_t(i)]; }
  /// The index of the direction nearest to `d` (unit); brute force over N, about 0.2 µs at 200.
  int nearest(const Eigen::Vector3d& d) const;
  /// The same index as nearest(), searching only the directions whose polar angle is close
  /// enough to beat the best found (|θᵢ − θ| ≤ the angle to it): about N/4 dot products
  /// instead of N, fewer with `hint` (an index near the answer, e.g. the last one of a
  /// sweep). `d` may be off unit length by rounding (a rotated unit axis). The oracle of it
  /// is nearest() (test).
  int nearest_banded(const Eigen::Vector3d& d, int hint = -1) const;
  /// The indices of the directions within `angle_rad` of `d` (unit), ascending.
  std::vector<int> within(const Eigen::Vector3d& d, double angle_rad) const;
  /// sqrt(4π / N): the mean angular spacing, radians.
  double mean_spacing_rad() const;

 private:
  std::vector<Eigen::Vector3d> directions_;
  std::vector<double> radial_;  ///< sqrt(x² + y²) of each direction (nearest_banded's bound)
};

/// Everything a map file says about how it was made.
struct CapabilityHeader {
  std::string base_link, tip_link;
  std::array<double, 6> mount_xyz_rpy{};           ///< the sensor mount after the tip
  Eigen::Vector3d viewing_axis = Eigen::Vector3d::UnitZ();
  std::string urdf_hash;
  double voxel_m = 0.05;
  Eigen::Vector3d origin_m = Eigen::Vector3d::Zero();  ///< the grid's minimum corner, base frame
  std::array<std::uint32_t, 3> dims{{0, 0, 0}};        ///< voxels along x, y, z
  int directions = 200;
  double position_tolerance_m = 0.005;
  double angle_tolerance_rad = 0.125;
  std::string method;                               ///< how bits were decided, e.g. "fk-seeded-ik"
  std::uint64_t seed = 1;
  std::uint32_t shard_index = 0, shard_count = 1;   ///< which voxels this file holds (z-slabs)
  /// "slab": a shard holds its z-slab's bits (a turn shard its height cells); "samples":
  /// fk-witness grid only, a shard holds its share of the witnesses' rounds (SampleRound,
  /// format version 4), and the merge applies the stop rule — `target_recall` within the
  /// budget of `fk_samples` configurations — to their union. Both are in the header of
  /// samples shards only.
  std::string shard_split = "slab";
  double target_recall = 0;
  std::uint64_t fk_samples = 0;
  std::string fvx_version;
  /// "grid": bits per voxel (format version 2); "turn": one witness per reduced cell of the
  /// first joint's turn (turn_layout.hpp, format version 3), expanded into the bits on load.
  /// A turn layout's shard holds the witnesses whose height cell is ≡ shard_index mod count.
  std::string layout = "grid";
  TurnFrame turn;  ///< the turn layout's frame and cells
};

/// What a samples shard (CapabilityHeader::shard_split) drew in one round of the fk-witness
/// build: its configurations, how many landed on bits its earlier rounds had set, and the
/// others that landed in the grid, as (bit = voxel · N + direction, configurations) in bit
/// order. Enough to tell, with the other shards, how many of the round landed on bits set
/// before it by any shard: the build's estimate of the recall.
struct SampleRound {
  std::uint64_t samples = 0, known = 0;
  std::vector<std::pair<std::int64_t, std::uint32_t>> fresh;
};

/// The arm settings a map was built with (links, mount, viewing axis), to load its URDF again.
ArmConfig arm_config_of(const CapabilityHeader& header);

class CapabilityMap {
 public:
  explicit CapabilityMap(CapabilityHeader header);

  const CapabilityHeader& header() const { return header_; }
  const DirectionSet& directions() const { return directions_; }
  std::size_t voxel_count() const { return voxels_.size(); }  ///< non-empty voxels

  /// The voxel containing `p_base`, or −1 outside the grid.
  std::int64_t voxel_of(const Eigen::Vector3d& p_base) const;
  Eigen::Vector3d center_of(std::int64_t voxel) const;

  void set(std::int64_t voxel, int direction);
  /// ORs a voxel's ceil(N/64) direction words into its bits.
  void set_words(std::int64_t voxel, const std::uint64_t* words);
  /// Turn layout: keeps the witnesses (one per reduced cell), sorted by turn_cell, and
  /// expands them into the bits (expand_turn_witnesses, at most `max_steps` steps).
  void set_turn_witnesses(std::vector<TurnWitness> witnesses, double max_steps = INFINITY);
  const std::vector<TurnWitness>& turn_witnesses() const { return turn_witnesses_; }
  /// Samples shard: its rounds. It holds no bits: the merge decides which of the bits the
  /// rounds landed on the build keeps.
  void set_sample_rounds(std::vector<SampleRound> rounds) { sample_rounds_ = std::move(rounds); }
  const std::vector<SampleRound>& sample_rounds() const { return sample_rounds_; }
  bool reachable(std::int64_t voxel, int direction) const;
  /// Is `p_base` reachable looking along `d_base` (unit)? Nearest voxel, nearest direction.
  bool reachable(const Eigen::Vector3d& p_base, const Eigen::Vector3d& d_base) const;
  /// The same for a map placed in the world at `T_world_base` (the arm's base pose): is the
  /// world-frame position reachable looking along the world-frame direction?
  bool reachable(const Eigen::Isometry3d& T_world_base, const Eigen::Vector3d& p_world,
                 const Eigen::Vector3d& d_world) const {
    return reachable(T_world_base.inverse() * p_world, T_world_base.linear().transpose() * d_world);
  }
  /// The reachable directions at a world-frame position, in the world frame.
  std::vector<Eigen::Vector3d> reachable_directions(const Eigen::Isometry3d& T_world_base,
                                                    const Eigen::Vector3d& p_world) const;
  /// 100 · reachable directions / N in the voxel of `p_base` (0 outside).
  double reachability_index(const Eigen::Vector3d& p_base) const;
  /// The reachable direction indices there.
  std::vector<int> reachable_directions(const Eigen::Vector3d& p_base) const;
  /// The box of the voxels (as cubes, base frame) with a reachable direction: outside it the
  /// reachability index is 0. Empty when no voxel has one.
  Eigen::AlignedBox3d reachable_box_base() const;

  /// Non-empty voxels in index order with their bitsets (64 bits per word).
  const std::map<std::int64_t, std::vector<std::uint64_t>>& voxels() const { return voxels_; }

  /// Joins shards 0 … n−1 of one build (same arm and settings) into the map a single run
  /// makes: its header says shard 0 of 1. Samples shards: the rounds of all shards in order,
  /// each round's estimate from the bits set before it, until the estimate reaches the
  /// target (round > 0) or the budget ends, as the single build stops. Throws Error for
  /// missing, repeated or foreign shards.
  static CapabilityMap merge(const std::vector<CapabilityMap>& shards);

  /// Writes `.fcm`, atomically. Format in man/fvx-capmap.5.
  void save(const std::string& path) const;
  /// Reads `.fcm`; FileError for a wrong magic or version, a truncated file or a checksum
  /// mismatch.
  static CapabilityMap load(const std::string& path);

 private:
  static CapabilityMap merge_sample_shards(const std::vector<CapabilityMap>& shards);

  CapabilityHeader header_;
  DirectionSet directions_;
  std::map<std::int64_t, std::vector<std::uint64_t>> voxels_;
  std::vector<TurnWitness> turn_witnesses_;
  std::vector<SampleRound> sample_rounds_;
};

}  // namespace fvx::capmap
