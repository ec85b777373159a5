// Integration speed: one 640×480 Kinect frame at 2.5 cm, 4 m range, through fvx (exact and
// --discretize; and the whole step: integrated, then frontiers, voids and frontier-voids
// updated from the change set, as issue 21 counts it) and through OctoMap's insertPointCloud
// (exact and discretised), in the same run;
// and the cells the rays visit per second beside a plain dense-grid DDA (the textbook
// Amanatides–Woo in float over a byte per cell, one thread) walking the same rays. Prints ratios against
// the OctoMap baselines measured in this run (machines are noisy; absolute times are not).
//
//   bench_integrate FRAME.pcd [google-benchmark flags]   (scripts/bench.sh passes a frame)
#include <benchmark/benchmark.h>
#include <octomap/OcTree.h>

#include <cmath>
#include <cstdio>
#include <map>

#include "../../src/map/ray_keys.hpp"
#include "fvx/map/occupancy_map.hpp"
#include "fvx/pipeline/pipeline.hpp"
#include "fvx/scan/load.hpp"

namespace {

constexpr double kResolutionM = 0.025;
constexpr double kMaxRangeM = 4.0;

std::vector<Eigen::Vector3f> g_points_world;
fvx::scan::Scan g_scan;  ///< the frame, its optical frame the world
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

/// The replay step without a search (fvx replay --no-register --search-every 0): the frame
/// integrated into an empty map, then frontiers, voids and frontier-voids from its change set.
void BM_FvxStep(benchmark::State& state) {
  fvx::pipeline::Config config;
  config.resolution_m = kResolutionM;
  config.max_range_m = kMaxRangeM;
  config.search = false;
  for (auto _ : state) {
    fvx::pipeline::State map_state(kResolutionM);
    map_state.analysed = true;  // the empty sets are the empty map's: updated from the change set, not rebuilt
    const fvx::pipeline::StepResult r = fvx::pipeline::integrate_step(map_state, g_scan, config);
    benchmark::DoNotOptimize(r.analysis.void_cells.data());
    state.counters["void_cells"] = double(r.analysis.void_cells.size());
    state.counters["integrate_ms"] = 1e3 * r.timing.integration_s;
    state.counters["analyse_ms"] = 1e3 * r.timing.frontiers_voids_s;
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
BENCHMARK(BM_FvxStep)->Unit(benchmark::kMillisecond)->MinTime(3.0);
BENCHMARK(BM_OctoMapInsertPointCloud)->Unit(benchmark::kMillisecond)->MinTime(3.0);
BENCHMARK(BM_OctoMapInsertPointCloudDiscrete)->Unit(benchmark::kMillisecond)->MinTime(3.0);

/// The rays as integrate() traces them: to each point, cut at kMaxRangeM.
std::vector<Eigen::Vector3f> ray_ends() {
  std::vector<Eigen::Vector3f> ends;
  for (const auto& p : g_points_world) {
    const Eigen::Vector3f d = p - g_origin_world;
    ends.push_back(d.norm() <= kMaxRangeM ? p : Eigen::Vector3f(g_origin_world + d.normalized() * float(kMaxRangeM)));
  }
  return ends;
}

/// Cells fvx's traversal visits for the frame (OctoMap's arithmetic, the end's cell excluded).
std::uint64_t fvx_cells_visited(const std::vector<Eigen::Vector3f>& ends) {
  const octomap::OcTree tree(kResolutionM);
  const octomap::point3d o(g_origin_world.x(), g_origin_world.y(), g_origin_world.z());
  std::uint64_t visits = 0;
  for (const auto& e : ends)
    fvx::map::for_each_ray_key(tree, o, octomap::point3d(e.x(), e.y(), e.z()), [&](const octomap::OcTreeKey&) { ++visits; });
  return visits;
}

/// The textbook traversal: Amanatides–Woo in float over a dense byte grid around the rays,
/// one thread, marking each cell's byte; returns the cells visited.
struct DenseGrid {
  Eigen::Vector3f min_m;
  Eigen::Vector3i size;
  std::vector<std::uint8_t> cells;
};
DenseGrid grid_around(const std::vector<Eigen::Vector3f>& ends) {
  Eigen::AlignedBox3f box(g_origin_world);
  for (const auto& e : ends) box.extend(e);
  DenseGrid g{box.min() - Eigen::Vector3f::Constant(2 * kResolutionM), {}, {}};
  g.size = ((box.sizes().array() / float(kResolutionM)).ceil() + 4).cast<int>();
  g.cells.assign(std::size_t(g.size.prod()), 0);
  return g;
}
std::uint64_t dense_dda(DenseGrid& g, const std::vector<Eigen::Vector3f>& ends) {
  const float R = float(kResolutionM);
  const Eigen::Vector3f o = (g_origin_world - g.min_m) / R;  // in cells
  const Eigen::Vector3i start = o.array().floor().cast<int>();
  const std::int64_t stride[3] = {1, g.size.x(), std::int64_t(g.size.x()) * g.size.y()};
  std::uint64_t visits = 0;
  for (const auto& e_m : ends) {
    const Eigen::Vector3f e = (e_m - g.min_m) / R, d = e - o;
    const float length = d.norm();
    if (!(length > 0)) continue;
    const Eigen::Vector3f dir = d / length;
    Eigen::Vector3i cell = start;
    const Eigen::Vector3i last = e.array().floor().cast<int>();
    std::int64_t index = cell.x() + stride[1] * cell.y() + stride[2] * cell.z(), step_index[3];
    float t_max[3], t_delta[3];
    int step[3];
    for (int i = 0; i < 3; ++i) {
      step[i] = dir[i] > 0 ? 1 : dir[i] < 0 ? -1 : 0;
      step_index[i] = step[i] * stride[i];
      t_delta[i] = step[i] ? 1.0f / std::abs(dir[i]) : INFINITY;
      t_max[i] = step[i] ? ((float(cell[i]) + (step[i] > 0 ? 1.0f : 0.0f)) - o[i]) / dir[i] : INFINITY;
    }
    while (cell != last) {
      g.cells[std::size_t(index)] = 1;
      ++visits;
      const int a = t_max[0] < t_max[1] ? (t_max[0] < t_max[2] ? 0 : 2) : (t_max[1] < t_max[2] ? 1 : 2);
      if (t_max[a] > length) break;
      cell[a] += step[a], index += step_index[a], t_max[a] += t_delta[a];
    }
  }
  return visits;
}

std::vector<Eigen::Vector3f> g_ends;
std::uint64_t g_dense_visits = 0;

void BM_PlainDenseGridDda(benchmark::State& state) {
  DenseGrid grid = grid_around(g_ends);
  for (auto _ : state) {
    g_dense_visits = dense_dda(grid, g_ends);
    benchmark::DoNotOptimize(grid.cells.data());
  }
}
BENCHMARK(BM_PlainDenseGridDda)->Unit(benchmark::kMillisecond)->MinTime(3.0);

/// Prints as usual and keeps each benchmark's mean real time for the ratio lines.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& run : runs)
      if (run.run_type == Run::RT_Iteration) {
        seconds_[run.run_name.function_name] = run.GetAdjustedRealTime();
        for (const auto& [name, value] : run.counters) counters_[run.run_name.function_name + "/" + name] = value;
      }
  }
  double time(const std::string& name) const { return seconds_.at(name); }
  double counter(const std::string& benchmark, const std::string& name) const {
    return counters_.at(benchmark + "/" + name);
  }

 private:
  std::map<std::string, double> seconds_, counters_;
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
  g_scan = scan;
  std::printf("frame %s: %zu finite points, resolution %.3f m, max range %.1f m\n", argv[1],
              g_points_world.size(), kResolutionM, kMaxRangeM);

  g_ends = ray_ends();
  const std::uint64_t fvx_visits = fvx_cells_visited(g_ends);

  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  const double fvx_ms = reporter.time("BM_FvxIntegrate");
  const double exact_ms = reporter.time("BM_OctoMapInsertPointCloud");
  const double discrete_ms = reporter.time("BM_OctoMapInsertPointCloudDiscrete");
  std::printf("\nfvx integrate vs OctoMap insertPointCloud (exact, same map):  %.2fx faster\n", exact_ms / fvx_ms);
  std::printf("fvx integrate vs OctoMap insertPointCloud (discretised):      %.2fx faster\n", discrete_ms / fvx_ms);
  std::printf("fvx step (integrate + frontiers, voids, frontier-voids) vs OctoMap insertPointCloud (exact): %.2fx faster\n",
              exact_ms / reporter.time("BM_FvxStep"));
  // GetAdjustedRealTime is in the benchmark's unit (ms): cells per second = visits / (ms / 1000).
  const double plain_ms = reporter.time("BM_PlainDenseGridDda");
  std::printf("cells visited per frame: %llu by fvx's rays (OctoMap's arithmetic), %llu by the dense DDA\n",
              static_cast<unsigned long long>(fvx_visits), static_cast<unsigned long long>(g_dense_visits));
  std::printf("fvx integrate (traversal + tree update, all threads): %.0f M cells/s; plain dense-grid DDA "
              "(traversal alone, one thread, marking bytes): %.0f M cells/s\n",
              double(fvx_visits) / fvx_ms / 1e3, double(g_dense_visits) / plain_ms / 1e3);
  std::printf("changed cells per frame: %.0f, so each is visited %.0f times by the rays\n",
              reporter.counter("BM_FvxIntegrate", "changed_cells"),
              double(fvx_visits) / reporter.counter("BM_FvxIntegrate", "changed_cells"));
  const double fvx_discrete_ms = reporter.time("BM_FvxIntegrateDiscrete");
  std::printf("fvx integrate --discretize vs OctoMap insertPointCloud (discretised, same map): %.2fx faster\n",
              discrete_ms / fvx_discrete_ms);
  return 0;
}
