#pragma once
/// \file
/// Stage `map` (paper §IV step 3): a probabilistic occupancy map. The facade hides
/// octomap::OcTree (the file format and current store) so that the integration path can be
/// replaced without touching callers. `integrate()` returns the change set that the
/// incremental frontier and void sets consume.
#include <Eigen/Geometry>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace octomap {
class OcTreeNode;
}

namespace fvx::map {

/// Tri-state cell state: a cell without data is Unknown; otherwise its occupancy probability
/// against the threshold decides Free or Occupied.
enum class VoxelState : std::uint8_t { Unknown, Free, Occupied };
const char* to_string(VoxelState state);

/// Integer cell address at the finest level (OctoMap's key space: 16 bits per axis, the
/// origin at key 32768, cell i covering [ (i − 32768)·R, (i − 32767)·R )).
struct VoxelKey {
  std::uint16_t x = 0, y = 0, z = 0;
  friend bool operator==(const VoxelKey& a, const VoxelKey& b) {
    return a.x == b.x && a.y == b.y && a.z == b.z;
  }
  friend bool operator!=(const VoxelKey& a, const VoxelKey& b) { return !(a == b); }
  /// Lexicographic on (z, y, x): the order of change sets and reports.
  friend bool operator<(const VoxelKey& a, const VoxelKey& b) {
    if (a.z != b.z) return a.z < b.z;
    if (a.y != b.y) return a.y < b.y;
    return a.x < b.x;
  }
};

/// One cell whose state an integration changed.
struct Change {
  VoxelKey key;
  VoxelState before = VoxelState::Unknown;
  VoxelState after = VoxelState::Unknown;
};

/// Result of integrate(): the change set (sorted by key, only cells whose state changed) and
/// counts of what the scan did.
struct Integration {
  std::vector<Change> changes;
  std::size_t points = 0;              ///< endpoints offered
  std::size_t points_beyond_range = 0; ///< rays cut at max range (their end is not marked)
  std::size_t points_out_of_map = 0;   ///< endpoints or origin outside the key space
  std::size_t free_updates = 0;        ///< distinct cells updated as free (miss)
  std::size_t occupied_updates = 0;    ///< distinct cells updated as occupied (hit)
};

/// What an integration did, without the change set.
struct IntegrationCounts {
  std::size_t changed_cells = 0;       ///< cells whose state changed
  std::size_t became_free = 0, became_occupied = 0;
  std::size_t points_beyond_range = 0, points_out_of_map = 0, free_updates = 0, occupied_updates = 0;
};
IntegrationCounts counts(const Integration& integration);

/// How a ray cast ended.
enum class RayOutcome {
  Hit,          ///< reached an occupied cell
  Unknown,      ///< reached an unknown cell (only when unknown cells stop the ray)
  MaxRange,     ///< travelled the full range through free (or passable unknown) cells
  OutOfBounds,  ///< left the map's key space, or started outside it
};
const char* to_string(RayOutcome outcome);

struct RayQuery {
  Eigen::Vector3d origin_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction_world = Eigen::Vector3d::UnitX();  ///< need not be unit length
  double max_range_m = std::numeric_limits<double>::infinity();
  bool pass_unknown = false;  ///< when true, unknown cells do not stop the ray
};

struct RayCast {
  RayOutcome outcome = RayOutcome::OutOfBounds;
  VoxelKey key;          ///< the cell where the ray stopped (Hit, Unknown)
  double distance_m = 0; ///< distance from the origin to where the ray stopped
};

/// OctoMap's sensor model, in probabilities (defaults are OctoMap's).
struct SensorModel {
  double prob_hit = 0.7;              ///< occupancy after one hit
  double prob_miss = 0.4;             ///< occupancy after one miss
  double clamp_min = 0.1192;          ///< lower clamping bound
  double clamp_max = 0.971;           ///< upper clamping bound
  double occupancy_threshold = 0.5;   ///< at or above: Occupied
  std::vector<std::string> validate() const;
};

/// A known leaf of the octree: a cube of `size_cells`³ finest cells with one state (OctoMap
/// prunes uniform regions into one leaf).
struct Leaf {
  VoxelKey min_key;            ///< the finest cell at its lowest corner
  std::uint32_t size_cells = 1;
  VoxelState state = VoxelState::Free;
};

/// Summary of a map.
struct Stats {
  double resolution_m = 0;
  std::size_t nodes = 0;           ///< octree nodes, inner and leaves
  std::size_t free_leaves = 0;     ///< leaves (pruned nodes count once)
  std::size_t occupied_leaves = 0;
  double free_volume_m3 = 0;
  double occupied_volume_m3 = 0;
  bool empty = true;
  Eigen::Vector3d known_min_m = Eigen::Vector3d::Zero();  ///< bounding box of known cells
  Eigen::Vector3d known_max_m = Eigen::Vector3d::Zero();
};

class OccupancyMap {
 public:
  /// An empty map with cells of edge `resolution_m` (> 0).
  explicit OccupancyMap(double resolution_m, const SensorModel& model = {});
  ~OccupancyMap();
  OccupancyMap(OccupancyMap&&) noexcept;
  OccupancyMap& operator=(OccupancyMap&&) noexcept;
  OccupancyMap(const OccupancyMap&) = delete;
  OccupancyMap& operator=(const OccupancyMap&) = delete;

