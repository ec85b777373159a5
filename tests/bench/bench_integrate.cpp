// Integration speed: one 640×480 Kinect frame at 2.5 cm, 4 m range, through fvx (exact and
// --discretize) and through OctoMap's insertPointCloud (exact and discretised), in the same run. Prints ratios against
// the OctoMap baselines measured in this run (machines are noisy; absolute times are not).
//
//   bench_integrate FRAME.pcd [google-benchmark flags]   (scripts/bench.sh passes a frame)
#include <benchmark/benchmark.h>
#include <octomap/OcTree.h>

#include <cstdio>
#include <map>

#include "fvx/map/occupancy_map.hpp"
#include "fvx/scan/load.hpp"

namespace {

constexpr double kResolutionM = 0.025;
constexpr double kMaxRangeM = 4.0;

std::vector<Eigen::Vector3f> g_points_world;
Eigen::Vector3f g_origin_world = Eigen::Vector3f::Zero();

octomap::Pointcloud octomap_cloud() {
  octomap::Pointcloud cloud;
  cloud.reserve(g_points_world.size());
  for (const auto& p : g_points_world) cloud.push_back(p.x(), p.y(), p.z());
  return cloud;
}

void BM_FvxIntegrate(benchmark::State& state) {
  for (auto _ : state) {
    fvx::map::OccupancyMap map(kResolutionM);
    const auto result = map.integrate(g_points_world, g_origin_world, kMaxRangeM);
    benchmark::DoNotOptimize(result.changes.data());
    state.counters["changed_cells"] = double(result.changes.size());
  }
}

void BM_FvxIntegrateDiscrete(benchmark::State& state) {
  for (auto _ : state) {
    fvx::map::OccupancyMap map(kResolutionM);
    const auto result = map.integrate(g_points_world, g_origin_world, kMaxRangeM, true);
    benchmark::DoNotOptimize(result.changes.data());
    state.counters["rays"] = double(result.points);
  }
}

void octomap_insert(benchmark::State& state, bool discretize) {
  const octomap::Pointcloud cloud = octomap_cloud();
  const octomap::point3d origin(g_origin_world.x(), g_origin_world.y(), g_origin_world.z());
  for (auto _ : state) {
    octomap::OcTree tree(kResolutionM);
    tree.insertPointCloud(cloud, origin, kMaxRangeM, false, discretize);
    benchmark::DoNotOptimize(tree.size());
  }
}
void BM_OctoMapInsertPointCloud(benchmark::State& state) { octomap_insert(state, false); }
void BM_OctoMapInsertPointCloudDiscrete(benchmark::State& state) { octomap_insert(state, true); }

BENCHMARK(BM_FvxIntegrate)->Unit(benchmark::kMillisecond)->MinTime(3.0);
BENCHMARK(BM_FvxIntegrateDiscrete)->Unit(benchmark::kMillisecond)->MinTime(3.0);
BENCHMARK(BM_OctoMapInsertPointCloud)->Unit(benchmark::kMillisecond)->MinTime(3.0);
BENCHMARK(BM_OctoMapInsertPointCloudDiscrete)->Unit(benchmark::kMillisecond)->MinTime(3.0);

/// Prints as usual and keeps each benchmark's mean real time for the ratio lines.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& run : runs)
      if (run.run_type == Run::RT_Iteration) seconds_[run.run_name.function_name] = run.GetAdjustedRealTime();
  }
  double time(const std::string& name) const { return seconds_.at(name); }

 private:
  std::map<std::string, double> seconds_;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (argc != 2) {
    std::fprintf(stderr, "usage: bench_integrate FRAME.pcd [benchmark flags]\n");
    return 2;
  }
  fvx::scan::LoadConfig load;
  load.use_viewpoint = false;  // the frame's own optical frame is the world
  std::vector<std::string> warnings;
  fvx::scan::Scan scan = fvx::scan::load_scan({argv[1], std::nullopt, fvx::scan::PoseSource::Identity, std::nullopt}, load, warnings);
  fvx::scan::filter(scan, {});
  g_points_world = fvx::scan::to_world(scan);
  std::printf("frame %s: %zu finite points, resolution %.3f m, max range %.1f m\n", argv[1],
              g_points_world.size(), kResolutionM, kMaxRangeM);

  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  const double fvx_ms = reporter.time("BM_FvxIntegrate");
  const double exact_ms = reporter.time("BM_OctoMapInsertPointCloud");
  const double discrete_ms = reporter.time("BM_OctoMapInsertPointCloudDiscrete");
  std::printf("\nfvx integrate vs OctoMap insertPointCloud (exact, same map):  %.2fx faster\n", exact_ms / fvx_ms);
  std::printf("fvx integrate vs OctoMap insertPointCloud (discretised):      %.2fx faster\n", discrete_ms / fvx_ms);
  const double fvx_discrete_ms = reporter.time("BM_FvxIntegrateDiscrete");
  std::printf("fvx integrate --discretize vs OctoMap insertPointCloud (discretised, same map): %.2fx faster\n",
              discrete_ms / fvx_discrete_ms);
  return 0;
}
