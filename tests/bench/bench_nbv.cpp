// The next-best-view search on the synthetic scenes, against the exhaustive strategy in the
// same run, with the time split; and the hot path, field-of-view ray casting, in cells per
// second against a plain 3-D DDA over the same dense cells and against octree look-ups.
//
//   bench_nbv CAPMAP.fcm [REPEATS]      (the repository's data/arms/fvx-arm.fcm)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

#include "fvx/nbv/nbv.hpp"
#include "fvx/sim/builtin_scenes.hpp"
#include "fvx/sim/depth_sensor.hpp"
#include "fvx/viewpoints/fov.hpp"

namespace {

using namespace fvx;

template <typename F>
double seconds(F f) {
  const auto start = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// The first views of an exploration: from above the arm's base and from one side.
map::OccupancyMap scan(const sim::Scene& scene, double resolution_m) {
  const auto caster = sim::make_ray_caster(scene.mesh);
  const Eigen::Vector3d target = scene.info.search_space->center() - Eigen::Vector3d(0, 0, 0.1);
  map::OccupancyMap map(resolution_m);
  for (const Eigen::Vector3d& eye : {Eigen::Vector3d(0.05, 0.0, 0.95), Eigen::Vector3d(0.3, 0.75, 0.85)}) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = eye;
    T.linear() = viewpoints::look_along(target - eye, 0.0);
    const sim::Frame frame = sim::render(*caster, T, sim::SensorConfig{});
    std::vector<Eigen::Vector3f> points;
    for (const auto& p : frame.points_sensor)
      if (p.allFinite()) points.push_back((T * p.cast<double>()).cast<float>());
    map.integrate(points, eye.cast<float>());
  }
  return map;
}

/// A textbook Amanatides–Woo walk over the dense states: no callback, no targets.
std::uint64_t plain_dda(const map::DenseGrid& grid, const Eigen::Vector3d& o, const Eigen::Vector3d& dir, double range) {
  const double R = grid.resolution_m();
  const Eigen::Vector3i n = grid.size();
  const int lo[3] = {grid.min_key().x, grid.min_key().y, grid.min_key().z};
  int c[3], step[3];
  double t_max[3], t_delta[3];
  const Eigen::Vector3d d = dir.normalized();
  for (int a = 0; a < 3; ++a) {
    c[a] = int(std::floor(o[a] / R)) + 32768 - lo[a];
    if (c[a] < 0 || c[a] >= n[a]) return 0;
    step[a] = d[a] > 0 ? 1 : (d[a] < 0 ? -1 : 0);
    const double edge = (double(c[a] + lo[a] - 32768) + (step[a] > 0 ? 1.0 : 0.0)) * R;
    t_max[a] = step[a] ? (edge - o[a]) / d[a] : INFINITY;
    t_delta[a] = step[a] ? R / std::abs(d[a]) : INFINITY;
  }
  std::uint64_t cells = 0;
  while (true) {
    ++cells;
    const std::size_t i = (std::size_t(c[2]) * std::size_t(n.y()) + std::size_t(c[1])) * std::size_t(n.x()) + std::size_t(c[0]);
    if (grid.state_at(i) == map::VoxelState::Occupied) return cells;
    const int a = t_max[0] < t_max[1] ? (t_max[0] < t_max[2] ? 0 : 2) : (t_max[1] < t_max[2] ? 1 : 2);
    if (t_max[a] > range) return cells;
    c[a] += step[a];
    if (c[a] < 0 || c[a] >= n[a]) return cells;
    t_max[a] += t_delta[a];
  }
}

/// The same walk with an octree look-up per cell instead of the dense array.
std::uint64_t octree_dda(const map::OccupancyMap& map, const map::DenseGrid& grid, const Eigen::Vector3d& o,
                         const Eigen::Vector3d& dir, double range) {
  std::uint64_t cells = 0;
  grid.walk(o, dir, range, [&](std::size_t i, map::VoxelState) {
    ++cells;
    return map.state(grid.key(i)) != map::VoxelState::Occupied;
  });
  return cells;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_nbv CAPMAP.fcm [REPEATS] [far-voids-only]\n");
    return 2;
  }
  const int repeats = argc > 2 ? std::max(1, std::atoi(argv[2])) : 5;
  // The default counts every void cell crossed; "far-voids-only" what the sensor can measure.
  nbv::Config base;
  base.count_near_void_cells = !(argc > 3 && std::string(argv[3]) == "far-voids-only");
  const capmap::CapabilityMap capmap = capmap::CapabilityMap::load(argv[1]);
  nbv::Reach reach{&capmap, Eigen::Isometry3d::Identity(), nullptr, {}};
  reach.T_world_base.translation() = Eigen::Vector3d(0.2, 0.0, 0.0);
  const double R = 0.025;
  std::printf("2 scans per scene at %.3f m; arm base (0.2, 0, 0); N = 50; 80x60 rays; median of %d; %s\n\n", R,
              repeats, base.count_near_void_cells ? "near void cells count" : "only measurable void cells count");
  std::printf("%-16s %7s %6s  %8s %8s %8s %8s %8s  %7s %9s  %8s %8s %6s\n", "scene", "voids", "fvs", "grid_s",
              "accum_s", "prune_s", "sample_s", "score_s", "total_s", "exhaust_s", "U_fv", "U_exh", "speed");
  std::vector<double> totals;
  for (const std::string name : {"closed-box", "crates", "paper-setting-1", "paper-setting-2"}) {
    const sim::Scene scene = sim::builtin_scene(name);
    const map::OccupancyMap map = scan(scene, R);
    frontiers::FrontierSet fs;
    fs.rebuild(map);
    voids::VoidSet vs;
    vs.rebuild(map);
    const auto a = frontier_voids::analyse(map, fs, &vs, scene.info.search_space, voids::ClusterConfig{});
    std::vector<double> grid, accum, prune, sample, score, total;
    nbv::Result fv;
    for (int r = 0; r < repeats; ++r) {
      fv = nbv::select(map, a, reach, base);
      grid.push_back(fv.timing.grid_s);
      accum.push_back(fv.timing.accumulation_s);
      prune.push_back(fv.timing.pruning_s);
      sample.push_back(fv.timing.sampling_s);
      score.push_back(fv.timing.scoring_s);
      total.push_back(fv.timing.total_s);
    }
    nbv::Config ex_config = base;
    ex_config.strategy = nbv::Strategy::Exhaustive;
    nbv::Result ex;
    const double ex_s = seconds([&] { ex = nbv::select(map, a, reach, ex_config); });
    const std::size_t u_fv = fv.views.empty() ? 0 : fv.views.front().void_cells_seen;
    const std::size_t u_ex = ex.views.empty() ? 0 : ex.views.front().void_cells_seen;
    std::printf("%-16s %7zu %6zu  %8.3f %8.3f %8.3f %8.3f %8.3f  %7.3f %9.2f  %8zu %8zu %5.0fx  U %.0f%%\n",
                name.c_str(), a.void_cells.size(), a.frontier_voids.size(), median(grid), median(accum),
                median(prune), median(sample), median(score), median(total), ex_s, u_fv, u_ex,
                ex_s / median(total), u_ex ? 100.0 * double(u_fv) / double(u_ex) : 0.0);
    totals.push_back(median(total));
    // The share depends on which cells yield the N poses, so on the seed: show its spread.
    double share_sum = 0, share_min = 1e9;
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
      nbv::Config c = base;
      c.seed = seed;
      const nbv::Result r = nbv::select(map, a, reach, c);
      const double share = u_ex ? 100.0 * double(r.views.empty() ? 0 : r.views.front().void_cells_seen) / double(u_ex) : 0.0;
      share_sum += share;
      share_min = std::min(share_min, share);
    }
    std::printf("%-16s U share over seeds 1-4: mean %.0f%%, min %.0f%%\n", "", share_sum / 4, share_min);

