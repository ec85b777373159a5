#pragma once
// What a view of a suite scene really reveals, by the Kinect's rule on the scene's mesh: the
// ground truth of the clairvoyant benchmarks (bench_clairvoyant, bench_regret).
#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <thread>
#include <vector>

#include "fvx/core/ray_box.hpp"
#include "fvx/core/threads.hpp"
#include "fvx/io/intrinsics.hpp"
#include "fvx/map/dense_grid.hpp"
#include "fvx/map/occupancy_map.hpp"
#include "fvx/sim/ground_truth.hpp"
#include "fvx/sim/scene.hpp"
#include "fvx/sim/ray_caster.hpp"

namespace fvx::bench {

using CellSet = std::vector<std::uint32_t>;  // sorted numbers of observable void cells

/// What a view reveals by the Kinect's rule, as fvx integrates it: a ray to the mesh's first
/// hit, if its depth lies within the camera's, knows every cell it crosses up to the hit (the
/// ground truth's voxels are fatter than the surface: a ray may pass a solid cell's empty part).
class Reveal {
 public:
  Reveal(const sim::Scene& scene, const sim::GroundTruth& gt, const std::vector<Eigen::Vector3d>& void_centres,
         const io::DepthCamera& camera)
      : caster_(sim::make_ray_caster(scene.mesh)), truth_(gt.to_map()), camera_(camera),
        grid_(truth_, box_of(gt)), number_(grid_.cell_count(), -1) {
    const double R = gt.resolution_m();
    for (std::size_t c = 0; c < void_centres.size(); ++c) {
      const auto key = truth_.key_of(void_centres[c]);
      if (!key || !grid_.contains(*key)) continue;
      number_[grid_.index(*key)] = std::int32_t(c);
      read_box_m_.extend(void_centres[c] - Eigen::Vector3d::Constant(R));
      read_box_m_.extend(void_centres[c] + Eigen::Vector3d::Constant(R));
    }
  }

  const io::DepthCamera& camera() const { return camera_; }

  /// Per pose, the observable void cells the fan `rays_sensor` (depth 1 along z) reveals.
  std::vector<CellSet> sets(const std::vector<Eigen::Isometry3d>& poses,
                            const std::vector<Eigen::Vector3d>& rays_sensor) const {
    std::vector<CellSet> out(poses.size());
    std::atomic<std::size_t> next{0};
    auto work = [&] {
      for (std::size_t p = next++; p < poses.size(); p = next++) out[p] = one(poses[p], rays_sensor);
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < core::worker_count(0); ++t) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
    return out;
  }

  /// Of the fan's rays from T: how many measure a surface within the depths, how many meet
  /// one nearer than the minimum depth (the Kinect returns nothing), how many meet none.
  std::array<std::size_t, 3> depths(const Eigen::Isometry3d& T, const std::vector<Eigen::Vector3d>& rays_sensor) const {
    std::array<std::size_t, 3> n{};
    for (const Eigen::Vector3d& ray : rays_sensor) {
      const Eigen::Vector3d d = (T.linear() * ray).normalized();
      const sim::Hit hit = caster_->cast(T.translation().cast<float>(), d.cast<float>(), 0.0f,
                                         float(camera_.depth_max_m * ray.norm()));
      ++n[!hit.hit() ? 2 : double(hit.distance) < camera_.depth_min_m * ray.norm() ? 1 : 0];
    }
    return n;
  }

 private:
  static Eigen::AlignedBox3d box_of(const sim::GroundTruth& gt) {
    const double R = gt.resolution_m();
    const Eigen::Vector3d lo = gt.center_of(gt.first_cell()) - Eigen::Vector3d::Constant(R / 2);
    return Eigen::AlignedBox3d(lo, lo + gt.size().cast<double>() * R);
  }

  CellSet one(const Eigen::Isometry3d& T, const std::vector<Eigen::Vector3d>& rays_sensor) const {
    CellSet set;
    for (const Eigen::Vector3d& ray : rays_sensor) {  // ray.z() == 1: its length per metre of depth
      const Eigen::Vector3d d = (T.linear() * ray).normalized();
      if (ray_box_exit(read_box_m_, T.translation(), d, camera_.depth_max_m * ray.norm()) < 0) continue;
      const sim::Hit hit = caster_->cast(T.translation().cast<float>(), d.cast<float>(), 0.0f,
                                         float(camera_.depth_max_m * ray.norm()));
      if (!hit.hit() || double(hit.distance) < camera_.depth_min_m * ray.norm()) continue;
      grid_.walk_cells(grid_.states(), T.translation(), d, double(hit.distance), [&](std::size_t i, std::uint8_t) {
        if (number_[i] >= 0) set.push_back(std::uint32_t(number_[i]));
        return true;
      });
    }
    std::sort(set.begin(), set.end());
    set.erase(std::unique(set.begin(), set.end()), set.end());
    return set;
  }

  std::unique_ptr<sim::RayCaster> caster_;
  map::OccupancyMap truth_;
  io::DepthCamera camera_;
  map::DenseGrid grid_;
  std::vector<std::int32_t> number_;
  Eigen::AlignedBox3d read_box_m_;
};

}  // namespace fvx::bench
