// The two reference strategies of `fvx nbv --strategy`: exhaustive (every reachable pose of
// the capability map, scored like the paper's) and plain frontier-based (no voids).
#include <algorithm>
#include <cmath>
#include <random>

#include "fvx/core/stopwatch.hpp"
#include "fvx/viewpoints/orientations.hpp"
#include "search.hpp"

namespace fvx::nbv::detail {

namespace {

/// A sphere around a void cluster's cells: a pose whose frustum misses every one sees no
/// void cell (U = 0) and need not be traced.
struct Sphere {
  Eigen::Vector3d center;
  double radius;
};

std::vector<Sphere> void_spheres(const Search& s) {
  std::vector<Sphere> spheres;
  const double half_diagonal = std::sqrt(3.0) * 0.5 * s.grid.resolution_m();
  for (const auto& v : s.a.void_clusters) {
    double r = 0.0;
    for (const map::VoxelKey& k : v.cells) r = std::max(r, (s.grid.center_of(k) - v.mean_m).norm());
    spheres.push_back({v.mean_m, r + half_diagonal});
  }
  return spheres;
}

/// Does a sphere meet the cone of half-angle `half_angle` along `axis` (unit) from `apex`,
/// within `range`? Conservative: true whenever the frustum inside the cone might.
bool meets_cone(const Sphere& sphere, const Eigen::Vector3d& apex, const Eigen::Vector3d& axis, double half_angle,
                double range) {
  const Eigen::Vector3d v = sphere.center - apex;
  const double distance = v.norm();
  if (distance <= sphere.radius) return true;
  if (distance - sphere.radius > range) return false;
  const double angle = std::acos(std::clamp(v.dot(axis) / distance, -1.0, 1.0));
  return angle - std::asin(sphere.radius / distance) <= half_angle;
}

/// The exhaustive strategy's pre-screen: below this many poses it scores them all with the
/// coarse fan; above it it keeps a quarter of those its fan sees anything from, at least this
/// many. Measured on 72 maps of the suite's exhaustive runs (views 1, 5 and 10 of its 24
/// scenes): a quarter kept the same ten views on every map at half the search time; an
/// eighth lowered the best U on one map (to 95 %).
constexpr std::size_t kPrescreenMinPoses = 1024;
constexpr std::size_t kPrescreenShare = 4;

/// U of every pose with the coarse fan (screen_fan()), or 0 where the pre-screen left the
/// pose out. The exhaustive strategy scores every pose the capability map holds (18 000 to
/// 22 000 on the suite's scenes), and the coarse fan's cast of them all was three quarters of
/// the default suite's time. A fan half as fine each way (a quarter of the rays) scores them
/// all first; the best share by its estimate of the full fan's U (viewpoints::CoarseFan) is
/// scored with the coarse fan, as the frontier-void strategy's poses are. (The share was
/// measured with plain counts, before the estimate.)
std::vector<std::size_t> screen_exhaustive(const Search& s, const std::vector<Pose>& poses, Result& result) {
  const viewpoints::CoarseFan* pre_fan = s.prescreen_fan();
  if (!pre_fan || poses.size() < kPrescreenMinPoses)
    return s.score(*s.void_scorer, poses, result, s.screen_fan());
  const std::vector<std::size_t> pre = s.score(*s.void_scorer, poses, result, pre_fan);
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < poses.size(); ++i)
    if (pre[i] > 0) order.push_back(i);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t l, std::size_t r) { return pre[l] > pre[r]; });
  order.resize(std::min(order.size(), std::max(kPrescreenMinPoses, order.size() / kPrescreenShare)));
  std::sort(order.begin(), order.end());  // generation order: ties rank as without the pre-screen
  std::vector<Pose> kept;
  kept.reserve(order.size());
  for (const std::size_t i : order) kept.push_back(poses[i]);
  // The poses were counted (scored, seeing nothing) by the pre-screen: not again.
  const std::size_t scored = result.poses_scored, seeing_nothing = result.pruning.seeing_nothing;
  const std::vector<std::size_t> U_kept = s.score(*s.void_scorer, kept, result, s.screen_fan());
  result.poses_scored = scored;
  result.pruning.seeing_nothing = seeing_nothing;
  std::vector<std::size_t> U(poses.size(), 0);
  for (std::size_t k = 0; k < order.size(); ++k) U[order[k]] = U_kept[k];
  return U;
}

}  // namespace