    if (name != "paper-setting-2") continue;
    // The hot path on this map: 50 poses in the search space looking at its centre.
    const map::DenseGrid dense(map, Eigen::AlignedBox3d(map.stats().known_min_m, map.stats().known_max_m));
    core::LargeVector<std::uint8_t> target(dense.cell_count(), 0);
    for (const auto& k : a.void_cells)
      if (dense.contains(k)) target[dense.index(k)] = 1;
    const auto rays = viewpoints::ray_fan(io::Intrinsics{}, 80, 60);
    const viewpoints::FovScorer scorer(dense, target, rays, 4.0);
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Eigen::Isometry3d> poses;
    const auto& box = *scene.info.search_space;
    while (poses.size() < 50) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() = box.min() + (box.max() - box.min()).cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
      T.translation().z() += 0.4;
      const auto key = map.key_of(T.translation());
      if (!key || !dense.contains(*key) || dense.state(*key) != map::VoxelState::Free) continue;
      T.linear() = viewpoints::look_along(box.center() - T.translation(), 0.0);
      poses.push_back(T);
    }
    std::uint64_t cells_scorer = 0, cells_plain = 0, cells_octree = 0;
    viewpoints::FovScorer::Workspace ws;
    std::vector<double> t_scorer, t_plain, t_octree;
    for (int r = 0; r < repeats; ++r) {
      cells_scorer = cells_plain = cells_octree = 0;
      t_scorer.push_back(seconds([&] {
        for (const auto& T : poses) cells_scorer += scorer.score(T, ws).cells_visited;
      }));
      t_plain.push_back(seconds([&] {
        for (const auto& T : poses)
          for (const auto& ray : rays) cells_plain += plain_dda(dense, T.translation(), T.linear() * ray, 4.0 * ray.norm());
      }));
      t_octree.push_back(seconds([&] {
        for (const auto& T : poses)
          for (const auto& ray : rays)
            cells_octree += octree_dda(map, dense, T.translation(), T.linear() * ray, 4.0 * ray.norm());
      }));
    }
    std::printf("\nfield-of-view ray casting, one thread, %zu poses x %zu rays on %s (%zu cells):\n", poses.size(),
                rays.size(), name.c_str(), dense.cell_count());
    std::printf("  fvx scorer (dense DDA + void stamps)  %10llu cells  %8.1f M cells/s\n",
                (unsigned long long)cells_scorer, double(cells_scorer) / median(t_scorer) / 1e6);
    std::printf("  plain 3-D DDA over the dense grid     %10llu cells  %8.1f M cells/s\n",
                (unsigned long long)cells_plain, double(cells_plain) / median(t_plain) / 1e6);
    std::printf("  same walk, octree look-up per cell    %10llu cells  %8.1f M cells/s\n\n",
                (unsigned long long)cells_octree, double(cells_octree) / median(t_octree) / 1e6);
  }
  std::printf("median search time over the scenes: %.3f s per view (target < 1 s)\n", median(totals));
  return 0;
}
