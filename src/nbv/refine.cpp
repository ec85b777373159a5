#include <algorithm>
#include <cmath>

#include "search.hpp"

// What follows the paper's N poses (not in the paper): stepping the best poses back along
// their optical axis, trying them at other rolls, and a local climb from the best one. U
// (Eq. 3) of one candidate moves by 10-15 % with its roll or a tilt of a few degrees, so the
// best of N sampled poses depends on chance; these steps bring it to the local maximum
// nearby, which makes the answer stable under small changes of the field (a sampled
// accumulation, another seed).

namespace fvx::nbv::detail {

namespace {

std::vector<std::size_t> by_score(const std::vector<std::size_t>& U) {
  std::vector<std::size_t> order(U.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t l, std::size_t r) { return U[l] > U[r]; });
  return order;
}

/// The refinement step (Config::refine_poses): the best poses, stepped back along their
/// optical axis, each step kept if it passes the position and orientation checks.
std::vector<Pose> stepped_back(const Search& s, const std::vector<Pose>& poses, const std::vector<std::size_t>& U,
                               Pruning& pruning) {
  const std::vector<std::size_t> order = by_score(U);
  std::vector<Pose> out;
  Pruning checks;  // the refinement's own rejections are not the paper's pruning counts
  for (std::size_t j = 0; j < order.size() && j < std::size_t(s.config.refine_poses) && U[order[j]] > 0; ++j) {
    const Eigen::Isometry3d& T = poses[order[j]].T_world_sensor;
    for (int step = 1; step * s.config.refine_step_m <= s.config.refine_max_m + 1e-9; ++step) {
      const Eigen::Vector3d q = T.translation() - step * s.config.refine_step_m * T.linear().col(2);
      const auto key = s.grid.cell_of(q);
      if (!key) break;  // beyond the known cells nothing is free
      ++pruning.refinement_steps;
      if (!s.keep_position(*key, s.grid.center_of(*key), checks)) continue;
      Pose pose;
      pose.T_world_sensor.translation() = s.grid.center_of(*key);
      pose.T_world_sensor.linear() = s.snap_to_reach(pose.T_world_sensor.translation(), T.linear());
      pose.cell = poses[order[j]].cell;  // it serves the same frontier-voids
      pose.stepped_back_from = order[j];
      if (s.keep_orientation(pose, s.config.seed ^ (0xD1B54A32D192ED03ull * (pruning.refinement_steps + 1)), checks))
        out.push_back(std::move(pose));
    }
  }
  pruning.refinement_poses = out.size();
  return out;
}

/// The polish step (Config::polish_poses): the best poses at other rolls about their optical
/// axis, evenly over a half turn (the image is symmetric under it), each kept if it passes the
/// orientation checks (the position is unchanged).
std::vector<Pose> rolled(const Search& s, const std::vector<Pose>& poses, const std::vector<std::size_t>& U,
                         Pruning& pruning) {
  const std::vector<std::size_t> order = by_score(U);
  std::vector<Pose> out;
  Pruning checks;  // rejections here are not the paper's pruning counts
  for (std::size_t j = 0; j < order.size() && j < std::size_t(s.config.polish_poses) && U[order[j]] > 0; ++j) {
    for (int k = 1; k < s.config.polish_rolls; ++k) {
      const Eigen::Matrix3d R = poses[order[j]].T_world_sensor.linear() *
                                Eigen::AngleAxisd(M_PI * k / s.config.polish_rolls, Eigen::Vector3d::UnitZ());
      Pose pose = moved(poses[order[j]], poses[order[j]].T_world_sensor.translation(), R, order[j]);
      if (s.keep_orientation(pose, s.config.seed ^ (0x94D049BB133111EBull * (out.size() + 1)), checks))
        out.push_back(std::move(pose));
    }
  }
  pruning.polish_poses += out.size();
  return out;
}

/// The neighbours of `from` for one round of the climb: the viewpoint moved by ±step_m along
/// each world axis (to the centre of the cell there, skipped if that is its own cell), and
/// the optical axis tilted by ±angle about the image's x and y axes.
std::vector<Pose> neighbours(const Search& s, const Pose& from, std::size_t from_index, double step_m,
                             double angle_rad, Pruning& pruning) {
  const Eigen::Vector3d p = from.T_world_sensor.translation();
  const Eigen::Matrix3d R = from.T_world_sensor.linear();
  std::vector<Pose> out;
  Pruning checks;
  auto keep = [&](Pose pose, bool position_changed) {
    if (position_changed) {  // to the centre of the cell there, where the checks hold
      const auto key = s.grid.cell_of(pose.T_world_sensor.translation());
      if (!key || s.grid.center_of(*key) == p) return;  // off the grid, or the same cell
      pose.T_world_sensor.translation() = s.grid.center_of(*key);
      if (!s.keep_position(*key, pose.T_world_sensor.translation(), checks)) return;
    }
    if (s.keep_orientation(pose, s.config.seed ^ (0xBF58476D1CE4E5B9ull * (pruning.polish_poses + out.size() + 1)),
                           checks))
      out.push_back(std::move(pose));
  };
  for (int axis = 0; axis < 3; ++axis)
    for (const double sign : {-1.0, 1.0}) keep(moved(from, p + sign * step_m * Eigen::Vector3d::Unit(axis), R, from_index), true);
  for (int axis = 0; axis < 2; ++axis)
    for (const double sign : {-1.0, 1.0})
      keep(moved(from, p, R * Eigen::AngleAxisd(sign * angle_rad, Eigen::Vector3d::Unit(axis)).toRotationMatrix(), from_index),
           false);
  return out;
}

/// Scores `extra` and appends it, with its scores, to `poses` and `U`.
void score_more(const Search& s, std::vector<Pose> extra, std::vector<Pose>& poses, std::vector<std::size_t>& U,
                Result& result) {
  const std::vector<std::size_t> U_extra = s.score(*s.void_scorer, extra, result, s.screen_fan());
  poses.insert(poses.end(), std::make_move_iterator(extra.begin()), std::make_move_iterator(extra.end()));
  U.insert(U.end(), U_extra.begin(), U_extra.end());
}

/// The climb (Config::climb_rounds): from each of the polish_poses best poses (at least one),
/// each round scores its neighbours and moves to the best of them if it sees more; otherwise
/// its step and tilt halve. Several starts: the best pose's basin is not always the highest.
void climb(const Search& s, std::vector<Pose>& poses, std::vector<std::size_t>& U, Result& result) {
  if (poses.empty() || s.config.climb_rounds == 0) return;
  struct Climber {
    std::size_t at;
    double step_m, angle_rad;
  };
  std::vector<Climber> climbers;
  for (const std::size_t i : by_score(U))
    if (U[i] > 0 && climbers.size() < std::size_t(std::max(1, s.config.polish_poses)))
      climbers.push_back({i, s.config.climb_step_m, s.config.climb_angle_deg * M_PI / 180.0});
  for (int round = 0; round < s.config.climb_rounds; ++round) {
    std::vector<Pose> next;
    std::vector<std::size_t> first;  // where each climber's neighbours start in `next`
    for (const Climber& c : climbers) {
      first.push_back(next.size());
      std::vector<Pose> mine = neighbours(s, poses[c.at], c.at, c.step_m, c.angle_rad, result.pruning);
      next.insert(next.end(), std::make_move_iterator(mine.begin()), std::make_move_iterator(mine.end()));
    }
    first.push_back(next.size());
    result.pruning.polish_poses += next.size();
    const std::size_t base = poses.size();
    score_more(s, std::move(next), poses, U, result);  // all climbers' neighbours at once, in parallel
    for (std::size_t k = 0; k < climbers.size(); ++k) {
      Climber& c = climbers[k];
      std::size_t improved = c.at;
      for (std::size_t i = base + first[k]; i < base + first[k + 1]; ++i)
        if (U[i] > U[improved]) improved = i;
      if (improved == c.at) {
        c.step_m /= 2;
        c.angle_rad /= 2;
      }
      c.at = improved;
    }
  }
}

}  // namespace

Pose moved(const Pose& from, const Eigen::Vector3d& p_world, const Eigen::Matrix3d& R, std::size_t from_index) {
  Pose pose;
  pose.T_world_sensor.translation() = p_world;
  pose.T_world_sensor.linear() = R;
  pose.cell = from.cell;  // it serves the same frontier-voids
  pose.polished_from = from_index;
  return pose;
}

void refine(const Search& s, std::vector<Pose>& poses, std::vector<std::size_t>& U, Result& result) {
  score_more(s, stepped_back(s, poses, U, result.pruning), poses, U, result);
  score_more(s, rolled(s, poses, U, result.pruning), poses, U, result);
  climb(s, poses, U, result);
}

}  // namespace fvx::nbv::detail
