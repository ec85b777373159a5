#pragma once
// A suite scene run through `fvx explore`'s own loop (its defaults, the arm at the scene's
// base), with what the clairvoyant benchmarks judge its views by: the true gain of a pose
// (reveal.hpp) and the best gain of any pose of the capability map (bench_regret,
// bench_rank_features).
#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "fvx/core/pose.hpp"
#include "fvx/nbv/loaded_arm.hpp"
#include "fvx/session/simulated_world.hpp"
#include "fvx/session/start.hpp"
#include "fvx/sim/builtin_scenes.hpp"
#include "fvx/viewpoints/fov.hpp"
#include "reveal.hpp"

namespace fvx::bench {

class SuiteLoop {
 public:
  SuiteLoop(int n, const std::string& capmap, const std::string& urdf, const std::string& tool)
      : scene_(sim::scene_from("builtin:suite/" + std::to_string(n), "")) {
    const double deg = M_PI / 180.0;
    const auto& b = scene_.info.bases.front();
    nbv::load_arm(capmap, urdf, pose_from_xyz_rpy(b[0], b[1], b[2], b[3] * deg, b[4] * deg, b[5] * deg), tool, arm_);
    S_ = *scene_.info.search_space;
    world_ = std::make_unique<session::SimulatedWorld>(scene_, 0.025, S_, std::nullopt, arm_.T_world_base,
                                                       S_.center() - Eigen::Vector3d(0, 0, 0.1), arm_.reach, camera_,
                                                       nbv::Config{}.clearance_m, 1, 0, [](const std::string&) {});
    const sim::GroundTruth& gt = world_->ground_truth();
    poses_ = session::capmap_view_poses(*arm_.reach, [&](const Eigen::Vector3d& p) {
      const Eigen::Vector3i cell = gt.cell_of(p);
      return gt.contains(cell) && gt.solid(cell);
    });
    centres_ = world_->score().observable_void_centres_m();
    if (centres_.empty()) return;
    reveal_ = std::make_unique<Reveal>(scene_, gt, centres_, camera_);
    coarse_ = reveal_->sets(poses_, viewpoints::ray_fan(camera_.intrinsics, 20, 15));
  }

  /// No observable void: nothing to judge.
  bool empty() const { return centres_.empty(); }

  /// Runs the loop with its defaults for `views` views, calling `each` after every view.
  void explore(int views, const std::function<void(const session::ViewRecord&, const pipeline::State&,
                                                   const session::ExploreConfig&)>& each) {
    session::ExploreConfig config;
    config.pipeline.bounds_m = S_;
    config.pipeline.nbv.sensor = camera_;
    config.pipeline.tie_to_search();
    config.max_views = views;
    config.T_world_sensor_start = world_->start();
    const session::Sensor kinect = world_->kinect(sim::SensorConfig::of(camera_, config.seed, 0));
    session::explore(kinect, arm_.reach, config,
                     [&](const session::ViewRecord& v, const pipeline::State& state) { each(v, state, config); });
  }

  /// The observable void cells of `set` that `map` does not know yet.
  std::size_t unknown_of(const map::OccupancyMap& map, const CellSet& set) const {
    std::size_t n = 0;
    for (const std::uint32_t c : set) {
      const auto key = map.key_of(centres_[c]);
      n += key && map.state(*key) == map::VoxelState::Unknown;
    }
    return n;
  }
  /// What the view from T reveals of the observable void `map` does not know (dense fan).
  double gain(const map::OccupancyMap& map, const Eigen::Isometry3d& T) const {
    return double(unknown_of(map, reveal_->sets({T}, dense_rays_)[0]));
  }
  double best_gain(const map::OccupancyMap& map, const std::vector<Eigen::Isometry3d>& poses) const {
    std::size_t best = 0;
    for (const CellSet& s : reveal_->sets(poses, dense_rays_)) best = std::max(best, unknown_of(map, s));
    return double(best);
  }
  /// The capability map's best pose: every pose screened by a 20 x 15 fan, the best 64 cast
  /// with the dense fan.
  double clairvoyant(const map::OccupancyMap& map) const {
    constexpr std::size_t kScreened = 64;
    std::vector<std::pair<std::size_t, std::size_t>> by_gain;  // (-gain, pose)
    for (std::size_t p = 0; p < poses_.size(); ++p) by_gain.push_back({~unknown_of(map, coarse_[p]), p});
    const std::size_t k = std::min(kScreened, by_gain.size());
    std::partial_sort(by_gain.begin(), by_gain.begin() + std::ptrdiff_t(k), by_gain.end());
    std::vector<Eigen::Isometry3d> screened;
    for (std::size_t i = 0; i < k; ++i) screened.push_back(poses_[by_gain[i].second]);
    return best_gain(map, screened);
  }

 protected:
  sim::Scene scene_;
  nbv::LoadedArm arm_;
  io::DepthCamera camera_;  // fvx explore's default sensor
  Eigen::AlignedBox3d S_;
  std::unique_ptr<session::SimulatedWorld> world_;
  std::vector<Eigen::Isometry3d> poses_;    ///< the capability map's poses, eye not in a solid
  std::vector<Eigen::Vector3d> centres_;    ///< the observable void cells
  /// The fan a true view is cast with: a quarter of the image's pixels.
  std::vector<Eigen::Vector3d> dense_rays_ = viewpoints::ray_fan(camera_.intrinsics, 320, 240);
  std::unique_ptr<Reveal> reveal_;
  std::vector<CellSet> coarse_;             ///< per pose of poses_, its 20 x 15 fan's set
};

}  // namespace fvx::bench
