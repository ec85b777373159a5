// Capability maps: building the youBot map (5 cm, 200 directions) with the FK-seeded IK
// method (the earlier default) and with fk-witness (the default), fk-witness at 2.5 cm, the
// exhaustive per-direction IK loop as the baseline of FK-seeded IK on the same z-slab in the
// same run (the whole exhaustive map would take many minutes), lookups, file size.
//
//   bench_capmap YOUBOT.urdf
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <random>

#include "fvx/capmap/build.hpp"

namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: bench_capmap YOUBOT.urdf\n");
    return 2;
  }
  using namespace fvx::capmap;
  const Arm arm = Arm::from_urdf(argv[1], {"base_link", "arm_link_5"});
  BuildConfig config;  // 5 cm, 200 directions
  config.method = BuildMethod::FkSeededIk;

  auto t = std::chrono::steady_clock::now();
  BuildStats full;
  const CapabilityMap map = build_capability_map(arm, config, &full);
  const double full_s = seconds_since(t);
  const std::string path = (std::filesystem::temp_directory_path() / "bench_youbot.fcm").string();
  map.save(path);
  std::printf("youBot, 5 cm, 200 directions (FK-seeded): %.1f s, %zu bits checked by IK, %zu set, %zu IK iterations, "
              "%zu voxels, file %.0f KB\n",
              full_s, full.candidates, full.reached, full.ik_iterations, map.voxel_count(),
              std::filesystem::file_size(path) / 1024.0);

  // fk-witness (some pose in the voxel, the axis in the direction's cell), the same grid and
  // at 2.5 cm: the defaults (one FK per 8 witnesses, turned about arm_joint_1), and one FK per
  // witness (the same bits) as the baseline of the turn.
  for (const double voxel_m : {0.05, 0.025}) {
    double turned_s = 0;
    for (const bool turn : {true, false}) {
      BuildConfig witness_config;
      witness_config.voxel_m = voxel_m;
      witness_config.use_first_joint_turn = turn;
      t = std::chrono::steady_clock::now();
      BuildStats witness;
      const CapabilityMap witness_map = build_capability_map(arm, witness_config, &witness);
      const double witness_s = seconds_since(t);
      if (turn) turned_s = witness_s;
      witness_map.save(path);
      std::printf("youBot, %.1f cm, 200 directions (fk-witness, %s): %.2f s, %zu configurations, %zu FK, %zu bits set, "
                  "estimated recall %.4f, file %.0f KB (%.1fx faster than FK-seeded IK at 5 cm; turned %.1fx faster)\n",
                  voxel_m * 100, turn ? "turned" : "FK per witness", witness_s, witness.fk_samples,
                  witness.fk_evaluations, witness.reached, witness.estimated_recall,
                  std::filesystem::file_size(path) / 1024.0, full_s / witness_s, witness_s / turned_s);
    }
  }

  // The turn layout (witnesses in the first joint's coordinates, expanded on load) against the
  // grid at 5, 2.5 and 1.25 cm: build, file, load, and how many of each other's bits they hold.
  for (const double voxel_m : {0.05, 0.025, 0.0125}) {
    BuildConfig grid_config;
    grid_config.voxel_m = voxel_m;
    t = std::chrono::steady_clock::now();
    const CapabilityMap grid = build_capability_map(arm, grid_config);
    const double grid_s = seconds_since(t);
    grid.save(path);
    const double grid_kb = std::filesystem::file_size(path) / 1024.0;
    t = std::chrono::steady_clock::now();
    CapabilityMap::load(path);
    const double grid_load_s = seconds_since(t);
    grid_config.layout = MapLayout::Turn;
    t = std::chrono::steady_clock::now();
    BuildStats turn_stats;
    const CapabilityMap turn = build_capability_map(arm, grid_config, &turn_stats);
    const double turn_s = seconds_since(t);
    turn.save(path);
    t = std::chrono::steady_clock::now();
    CapabilityMap::load(path);
    const double turn_load_s = seconds_since(t);
    std::size_t grid_bits = 0, turn_bits = 0, shared = 0;
    for (const auto& [voxel, words] : grid.voxels())
      for (int d = 0; d < 200; ++d) grid_bits += grid.reachable(voxel, d), shared += grid.reachable(voxel, d) && turn.reachable(voxel, d);
    for (const auto& [voxel, words] : turn.voxels())
      for (int d = 0; d < 200; ++d) turn_bits += turn.reachable(voxel, d);
    std::printf("youBot, %.2f cm: grid %.2f s, %.0f KB, load %.3f s; turn layout %.2f s (%zu configurations, %zu "
                "witnesses), %.0f KB, load %.3f s; turn holds %.1f %% of the grid's bits, grid %.1f %% of the turn's\n",
                voxel_m * 100, grid_s, grid_kb, grid_load_s, turn_s, turn_stats.fk_samples, turn.turn_witnesses().size(),
                std::filesystem::file_size(path) / 1024.0, turn_load_s, 100.0 * shared / grid_bits,
                100.0 * shared / turn_bits);
  }

  // The same z-slab (the middle of 8) both ways.
  config.shard_count = 8;
  config.shard_index = 4;
  t = std::chrono::steady_clock::now();
  BuildStats seeded;
  const CapabilityMap slab = build_capability_map(arm, config, &seeded);
  const double seeded_s = seconds_since(t);
  config.method = BuildMethod::ExhaustiveIk;
  t = std::chrono::steady_clock::now();
  BuildStats exhaustive;
  const CapabilityMap slab_exhaustive = build_capability_map(arm, config, &exhaustive);
  const double exhaustive_s = seconds_since(t);
  std::size_t bits_seeded = 0, bits_exhaustive = 0, both = 0;
  for (const auto& [voxel, words] : slab_exhaustive.voxels())
    for (int d = 0; d < 200; ++d)
      if (slab_exhaustive.reachable(voxel, d)) {
        ++bits_exhaustive;
        both += slab.reachable(voxel, d);
      }
  for (const auto& [voxel, words] : slab.voxels())
    for (int d = 0; d < 200; ++d) bits_seeded += slab.reachable(voxel, d);
  std::printf("z-slab 5 of 8: FK-seeded %.1f s (%zu IK iterations, %zu bits); exhaustive %.1f s (%zu IK iterations, "
              "%zu bits); %.1fx faster; the seeded map has %zu of the exhaustive bits (%.0f %%)\n",
              seeded_s, seeded.ik_iterations, bits_seeded, exhaustive_s, exhaustive.ik_iterations, bits_exhaustive,
              exhaustive_s / seeded_s, both, bits_exhaustive ? 100.0 * both / bits_exhaustive : 0.0);

  // Lookups: random positions in the grid, random directions.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g(0, 1);
  const auto& h = map.header();
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> queries;
  for (int i = 0; i < 200000; ++i)
    queries.emplace_back(h.origin_m + Eigen::Vector3d(u(rng) * h.dims[0], u(rng) * h.dims[1], u(rng) * h.dims[2]) * h.voxel_m,
                         Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized());
  std::size_t yes = 0;
  t = std::chrono::steady_clock::now();
  for (const auto& [p, d] : queries) yes += map.reachable(p, d);
  const double query_s = seconds_since(t);
  std::printf("lookups: %.0f ns per query (%zu of %zu reachable)\n", query_s / double(queries.size()) * 1e9, yes,
              queries.size());
  return 0;
}
