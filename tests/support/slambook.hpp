#pragma once
// The slambook-joinmap-5kf frames with the recipe of its PROVENANCE.md (fx/fy/cx/cy
// 518/519/325.5/253.5, depth in mm, depth < 7 m, poses by order), for tests that integrate
// them. Needs fvx_scan.
#include <string>
#include <vector>

#include "fvx/scan/load.hpp"

namespace fvx::test {

/// Calls f(points_world, origin_world, path) for each of the five frames in order.
template <typename F>
void for_each_slambook_frame(const std::string& frames_dir, F f) {
  scan::LoadConfig load;
  load.intrinsics = io::Intrinsics{518.0, 519.0, 325.5, 253.5, 1000.0, 640, 480};
  load.trajectory_path = frames_dir + "/pose.txt";
  std::vector<std::string> paths;
  for (int i = 1; i <= 5; ++i) paths.push_back(frames_dir + "/depth/" + std::to_string(i) + ".pgm");
  scan::FilterConfig filter;
  filter.depth_max_m = 7.0;  // the recipe drops d >= 7000 mm
  std::vector<std::string> warnings;
  for (const auto& source : scan::plan_scans(paths, load).scans) {
    scan::Scan s = scan::load_scan(source, load, warnings);
    scan::filter(s, filter);
    f(scan::to_world(s), Eigen::Vector3f(s.T_world_sensor.translation().cast<float>()), source.path);
  }
}

}  // namespace fvx::test
