// Rendering speed of the virtual Kinect: one 640×480 frame of a 100k-triangle scene through
// Embree and CGAL's AABB tree, and on a small scene each tree against a brute-force
// per-triangle test, in the same run. Reports medians of 5 repetitions and their ratios.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <random>

#include "fvx/sim/depth_sensor.hpp"

namespace {

/// A floor and `boxes` seeded random crates of 5–20 cm in front of a sensor at the origin
/// looking along +x (12 triangles each).
fvx::sim::Mesh rubble(int boxes) {
  fvx::sim::Mesh mesh;
  mesh.add_box(Eigen::AlignedBox3f(Eigen::Vector3f(0, -3, -1.05f), Eigen::Vector3f(5, 3, -1.0f)));
  std::mt19937 rng(42);
  std::uniform_real_distribution<float> x(0.8f, 4.0f), y(-2.0f, 2.0f), z(-1.0f, 0.8f), size(0.05f, 0.2f);
  for (int i = 0; i < boxes; ++i) {
    const Eigen::Vector3f lo(x(rng), y(rng), z(rng));
    mesh.add_box(Eigen::AlignedBox3f(lo, lo + Eigen::Vector3f(size(rng), size(rng), size(rng))));
  }
  return mesh;
}

const fvx::sim::Mesh& large_scene() {
  static const fvx::sim::Mesh mesh = rubble(8333);  // 12 + 8333·12 = 100 008 triangles
  return mesh;
}
const fvx::sim::Mesh& small_scene() {
  static const fvx::sim::Mesh mesh = rubble(83);  // 1 008 triangles
  return mesh;
}

Eigen::Isometry3d sensor_pose() {
  // Optical z along world +x, x right (−y), y down (−z).
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  return T;
}

void render(benchmark::State& state, const fvx::sim::Mesh& mesh, fvx::sim::Backend backend, int width) {
  const auto caster = fvx::sim::make_ray_caster(mesh, backend);
  fvx::sim::SensorConfig config;
  config.intrinsics.width = width;
  config.intrinsics.height = width * 3 / 4;
  config.intrinsics.fx = config.intrinsics.fy = 525.0 * width / 640.0;
  config.intrinsics.cx = (width - 1) / 2.0;
  config.intrinsics.cy = (width * 3 / 4 - 1) / 2.0;
  config.depth_max_m = 8.0;
  std::size_t valid = 0;
  for (auto _ : state) valid = fvx::sim::render(*caster, sensor_pose(), config).valid;
  state.counters["triangles"] = double(mesh.triangles.size());
  state.counters["valid_pixels"] = double(valid);
}

void BM_Large_Embree(benchmark::State& s) { render(s, large_scene(), fvx::sim::Backend::Embree, 640); }
void BM_Large_CgalAabb(benchmark::State& s) { render(s, large_scene(), fvx::sim::Backend::CgalAabb, 640); }
void BM_Small_Embree(benchmark::State& s) { render(s, small_scene(), fvx::sim::Backend::Embree, 160); }
void BM_Small_CgalAabb(benchmark::State& s) { render(s, small_scene(), fvx::sim::Backend::CgalAabb, 160); }
void BM_Small_BruteForce(benchmark::State& s) { render(s, small_scene(), fvx::sim::Backend::BruteForce, 160); }

BENCHMARK(BM_Large_Embree)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true)->Iterations(10);
BENCHMARK(BM_Large_CgalAabb)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true)->Iterations(1);
BENCHMARK(BM_Small_Embree)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true)->Iterations(20);
BENCHMARK(BM_Small_CgalAabb)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true)->Iterations(5);
BENCHMARK(BM_Small_BruteForce)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true)->Iterations(1);

/// Prints as usual and keeps the median real time of each benchmark.
class MedianReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& run : runs)
      if (run.run_type == Run::RT_Aggregate && run.aggregate_name == "median")
        ms_[run.run_name.function_name] = run.GetAdjustedRealTime();
  }
  double ms(const std::string& name) const { return ms_.at(name); }

 private:
  std::map<std::string, double> ms_;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  MedianReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  std::printf("\n640x480 frame, %zu triangles: Embree %.1f ms (target < 100 ms), CGAL AABB tree %.1f ms "
              "(Embree %.1fx faster)\n",
              large_scene().triangles.size(), reporter.ms("BM_Large_Embree"), reporter.ms("BM_Large_CgalAabb"),
              reporter.ms("BM_Large_CgalAabb") / reporter.ms("BM_Large_Embree"));
  std::printf("160x120 frame, %zu triangles: brute force %.1f ms; AABB trees faster by: Embree %.0fx, CGAL %.0fx\n",
              small_scene().triangles.size(), reporter.ms("BM_Small_BruteForce"),
              reporter.ms("BM_Small_BruteForce") / reporter.ms("BM_Small_Embree"),
              reporter.ms("BM_Small_BruteForce") / reporter.ms("BM_Small_CgalAabb"));
  return 0;
}
