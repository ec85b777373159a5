// Replay throughput on a long recorded sequence: the frames of a scan list with a trajectory
// (scripts/bench.sh passes the 211 Redwood frames) at 2.5 cm and 4 m, loaded into memory
// first, then in the same run
//  - OctoMap's own insertPointCloud, frame after frame into one tree (the baseline);
//  - fvx's replay step without the search: integrate, then update frontiers and voids
//    incrementally from the change set (the paper's "integration time");
//  - fvx's integration alone.
// Prints frames per second and the ratios against the baseline of this run.
//
//   bench_replay TRAJECTORY FRAME... [--frames N]
#include <octomap/OcTree.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "fvx/pipeline/pipeline.hpp"
#include "fvx/scan/load.hpp"

namespace {

constexpr double kResolutionM = 0.025;
constexpr double kMaxRangeM = 4.0;

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> frames;
  std::string trajectory;
  std::size_t limit = 0;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--frames") && i + 1 < argc) limit = std::stoul(argv[++i]);
    else if (trajectory.empty()) trajectory = argv[i];
    else frames.emplace_back(argv[i]);
  }
  if (trajectory.empty() || frames.empty()) {
    std::fprintf(stderr, "usage: bench_replay TRAJECTORY FRAME... [--frames N]\n");
    return 2;
  }
  if (limit && frames.size() > limit) frames.resize(limit);

  fvx::scan::LoadConfig load;
  load.trajectory_path = trajectory;
  load.intrinsics = fvx::io::Intrinsics{};  // PrimeSense defaults: 525, 525, 319.5, 239.5, 1000 per metre
  const fvx::scan::ScanPlan plan = fvx::scan::plan_scans(frames, load);
  fvx::scan::FilterConfig filter;
  filter.depth_max_m = kMaxRangeM;
  std::vector<fvx::scan::Scan> scans;
  std::size_t points = 0;
  for (const auto& source : plan.scans) {
    std::vector<std::string> warnings;
    fvx::scan::Scan s = fvx::scan::load_scan(source, load, warnings);
    fvx::scan::filter(s, filter);
    points += s.points_sensor.size();
    scans.push_back(std::move(s));
  }
  const double n = double(scans.size());
  std::printf("%zu frames, %.0f points per frame after the 4 m cut, %.3f m cells\n", scans.size(),
              double(points) / n, kResolutionM);

  // OctoMap: the same world points and origin, one tree for the whole sequence.
  double octomap_s = 0;
  {
    octomap::OcTree tree(kResolutionM);
    for (const auto& s : scans) {
      octomap::Pointcloud cloud;
      cloud.reserve(s.points_sensor.size());
      for (const auto& p : s.points_sensor) {
        const Eigen::Vector3d w = s.T_world_sensor * p;
        cloud.push_back(float(w.x()), float(w.y()), float(w.z()));
      }
      const Eigen::Vector3d o = s.T_world_sensor.translation();
      const auto t0 = Clock::now();
      tree.insertPointCloud(cloud, octomap::point3d(float(o.x()), float(o.y()), float(o.z())), kMaxRangeM);
      octomap_s += seconds_since(t0);
    }
    std::printf("OctoMap insertPointCloud:                 %7.2f frames/s  (%zu leaves)\n", n / octomap_s,
                tree.getNumLeafNodes());
  }

  // fvx: run_step without the search (integrate, frontiers and voids), as fvx replay
  // --search-every 0 --no-register runs it.
  fvx::pipeline::Config config;
  config.resolution_m = kResolutionM;
  config.max_range_m = kMaxRangeM;
  config.search = false;
  double step_s = 0, integrate_s = 0, frontiers_voids_s = 0;
  std::size_t void_cells = 0;
  {
    fvx::pipeline::State state(kResolutionM);
    for (auto& s : scans) {  // last use of the scans
      const auto t0 = Clock::now();
      const fvx::pipeline::StepResult r = fvx::pipeline::run_step(state, std::move(s), std::nullopt, config);
      step_s += seconds_since(t0);
      integrate_s += r.timing.integration_s;
      frontiers_voids_s += r.timing.frontiers_voids_s;
      void_cells = r.analysis.void_cells.size();
    }
  }
  std::printf("fvx replay step (integrate + frontiers/voids): %7.2f frames/s  (%.2fx OctoMap's rate; "
              "integration %.2f, frontiers/voids %.2f s in all; %zu void cells at the end)\n",
              n / step_s, octomap_s / step_s, integrate_s, frontiers_voids_s, void_cells);
  std::printf("fvx integration alone:                    %7.2f frames/s  (%.2fx OctoMap's rate)\n", n / integrate_s,
              octomap_s / integrate_s);
  return 0;
}
