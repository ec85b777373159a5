// Incremental frontier and void updates against recomputing both from scratch, frame by
// frame over a Kinect sequence, in the same run (the machine's noise hits both alike).
//
//   bench_frontiers_voids DEPTH_DIR TRAJECTORY.log [FRAMES]   (Redwood layout: 00000.png …)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "fvx/frontiers/frontiers.hpp"
#include "fvx/scan/load.hpp"
#include "fvx/voids/voids.hpp"

namespace {

template <typename F>
double seconds(F f) {
  const auto start = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: bench_frontiers_voids DEPTH_DIR TRAJECTORY.log [FRAMES]\n");
    return 2;
  }
  const int frames = argc > 3 ? std::atoi(argv[3]) : 15;
  fvx::scan::LoadConfig load;
  load.intrinsics = fvx::io::Intrinsics{};  // PrimeSense / Kinect: 525, 319.5, 239.5, mm
  load.trajectory_path = argv[2];
  std::vector<std::string> paths;
  for (int i = 0; i < frames; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "/%05d.png", i);
    paths.push_back(std::string(argv[1]) + name);
  }
  const fvx::scan::ScanPlan plan = fvx::scan::plan_scans(paths, load);
  fvx::scan::FilterConfig filter;
  filter.depth_max_m = 4.0;

  fvx::map::OccupancyMap map(0.025);
  fvx::frontiers::FrontierSet frontiers;
  fvx::voids::VoidSet voids;
  std::vector<std::string> warnings;
  std::printf("frame  changed  frontier  void      incremental_ms (frontiers + voids)  from_scratch_ms  ratio\n");
  double sum_incremental = 0, sum_scratch = 0, sum_frontiers = 0;
  int later = 0;
  for (int i = 0; i < frames; ++i) {
    fvx::scan::Scan s = fvx::scan::load_scan(plan.scans[std::size_t(i)], load, warnings);
    fvx::scan::filter(s, filter);
    const auto changes = map.integrate(fvx::scan::to_world(s), s.T_world_sensor.translation().cast<float>(), 4.0).changes;
    const double frontier_s = seconds([&] { frontiers.update(map, changes); });
    const double incremental = frontier_s + seconds([&] { voids.update(map, changes); });
    fvx::frontiers::FrontierSet f2;
    fvx::voids::VoidSet v2;
    const double scratch = seconds([&] {
      f2.rebuild(map);
      v2.rebuild(map);
    });
    if (f2.size() != frontiers.size() || v2.size() != voids.size()) {
      std::fprintf(stderr, "frame %d: incremental and from-scratch sets differ\n", i);
      return 1;
    }
    std::printf("%5d  %7zu  %8zu  %8zu  %14.1f (%5.1f + %5.1f)  %15.1f  %5.1fx\n", i, changes.size(), frontiers.size(),
                voids.size(), incremental * 1e3, frontier_s * 1e3, (incremental - frontier_s) * 1e3, scratch * 1e3,
                scratch / incremental);
    if (i >= frames / 2) {
      sum_incremental += incremental;
      sum_frontiers += frontier_s;
      sum_scratch += scratch;
      ++later;
    }
  }
  std::printf("\nlater frames (%d to %d): incremental %.1f ms (frontiers %.1f ms), from scratch %.1f ms per frame: %.1fx faster\n",
              frames / 2, frames - 1, sum_incremental / later * 1e3, sum_frontiers / later * 1e3,
              sum_scratch / later * 1e3, sum_scratch / sum_incremental);
  return 0;
}
