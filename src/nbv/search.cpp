#include "search.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numeric>
#include <random>
#include <thread>

#include "fvx/core/error.hpp"
#include "fvx/core/memory.hpp"
#include "fvx/core/threads.hpp"

namespace fvx::nbv::detail {

namespace {

Eigen::AlignedBox3d known_box(const map::OccupancyMap& map) {
  const map::Stats stats = map.stats();
  return stats.empty ? Eigen::AlignedBox3d() : Eigen::AlignedBox3d(stats.known_min_m, stats.known_max_m);
}

/// Rays run between the view bounds and the search space's known part (its void and frontier
/// cells are known or within the voids' hull, which the known cells bound): the box around
/// both, within the known cells (beyond them every cell is unknown and no viewpoint can be).
/// With Config::exterior view or free the unknown cells around them may hold viewpoints: the
/// box then reaches the sensor's range beyond the known cells (an eye farther away sees only
/// unknown cells outside every void's hull, and no utility ray is longer). Before the grid is
/// allocated, a box that would need more memory than is available is refused (about 24 B per
/// cell: states, void labels, distances, the field and the threads' scratch).
Eigen::AlignedBox3d grid_box(const Eigen::AlignedBox3d& known, const Eigen::AlignedBox3d& search_space,
                             const Eigen::AlignedBox3d& view_bounds, const Config& config, double R) {
  if (known.isEmpty()) return known;
  const Eigen::AlignedBox3d around = search_space.intersection(known).merged(view_bounds);
  const Eigen::Vector3d range = Eigen::Vector3d::Constant(config.sensor.depth_max_m);
  const Eigen::AlignedBox3d reach = config.exterior == Exterior::Unknown
                                        ? known
                                        : Eigen::AlignedBox3d(known.min() - range, known.max() + range);
  const Eigen::AlignedBox3d box = around.intersection(reach);
  core::require_memory_for_box(box, R, 24.0, "the search's grid",
                               "give a smaller --bounds or --view-bounds, metres x0,y0,z0,x1,y1,z1");
  return box;
}

/// The world box around the arm's reachable voxels (empty when none is reachable).
Eigen::AlignedBox3d reach_box_world(const Reach& reach) {
  const Eigen::AlignedBox3d base = reach.capmap->reachable_box_base();
  Eigen::AlignedBox3d world;
  if (!base.isEmpty())
    for (int c = 0; c < 8; ++c) world.extend(reach.T_world_base * base.corner(Eigen::AlignedBox3d::CornerType(c)));
  return world;
}

/// The sensor's box without --view-bounds: the known cells' box within the sensor's range of
/// the search space (all of it when S is the default, the known cells' box) and, when unknown cells
/// outside the hull may hold viewpoints (Config::exterior), the arm's reach as well, as far
/// as it lies within the sensor's range of the search space (an eye farther away sees no
/// void; a far base would otherwise stretch the grid across the distance) and no lower than
/// the known cells.
Eigen::AlignedBox3d default_view_bounds(const Eigen::AlignedBox3d& known, const Eigen::AlignedBox3d& search_space,
                                        const std::optional<Reach>& reach, const Config& config) {
  if (config.view_bounds_m) return *config.view_bounds_m;
  // An eye farther than the sensor's range from the search space sees none of its voids: a
  // small search space of a large map reads a grid around it, not around the whole map.
  const Eigen::Vector3d range = Eigen::Vector3d::Constant(config.sensor.depth_max_m);
  const Eigen::AlignedBox3d in_range(search_space.min() - range, search_space.max() + range);
  const Eigen::AlignedBox3d known_in_range = known.isEmpty() || search_space.isEmpty() ? known : known.intersection(in_range);
  if (config.exterior == Exterior::Unknown || known.isEmpty() || !reach || !reach->capmap) return known_in_range;
  const Eigen::AlignedBox3d reach_in_range = reach_box_world(*reach).intersection(in_range);
  if (reach_in_range.isEmpty()) return known_in_range;
  // Sideways and upwards, not downwards: below the lowest cell any ray reached lies what the
  // scene stands on (the floor's underside), not air a sensor can stand in. On the suite the
  // exhaustive planner took views from under the floor, up through its unseen cells, which
  // measured nothing (README, "Exploration over a scene suite").
  Eigen::AlignedBox3d bounds = known_in_range.merged(reach_in_range);
  bounds.min().z() = known.min().z();
  return bounds;
}

/// The view bounds within the world box around the arm's reachable voxels.
Eigen::AlignedBox3d candidate_box(const Eigen::AlignedBox3d& view_bounds, const std::optional<Reach>& reach) {
  if (!reach || !reach->capmap) return view_bounds;
  const Eigen::AlignedBox3d world = reach_box_world(*reach);
  return world.isEmpty() ? world : world.intersection(view_bounds);
}

/// Per cell of `cluster`, the sum of the unit steps to its unknown face-neighbours.
std::vector<Eigen::Vector3d> unknown_sides(const map::OccupancyMap& map, const frontiers::Cluster& cluster) {
  std::vector<Eigen::Vector3d> sides;
  for (const map::VoxelKey& f : cluster.cells) {
    Eigen::Vector3d toward = Eigen::Vector3d::Zero();
    for (int a = 0; a < 3; ++a)
      for (int sign : {-1, 1}) {
        map::VoxelKey n = f;
        (a == 0 ? n.x : a == 1 ? n.y : n.z) = std::uint16_t((a == 0 ? f.x : a == 1 ? f.y : f.z) + sign);
        if (map.state(n) == map::VoxelState::Unknown) toward[a] += sign;
      }
    sides.push_back(toward);
  }
  return sides;
}

/// The view moved to the pose IK reached: its position and viewing axis, the roll kept (the
/// axis turned by the smallest rotation).
Eigen::Isometry3d snapped_pose(const Eigen::Isometry3d& asked, const Eigen::Vector3d& p_world,
                               const Eigen::Vector3d& axis_world) {
  Eigen::Isometry3d T = asked;
  T.translation() = p_world;
  T.linear() = (Eigen::Quaterniond::FromTwoVectors(asked.linear().col(2), axis_world) * Eigen::Quaterniond(asked.linear()))
                   .normalized()
                   .toRotationMatrix();
  return T;
}

}  // namespace

Search::Search(const map::OccupancyMap& map_in, const frontier_voids::Analysis& analysis,
               const std::optional<Reach>& reach_in, const Config& config_in,
               const std::vector<map::VoxelKey>& hidden_void_cells)
    : a(analysis),
      reach(reach_in),
      config(config_in),
      known_m(known_box(map_in)),
      view_bounds_m(default_view_bounds(known_m, analysis.bounds_m, reach_in, config_in)),
      candidate_box_m(candidate_box(view_bounds_m, reach_in)),
      grid(map_in, grid_box(known_m, analysis.bounds_m, view_bounds_m, config_in, map_in.resolution_m())) {
  if (config.exterior != Exterior::Unknown) mark_exterior();
  // Only voids a frontier touches count: an enclosed void (inside a closed box or a solid)
  // has no free cell beside it, so no view can see into it (paper §IV-B pairs voids with
  // frontiers for this reason).
  void_label.assign(grid.cell_count(), -1);
  for (const auto& v : a.void_clusters)
    if (!a.frontier_voids[std::size_t(v.id)].enclosed())
      for (const map::VoxelKey& k : v.cells)
        if (grid.contains(k)) void_label[grid.index(k)] = v.id;
  const std::vector<std::size_t> blocking = config.near_unknown == viewpoints::NearUnknown::Hidden
                                                ? blocking_cells(hidden_void_cells)
                                                : std::vector<std::size_t>{};
  for (const map::VoxelKey& k : hidden_void_cells)
    if (grid.contains(k)) void_label[grid.index(k)] = -1;
  any_hidden = !hidden_void_cells.empty();
  // Only "an occupied cell within clearance_m of the eye?" is asked of it (clear_of_occupied).
  // The eye may sit anywhere in its cell, up to sqrt(3)/2 cells from the centre: distances
  // beyond the clearance plus one cell are dropped by the transform (cheaper).
  const double R = grid.resolution_m();
  const double reach_cells = config.clearance_m / R + 1.0;
  occupied_distance_sq = map::squared_distance_to(grid, map::VoxelState::Occupied, config.threads,
                                                  float(std::ceil(reach_cells * reach_cells)));
  rays_sensor = viewpoints::ray_fan(config.sensor.intrinsics, config.ray_cols, config.ray_rows);
  const bool screens = config.strategy == Strategy::FrontierVoid || config.strategy == Strategy::Exhaustive;
  const auto fan = [&](int cols, int rows) {
    return viewpoints::coarse_fan(config.sensor.intrinsics, cols, rows, config.ray_cols, config.ray_rows, R);
  };
  if (screens && config.coarse_ray_cols > 0 &&
      std::size_t(config.coarse_ray_cols) * std::size_t(config.coarse_ray_rows) < rays_sensor.size())
    fan_coarse = fan(config.coarse_ray_cols, config.coarse_ray_rows);
  const int pre_cols = std::max(1, config.coarse_ray_cols / 2), pre_rows = std::max(1, config.coarse_ray_rows / 2);
  // Only a fan with fewer rays than the coarse one saves work (a 1 x N coarse fan has none).
  if (config.strategy == Strategy::Exhaustive &&
      std::size_t(pre_cols) * std::size_t(pre_rows) < fan_coarse.rays.size())
    fan_prescreen = fan(pre_cols, pre_rows);
  const io::Intrinsics& K = config.sensor.intrinsics;
  half_fov_rad = std::min(std::atan(0.5 * K.width / std::abs(K.fx)), std::atan(0.5 * K.height / std::abs(K.fy)));
  void_scorer = std::make_unique<viewpoints::FovScorer>(grid, void_mask(), rays_sensor, config.sensor.depth_max_m,
                                                        config.sensor.depth_min_m, config.count_near_void_cells);
  void_scorer->set_unknown_depth(config.unknown_depth_cells);
  void_scorer->set_near_unknown(config.near_unknown);
  void_scorer->set_blocking(blocking);
  if (config.strategy == Strategy::Frontier) {
    for (const auto& c : a.frontier_clusters)
      if (!frontier_target || c.cells.size() > frontier_target->cells.size()) frontier_target = &c;
    if (frontier_target) toward_unknown = unknown_sides(map_in, *frontier_target);
  }
}

void Search::mark_exterior() {
  // Outside the hull no void lies: what the map does not know there is taken for air.
  const core::LargeVector<std::uint8_t> inside = voids::inside_hull(grid, a.hull);
  exterior_view.assign(grid.cell_count(), 0);
  for (std::size_t i = 0; i < inside.size(); ++i) {
    if (inside[i] || grid.state_at(i) != map::VoxelState::Unknown) continue;
    exterior_view[i] = 1;
    if (config.exterior == Exterior::Free) grid.set_state_at(i, map::VoxelState::Free);
  }
}

core::LargeVector<std::uint8_t> Search::void_mask() const {
  core::LargeVector<std::uint8_t> mask(void_label.size());
  for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = void_label[i] >= 0;
  return mask;
}

std::vector<std::size_t> Search::blocking_cells(const std::vector<map::VoxelKey>& hidden_void_cells) const {
  // A taken view left these cells unknown: something may hide in their voids, nearer than
  // the minimum depth as well (a shelf's back wall), so the rule covers the whole void.
  // Measured against blocking the hidden cells alone (README, "Exploration over a scene
  // suite"): a higher AUC on every seed and the loop ending with utility 0 far more often.
  std::vector<char> holds_hidden(a.void_clusters.size(), 0);
  std::vector<std::size_t> blocking;
  for (const map::VoxelKey& k : hidden_void_cells) {
    if (!grid.contains(k)) continue;
    const std::size_t i = grid.index(k);
    blocking.push_back(i);
    if (void_label[i] >= 0) holds_hidden[std::size_t(void_label[i])] = 1;
  }
  for (const auto& v : a.void_clusters)
    if (holds_hidden[std::size_t(v.id)])
      for (const map::VoxelKey& k : v.cells)
        if (grid.contains(k)) blocking.push_back(grid.index(k));
  return blocking;
}

frontier_voids::Analysis Search::visible_utility() const {
  frontier_voids::Analysis visible = a;
  const double cell_m3 = std::pow(grid.resolution_m(), 3);
  for (auto& fv : visible.frontier_voids) {
    std::size_t cells = 0;
    for (const map::VoxelKey& k : a.void_clusters[std::size_t(fv.void_id)].cells)
      cells += grid.contains(k) && void_label[grid.index(k)] == fv.void_id;
    fv.utility_m3 = double(cells) * cell_m3;
  }
  return visible;
}

Eigen::Matrix3d Search::snap_to_reach(const Eigen::Vector3d& p_world, const Eigen::Matrix3d& R) const {
  if (!reach) return R;
  const std::vector<Eigen::Vector3d> reachable = reach->capmap->reachable_directions(reach->T_world_base, p_world);
  if (reachable.empty()) return R;
  const Eigen::Vector3d axis = R.col(2);
  const auto nearest = std::max_element(reachable.begin(), reachable.end(),
                                        [&](const auto& l, const auto& r) { return l.dot(axis) < r.dot(axis); });
  if (nearest->dot(axis) < std::cos(half_fov_rad)) return R;
  return Eigen::Quaterniond::FromTwoVectors(axis, *nearest) * R;
}

bool Search::clear_of_occupied(const map::VoxelKey& cell, const Eigen::Vector3d& p_world) const {
  // Occupied cell centres within clearance_m (the grid covers the known cells in reach). The
  // transform gives the distance from the cell's centre: a centre within the clearance fails
  // the cell; an eye off the centre (an IK snap, a capability-map voxel) by `off` is clear
  // when the centre is farther than clearance + off, and else is measured against the
  // occupied cells around it.
  const double R = grid.resolution_m(), clearance = config.clearance_m;
  const double centre_m = std::sqrt(double(occupied_distance_sq[grid.index(cell)])) * R;
  if (centre_m <= clearance) return false;
  const double off_m = (p_world - grid.center_of(cell)).norm();
  if (centre_m - off_m > clearance) return true;
  const int r = int(std::ceil((clearance + off_m) / R));
  const Eigen::Vector3i size = grid.size();
  const int c[3] = {cell.x - grid.min_key().x, cell.y - grid.min_key().y, cell.z - grid.min_key().z};
  for (int z = std::max(0, c[2] - r); z <= std::min(size.z() - 1, c[2] + r); ++z)
    for (int y = std::max(0, c[1] - r); y <= std::min(size.y() - 1, c[1] + r); ++y)
      for (int x = std::max(0, c[0] - r); x <= std::min(size.x() - 1, c[0] + r); ++x) {
        const map::VoxelKey k{std::uint16_t(grid.min_key().x + x), std::uint16_t(grid.min_key().y + y),
                              std::uint16_t(grid.min_key().z + z)};
        if (grid.state(k) == map::VoxelState::Occupied && (grid.center_of(k) - p_world).norm() <= clearance)
          return false;
      }
  return true;
}

bool Search::keep_position(const map::VoxelKey& cell, const Eigen::Vector3d& p_world, Pruning& pruning) const {
  if (!grid.contains(cell) || !may_stand_in(grid.index(cell))) {
    ++pruning.not_free;
    return false;
  }
  if (!view_bounds_m.contains(p_world)) {
    ++pruning.outside_view_bounds;
    return false;
  }
  if (!clear_of_occupied(cell, p_world)) {
    ++pruning.too_close_to_obstacle;
    return false;
  }
  if (reach) {
    const Eigen::Vector3d p_base = reach->T_world_base.inverse() * p_world;
    if (reach->capmap->reachability_index(p_base) <= 0.0) {
      ++pruning.unreachable_position;
      return false;
    }
  }
  return true;
}

std::size_t CandidateOrder::operator[](std::size_t i) {
  if (i >= sorted_) {
    const auto before = [v = value_](std::size_t l, std::size_t r) {
      return (*v)[l] > (*v)[r] || ((*v)[l] == (*v)[r] && l < r);  // a total order: one result from any sort
    };
    const std::size_t end = std::min(cells_.size(), std::max({i + 1, 2 * sorted_, sorted_ + 1024}));
    const auto first = cells_.begin() + std::ptrdiff_t(sorted_), last = cells_.begin() + std::ptrdiff_t(end);
    std::nth_element(first, last - 1, cells_.end(), before);
    std::sort(first, last, before);
    sorted_ = end;
  }
  return cells_[i];
}

CandidateOrder Search::prune(const core::LargeVector<double>& value, Result& result) const {
  std::vector<std::size_t> candidates;
  for (std::size_t i = 0; i < value.size(); ++i) {
    if (!(value[i] > 0.0)) continue;
    ++result.pruning.utility_cells;
    const map::VoxelKey k = grid.key(i);
    const bool keep = keep_position(k, grid.center_of(k), result.pruning);
    if (keep) candidates.push_back(i);
    if (config.keep_utility_field) result.utility_field.push_back({grid.center_of(k), value[i], keep});
  }
  result.pruning.candidate_cells = candidates.size();
  return CandidateOrder(std::move(candidates), value);
}

void Search::add_pose(const Eigen::Vector3d& p, const Eigen::Matrix3d& R, std::size_t cell, Pruning& pruning,
                      std::vector<Pose>& poses) const {
  Pose pose;
  pose.T_world_sensor.linear() = snap_to_reach(p, R);
  pose.T_world_sensor.translation() = p;
  pose.cell = cell;
  if (keep_orientation(pose, config.seed + 0x9E3779B97F4A7C15ull * (pruning.orientations_sampled + 1), pruning))
    poses.push_back(std::move(pose));
}

bool Search::keep_orientation(Pose& pose, std::uint64_t pose_seed, Pruning& pruning) const {
  ++pruning.orientations_sampled;
  if (!reach) return true;
  const Eigen::Vector3d p = pose.T_world_sensor.translation(), d = pose.T_world_sensor.linear().col(2);
  if (!reach->capmap->reachable(reach->T_world_base, p, d)) {
    ++pruning.unreachable_orientation;
    return false;
  }
  if (reach->arm) {
    std::mt19937_64 rng(pose_seed);
    const Eigen::Isometry3d T_base_world = reach->T_world_base.inverse();
    const capmap::IkResult ik = capmap::solve_in_bit(*reach->capmap, *reach->arm, T_base_world * p,
                                                     T_base_world.linear() * d, reach->ik, rng);
    if (!ik.reached) {
      ++pruning.ik_failed;
      return false;
    }
    pose.joints_rad = ik.q;
    if (ik.snapped) {  // the map's bit holds a pose near this one: the view moves there
      const Eigen::Isometry3d T_base_reached = reach->arm->fk(ik.q);
      const Eigen::Vector3d p_snapped = reach->T_world_base * T_base_reached.translation();
      const std::optional<map::VoxelKey> cell = grid.cell_of(p_snapped);
      if (!cell || !keep_position(*cell, p_snapped, pruning)) return false;
      const Eigen::Vector3d axis_base = T_base_reached.linear() * reach->arm->config().viewing_axis_sensor;
      pose.T_world_sensor = snapped_pose(pose.T_world_sensor, p_snapped, reach->T_world_base.linear() * axis_base);
    }
  }
  return true;
}

void Search::parallel(std::size_t n, const std::function<void(std::size_t, viewpoints::FovScorer::Workspace&)>& fn,
                      const char* stage) const {
  const unsigned threads = core::worker_count(config.threads, n);
  if (workspaces.size() < threads) workspaces.resize(threads);
  std::atomic<std::size_t> next{0};
  auto work = [&](unsigned t) {
    const bool report = t == 0 && stage && config.progress;
    for (std::size_t i = next++; i < n; i = next++) {
      fn(i, workspaces[t]);
      if (report && i % std::max<std::size_t>(256, n / 100) == 0) config.progress(stage, i, n);
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work, t);
  work(0);
  for (auto& t : pool) t.join();
}

std::vector<std::size_t> Search::score(const viewpoints::FovScorer& scorer, const std::vector<Pose>& poses,
                                       Result& result, const viewpoints::CoarseFan* coarse) const {
  std::vector<viewpoints::FovScorer::Score> scores(poses.size());
  parallel(
      poses.size(),
      [&](std::size_t i, viewpoints::FovScorer::Workspace& ws) {
        scores[i] = scorer.score(poses[i].T_world_sensor, ws, nullptr, coarse);
      },
      "scoring poses");
  std::vector<std::size_t> seen(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    // Screened, the estimate of the full fan's U ranks (it is never below the coarse count).
    seen[i] = std::size_t(std::llround(scores[i].full_fan_estimate));
    result.pruning.seeing_nothing += seen[i] == 0;
    result.timing.cells_visited += scores[i].cells_visited;
  }
  result.timing.rays += poses.size() * (coarse ? coarse->rays.size() : scorer.ray_count());
  result.poses_scored += poses.size();
  return seen;
}

/// Screened ranks (Search::rank): besides config.top, this many more views (at most) are
/// scored with the full fan, so that a view the coarse fan placed just below the top can
/// still take its place.
constexpr std::size_t kRescoredBeyondTop = Config::kRescoredBeyondTop;

View Search::describe(const Pose& pose, std::size_t i, const core::LargeVector<double>* util_m3,
                      const utility::Field* field, viewpoints::FovScorer::Workspace& ws,
                      std::vector<std::size_t>& seen) const {
  View v;
  v.T_world_sensor = pose.T_world_sensor;
  v.pose_index = i;
  if (pose.stepped_back_from != kNoCell) v.stepped_back_from = pose.stepped_back_from;
  if (pose.polished_from != kNoCell) v.polished_from = pose.polished_from;
  v.joints_rad = pose.joints_rad;
  v.void_cells_seen = void_scorer->score(pose.T_world_sensor, ws, &seen).targets_seen;
  if (pose.cell != kNoCell) {
    if (util_m3) v.accumulated_utility_m3 = (*util_m3)[pose.cell];
    if (field)
      for (const std::int32_t fv : field->contributors[pose.cell])
        if (fv >= 0) v.utility_from.push_back(fv);
  }
  return v;
}

void Search::name_seen(View& v, const std::vector<std::size_t>& seen) const {
  // `seen` ascends by grid index, which orders cells as keys do: (z, y, x).
  v.seen_void_cells.reserve(seen.size());
  for (const std::size_t c : seen) v.seen_void_cells.push_back(grid.key(c));
  std::vector<std::size_t> per_void;  // by void id (labels of seen cells are ids >= 0)
  for (const std::size_t c : seen) {
    const auto id = std::size_t(void_label[c]);
    if (id >= per_void.size()) per_void.resize(id + 1, 0);
    ++per_void[id];
  }
  for (std::size_t id = 0; id < per_void.size(); ++id)
    if (per_void[id] > 0) v.voids_seen.emplace_back(int(id), per_void[id]);
  std::stable_sort(v.voids_seen.begin(), v.voids_seen.end(),
                   [](const auto& l, const auto& r) { return l.second > r.second; });
}

bool Search::repeats_taken(const Eigen::Isometry3d& T_world_sensor) const {
  return nbv::repeats_taken(taken_views, T_world_sensor);
}

std::vector<View> Search::rank(std::vector<Pose>& poses, const std::vector<std::size_t>& score, Pruning& pruning,
                               const core::LargeVector<double>* util_m3, const utility::Field* field,
                               const std::function<bool(Pose&, std::size_t)>& accept) const {
  const bool screened = screen_fan() != nullptr;  // `score` came from the coarse fan
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < poses.size(); ++i)
    if (score[i] > 0) order.push_back(i);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t l, std::size_t r) { return score[l] > score[r]; });
  const std::size_t top = std::size_t(config.top);
  const std::size_t wanted = !screened                 ? top
                             : config.rescored_poses > 0 ? std::max(top, std::size_t(config.rescored_poses))
                                                         : top + std::min(top, kRescoredBeyondTop);
  std::vector<std::size_t> chosen;  // accepted, in score order
  for (const std::size_t i : order) {
    if (chosen.size() >= wanted) break;
    if (accept && !accept(poses[i], i)) continue;
    // After `accept`, which may move the pose: the view the loop would take is compared.
    if (repeats_taken(poses[i].T_world_sensor)) {
      ++pruning.already_taken;
      continue;
    }
    chosen.push_back(i);
  }
  std::vector<View> described(chosen.size());
  std::vector<std::vector<std::size_t>> seen(chosen.size());
  parallel(chosen.size(), [&](std::size_t k, viewpoints::FovScorer::Workspace& ws) {
    described[k] = describe(poses[chosen[k]], chosen[k], util_m3, field, ws, seen[k]);
  });
  std::vector<std::size_t> kept(described.size());  // into `described`, best first
  std::iota(kept.begin(), kept.end(), std::size_t(0));
  // Where `score` is a count of void cells, the full fan's U of the pose as accepted decides;
  // ties keep the score order. Screened, `score` was the coarse fan's; unscreened it can
  // still differ, since `accept` may move a pose (IK snaps it to one the capability map
  // holds: the exhaustive strategy). The frontier strategy's score counts frontier cells.
  if (config.strategy != Strategy::Frontier) {
    std::stable_sort(kept.begin(), kept.end(), [&](std::size_t l, std::size_t r) {
      return described[l].void_cells_seen > described[r].void_cells_seen;
    });
    while (!kept.empty() && described[kept.back()].void_cells_seen == 0) kept.pop_back();
  }
  if (kept.size() > top) kept.resize(top);
  std::vector<View> views(kept.size());
  parallel(kept.size(), [&](std::size_t j, viewpoints::FovScorer::Workspace&) {
    views[j] = std::move(described[kept[j]]);
    name_seen(views[j], seen[kept[j]]);
  });
  return views;
}

}  // namespace fvx::nbv::detail
