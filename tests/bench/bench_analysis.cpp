// Where the whole `fvx nbv` spends its time before the search, stage by stage, on a map file:
// reading it; the incremental path (the frontier and void sets rebuilt, their cells, the
// clusters, the pairing); the one-shot dense path of the commands (frontier_voids::analyse_map)
// with its dense stages; the search's distance transform. Each stage is timed once, in order.
//
//   bench_analysis MAP.bt|MAP.ot [SEED]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "fvx/frontier_voids/frontier_voids.hpp"
#include "fvx/frontiers/frontiers.hpp"
#include "fvx/map/dense_grid.hpp"
#include "fvx/voids/clusters.hpp"
#include "fvx/voids/voids.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point& t) {
  const auto now = Clock::now();
  const double ms = std::chrono::duration<double, std::milli>(now - t).count();
  t = now;
  return ms;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_analysis MAP.bt|MAP.ot [SEED]\n");
    return 2;
  }
  namespace fv = fvx::frontier_voids;
  auto t = Clock::now();
  const auto map = fvx::map::OccupancyMap::load(argv[1]);
  std::printf("load            %8.1f ms\n", ms_since(t));
  fvx::frontiers::FrontierSet frontier_set;
  frontier_set.rebuild(map);
  std::printf("frontier set    %8.1f ms  %zu cells\n", ms_since(t), frontier_set.size());
  fvx::voids::VoidSet void_set;
  void_set.rebuild(map);
  std::printf("void set        %8.1f ms  %zu cells\n", ms_since(t), void_set.size());
  const fvx::map::Stats stats = map.stats();
  const Eigen::AlignedBox3d box(stats.known_min_m, stats.known_max_m);
  fv::Analysis a;
  a.frontier_cells = frontier_set.cells(map, box);
  std::printf("frontier cells  %8.1f ms\n", ms_since(t));
  a.frontier_clusters = fvx::frontiers::cluster(map, a.frontier_cells);
  std::printf("frontier clust. %8.1f ms  %zu clusters\n", ms_since(t), a.frontier_clusters.size());
  a.void_cells = void_set.cells(map, box);
  std::printf("void cells      %8.1f ms\n", ms_since(t));
  fvx::voids::ClusterConfig config;
  config.seed = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 1;
  a.void_clusters = fvx::voids::cluster_voids(map, a.void_cells, config);
  std::printf("void clusters   %8.1f ms  %zu clusters\n", ms_since(t), a.void_clusters.size());
  a.frontier_voids = fv::pair_frontier_voids(a.void_clusters, a.frontier_clusters);
  std::printf("pairing         %8.1f ms\n", ms_since(t));
  const fvx::map::DenseGrid grid(map, box);
  std::printf("dense grid      %8.1f ms  %zu cells\n", ms_since(t), grid.cell_count());
  const auto frontier_cells = fvx::frontiers::frontier_cells(grid);
  std::printf("dense frontiers %8.1f ms  %zu cells\n", ms_since(t), frontier_cells.size());
  fvx::voids::Hull hull;
  const auto void_cells = fvx::voids::void_cells(grid, hull);
  std::printf("dense voids     %8.1f ms  %zu cells\n", ms_since(t), void_cells.size());
  const fv::Analysis one_shot = fv::analyse_map(map, std::nullopt, config);
  std::printf("analyse_map     %8.1f ms  (all of the one-shot path)\n", ms_since(t));
  if (one_shot.void_cells != a.void_cells || one_shot.frontier_cells != a.frontier_cells) {
    std::fprintf(stderr, "bench_analysis: the one-shot path differs from the sets\n");
    return 1;
  }
  const auto d = fvx::map::squared_distance_to(grid, fvx::map::VoxelState::Occupied);
  std::printf("distance        %8.1f ms\n", ms_since(t));
  return d.empty() ? 1 : 0;
}