Result select_exhaustive(Search& s, Result result) {
  Stopwatch t0;
  const capmap::CapabilityMap& cm = *s.reach->capmap;
  const Eigen::Isometry3d& T_world_base = s.reach->T_world_base;
  Pruning& pruning = result.pruning;
  const auto spheres = void_spheres(s);
  if (s.config.progress) s.config.progress("enumerating the capability map", 0, cm.voxels().size());
  double half_angle = 0.0, longest = 1.0;
  for (const Eigen::Vector3d& ray : s.rays_sensor) {
    half_angle = std::max(half_angle, std::acos(1.0 / ray.norm()));
    longest = std::max(longest, ray.norm());
  }
  const double range = s.config.sensor.depth_max_m * longest;
  std::vector<Pose> poses;
  for (const auto& [voxel, bits] : cm.voxels()) {
    ++pruning.utility_cells;
    const Eigen::Vector3d p = T_world_base * cm.center_of(voxel);
    const auto key = s.grid.cell_of(p);
    if (!key) {
      ++pruning.not_free;
      continue;
    }
    if (!s.keep_position(*key, p, pruning)) continue;
    ++pruning.candidate_cells;
    ++pruning.cells_tried;
    const std::size_t cell = s.grid.index(*key);
    for (int d = 0; d < cm.directions().size(); ++d) {
      if (!(bits[std::size_t(d) / 64] >> (d % 64) & 1u)) continue;
      const Eigen::Vector3d d_world = T_world_base.linear() * cm.directions()[d];
      for (int k = 0; k < s.config.exhaustive_rolls; ++k) {
        ++pruning.orientations_sampled;
        ++pruning.valid_poses;
        const bool visible = std::any_of(spheres.begin(), spheres.end(), [&](const Sphere& sphere) {
          return meets_cone(sphere, p, d_world, half_angle, range);
        });
        if (!visible) {
          ++pruning.culled;
          continue;
        }
        Pose pose;
        pose.T_world_sensor.linear() = viewpoints::look_along(d_world, M_PI * k / s.config.exhaustive_rolls);
        pose.T_world_sensor.translation() = p;
        pose.cell = cell;
        poses.push_back(std::move(pose));
      }
    }
  }
  result.timing.pruning_s = t0.seconds();

  t0 = Stopwatch();
  // Screened as the frontier-void strategy is (coarse fan, the best again with the full
  // fan in rank()), so that the two differ in which poses they score, not in how.
  const std::vector<std::size_t> U = screen_exhaustive(s, poses, result);
  pruning.seeing_nothing += pruning.culled;
  result.timing.scoring_s = t0.seconds();
  // IK only for the poses that make the ranking (it would cost seconds for all of them).
  t0 = Stopwatch();
  Pruning ik_pruning;
  result.views = s.rank(poses, U, pruning, nullptr, nullptr, [&](Pose& pose, std::size_t i) {
    return !s.reach->arm || s.keep_orientation(pose, s.config.seed + 0x9E3779B97F4A7C15ull * (i + 1), ik_pruning);
  });
  pruning.ik_failed = ik_pruning.ik_failed;
  result.timing.sampling_s = t0.seconds();
  if (result.views.empty())
    result.reason = pruning.candidate_cells == 0
                        ? "no voxel of the capability map is a free cell of the map clear of obstacles"
                        : "no reachable pose sees a void cell";
  return result;
}

Result select_frontier(Search& s, Result result) {
  Stopwatch t0;
  if (s.config.progress) s.config.progress("rays in front of the largest frontier cluster", 0, 0);
  const frontiers::Cluster* target = s.frontier_target;
  // A frontier-based viewer stands in the free space in front of the frontier: from each
  // frontier cell a ray goes away from its unknown face-neighbours; cells it passes gain 1.
  core::LargeVector<double> rays_through(s.grid.cell_count(), 0.0);
  core::LargeVector<std::uint8_t> mask(s.grid.cell_count(), 0);
  std::size_t vectors = 0;
  for (std::size_t j = 0; j < target->cells.size(); ++j) {
    const map::VoxelKey& f = target->cells[j];
    if (!s.grid.contains(f)) continue;
    mask[s.grid.index(f)] = 1;
    const Eigen::Vector3d& toward_unknown = s.toward_unknown[j];
    if (toward_unknown.norm() < 1e-9) continue;
    ++vectors;
    s.grid.walk(s.grid.center_of(f), -toward_unknown, s.config.sensor.depth_max_m,
                [&](std::size_t i, map::VoxelState state) {
                  if (state != map::VoxelState::Free) return false;
                  rays_through[i] += 1.0;
                  return true;
                });
  }
  result.utility_vectors = vectors;
  result.timing.accumulation_s = t0.seconds();

  t0 = Stopwatch();
  Pruning& pruning = result.pruning;
  CandidateOrder candidates = s.prune(rays_through, result);
  result.timing.pruning_s = t0.seconds();

  t0 = Stopwatch();
  std::mt19937_64 rng(s.config.seed);
  const double jitter_rad = s.config.jitter_deg * M_PI / 180.0;
  std::vector<Pose> poses;
  for (std::size_t n = 0; n < candidates.size(); ++n) {
    if (poses.size() >= std::size_t(s.config.valid_poses)) break;
    const std::size_t cell = candidates[n];
    ++pruning.cells_tried;
    const Eigen::Vector3d p = s.grid.center_of(s.grid.key(cell));
    for (const Eigen::Matrix3d& R : viewpoints::sample_orientations(p, {target->centroid_m},
                                                                    s.config.orientations_per_cell, jitter_rad, rng)) {
      if (poses.size() >= std::size_t(s.config.valid_poses)) break;
      s.add_pose(p, R, cell, pruning, poses);
    }
  }
  pruning.valid_poses = poses.size();
  result.timing.sampling_s = t0.seconds();

  t0 = Stopwatch();
  const viewpoints::FovScorer scorer(s.grid, std::move(mask), s.rays_sensor, s.config.sensor.depth_max_m,
                                     s.config.sensor.depth_min_m);
  const std::vector<std::size_t> seen = s.score(scorer, poses, result);
  result.views = s.rank(poses, seen, result.pruning, &rays_through, nullptr);
  for (View& v : result.views) {  // rank() reads the field as util(c): it is a ray count here
    v.frontier_rays_through_cell = v.accumulated_utility_m3;
    v.accumulated_utility_m3 = 0.0;
  }
  for (View& v : result.views) v.frontier_cells_seen = seen[v.pose_index];
  result.timing.scoring_s = t0.seconds();
  if (result.views.empty())
    result.reason = candidates.empty() ? "pruning removed every cell in front of the largest frontier cluster"
                                       : "no valid pose sees the largest frontier cluster";
  return result;
}