  /// Reads `.bt` (occupancy only) or `.ot` (full tree; ColorOcTree and OcTreeStamped are read
  /// as occupancy). Throws FileError for a missing, truncated or foreign file.
  static OccupancyMap load(const std::string& path);
  /// Writes `.bt` (max-likelihood, as OctoMap's writeBinary) or `.ot` (log-odds), chosen by
  /// extension, atomically: an existing file is replaced only by a complete one.
  void save(const std::string& path) const;

  double resolution_m() const;
  SensorModel sensor_model() const;

  /// The key of the cell containing `p_world`; empty outside the key space.
  std::optional<VoxelKey> key_of(const Eigen::Vector3d& p_world) const;
  /// The centre of a cell, metres.
  Eigen::Vector3d center_of(const VoxelKey& key) const;
  VoxelState state(const VoxelKey& key) const;
  /// Occupancy probability of a cell, or empty when unknown.
  std::optional<double> probability(const VoxelKey& key) const;

  /// Integrates one scan (OctoMap's insertPointCloud semantics, exact): every ray from
  /// `origin_world` to an endpoint marks the cells it crosses free and the endpoint's cell
  /// occupied (occupied wins over free within one scan; each cell is updated once per scan).
  /// Endpoints farther than `max_range_m` (infinity: no limit) cut the ray at that range and
  /// mark nothing occupied. `discretize`: OctoMap's insertPointCloud(…, discretize = true) —
  /// the scan's points are first replaced by the centres of the distinct cells they fall in,
  /// one ray per cell (points outside the key space stay as they are, where OctoMap's
  /// unchecked coordToKey would wrap them around); Integration::points then counts the
  /// centres.
  Integration integrate(const std::vector<Eigen::Vector3f>& points_world,
                        const Eigen::Vector3f& origin_world,
                        double max_range_m = std::numeric_limits<double>::infinity(), bool discretize = false);

  /// Sets a cell to a state directly: Free and Occupied at the clamping bounds, Unknown by
  /// deleting it. For ground truth and tests; scans go through integrate().
  void set_state(const VoxelKey& key, VoxelState state);

  /// Walks the cells along a ray (Amanatides–Woo) and reports how it ended.
  RayCast cast_ray(const RayQuery& query) const;

  /// Centres of all occupied cells at the finest level (pruned leaves are expanded), in key
  /// order. The accumulated cloud that registration aligns new scans to.
  std::vector<Eigen::Vector3f> occupied_centers() const;

  Stats stats() const;

  /// Every known leaf, in the octree's order.
  std::vector<Leaf> leaves() const;
  /// The known leaves that hold a cell of the key box [lo, hi] (a leaf may reach beyond it),
  /// in the octree's order; the octree's branches outside the box are not visited.
  std::vector<Leaf> leaves(const VoxelKey& lo, const VoxelKey& hi) const;

  struct Impl;  ///< private; defined in src/map/tree.hpp

 private:
  friend class StateReader;
  std::unique_ptr<Impl> impl_;
};

/// The states of many cells of one map, looked up one after another: the same answers as
/// OccupancyMap::state, faster when each key is near the one before it. A look-up descends
/// the octree from its root, 16 levels; two keys whose coordinates differ only in their low
/// bits share the upper part of that path, so the reader keeps the last path and descends
/// only from the deepest node the two keys share. Valid while the map is not changed.
class StateReader {
 public:
  explicit StateReader(const OccupancyMap& map);
  VoxelState operator()(const VoxelKey& key);

 private:
  const OccupancyMap::Impl& impl_;
  const octomap::OcTreeNode* path_[17] = {};  ///< path_[d]: the last key's node at depth d, for d <= reached_
  int reached_ = -1;           ///< the depth where the last look-up ended; −1: none yet
  VoxelKey last_;
  VoxelState last_state_ = VoxelState::Unknown;
};

/// The keys whose cell centres lie in `bounds_m`, order kept (the search space S filters
/// the frontier and void sets at query time).
std::vector<VoxelKey> keys_within(const OccupancyMap& map, std::vector<VoxelKey> keys,
                                  const Eigen::AlignedBox3d& bounds_m);

}  // namespace fvx::map