// A random reachable view: positions uniform over the cells that pass pruning (with an arm,
// the capability map's voxels), a uniform roll, and a direction uniform over the reachable
// ones (without an arm: over the sphere). Poses are drawn until one sees a void cell.
Result select_random(Search& s, Result result) {
  Stopwatch t0;
  Pruning& pruning = result.pruning;
  std::vector<Eigen::Vector3d> positions;
  if (s.reach) {
    for (const auto& [voxel, bits] : s.reach->capmap->voxels()) {
      ++pruning.utility_cells;
      const Eigen::Vector3d p = s.reach->T_world_base * s.reach->capmap->center_of(voxel);
      const auto key = s.grid.cell_of(p);
      if (!key) {
        ++pruning.not_free;
        continue;
      }
      if (s.keep_position(*key, p, pruning)) positions.push_back(p);
    }
  } else {
    for (std::size_t i = 0; i < s.grid.cell_count(); ++i) {
      if (!s.may_stand_in(i)) continue;
      ++pruning.utility_cells;
      const map::VoxelKey k = s.grid.key(i);
      if (s.keep_position(k, s.grid.center_of(k), pruning)) positions.push_back(s.grid.center_of(k));
    }
  }
  pruning.candidate_cells = positions.size();
  result.timing.pruning_s = t0.seconds();
  if (positions.empty()) {
    result.reason = "pruning removed every position (not free, outside the view bounds, too close to an obstacle "
                    "or out of the arm's reach)";
    return result;
  }
  t0 = Stopwatch();
  std::mt19937_64 rng(s.config.seed);
  std::uniform_int_distribution<std::size_t> pick(0, positions.size() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Pose> poses;
  std::vector<std::size_t> U;
  for (int tries = 0; tries < s.config.random_tries; ++tries) {
    const Eigen::Vector3d p = positions[pick(rng)];
    Eigen::Vector3d d;
    if (s.reach) {
      const auto reachable = s.reach->capmap->reachable_directions(s.reach->T_world_base, p);
      d = reachable[std::uniform_int_distribution<std::size_t>(0, reachable.size() - 1)(rng)];
    } else {
      const double z = 2.0 * unit(rng) - 1.0, phi = 2.0 * M_PI * unit(rng);
      d = Eigen::Vector3d(std::sqrt(1 - z * z) * std::cos(phi), std::sqrt(1 - z * z) * std::sin(phi), z);
    }
    Pose pose;
    pose.T_world_sensor.linear() = viewpoints::look_along(d, M_PI * unit(rng));
    pose.T_world_sensor.translation() = p;
    pose.cell = s.grid.index(*s.grid.cell_of(p));
    ++pruning.cells_tried;
    if (!s.keep_orientation(pose, rng(), pruning)) continue;
    ++pruning.valid_poses;
    const std::size_t seen = s.score(*s.void_scorer, {pose}, result).front();
    poses.push_back(std::move(pose));
    U.push_back(seen);
    if (seen > 0 && !s.repeats_taken(poses.back().T_world_sensor)) break;
  }
  result.timing.scoring_s = t0.seconds();
  result.views = s.rank(poses, U, result.pruning, nullptr, nullptr);
  if (result.views.empty())
    result.reason = "none of " + std::to_string(poses.size()) + " random reachable poses (" +
                    std::to_string(s.config.random_tries) + " drawn) sees a void cell";
  return result;
}

}  // namespace fvx::nbv::detail
