// How few views could reach 95 % of a suite scene's observable void volume at all? A
// clairvoyant greedy planner on the ground truth: from the loop's own first view, each next
// view is the pose of the arm's capability map (the poses that define "observable") that
// reveals the most observable void cells not yet revealed, by the Kinect's rule on the ground
// truth (a ray reveals the cells it crosses when it measures a surface within the sensor's
// depths, every cell it crosses up to the mesh's first hit). It knows every surface: what a
// planner with perfect predictions of U would need with these poses, greedily (not the best
// sequence). Issue 17's "median of at most 7 views"; README, "Exploration over a scene suite".
//
//   bench_clairvoyant CAPMAP.fcm URDF FIRST LAST [FAN_COLS FAN_ROWS]
//
// One line per scene builtin:suite/N, N = FIRST..LAST (fvx explore's defaults: 2.5 cm, the
// Kinect's intrinsics and depths, seed 1, the arm at the scene's base); FAN default 320 x 240
// (a quarter of the image's pixels; the first view takes them all).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "fvx/core/pose.hpp"
#include "fvx/frontier_voids/frontier_voids.hpp"
#include "fvx/map/occupancy_map.hpp"
#include "fvx/nbv/loaded_arm.hpp"
#include "fvx/session/simulated_world.hpp"
#include "fvx/session/start.hpp"
#include "fvx/sim/builtin_scenes.hpp"
#include "fvx/viewpoints/fov.hpp"
#include "reveal.hpp"

namespace {

using namespace fvx;
using bench::CellSet;
using bench::Reveal;

/// Clairvoyant greedy from the first view (the last pose, every pixel): each next view the pose whose
/// dense fan reveals the most cells not yet revealed, among the kScreened poses whose coarse
/// fan does. The share of `total` revealed after each view (view 1 = the first).
std::vector<double> greedy_cover(const Reveal& reveal, const std::vector<Eigen::Isometry3d>& poses,
                                 const std::vector<CellSet>& coarse, const std::vector<Eigen::Vector3d>& dense_rays,
                                 std::size_t total, int views) {
  constexpr std::size_t kScreened = 64;
  std::vector<char> covered(total, 0);
  std::size_t count = 0;
  auto fresh = [&](const CellSet& s) {
    std::size_t n = 0;
    for (const std::uint32_t c : s) n += !covered[c];
    return n;
  };
  auto take = [&](const CellSet& s) {
    for (const std::uint32_t c : s) count += !covered[c], covered[c] = 1;
  };
  const io::Intrinsics& K = reveal.camera().intrinsics;
  take(reveal.sets({poses.back()}, viewpoints::ray_fan(K, K.width, K.height))[0]);
  std::vector<double> shares = {double(count) / double(total)};
  std::vector<std::size_t> order(poses.size());
  for (int v = 2; v <= views; ++v) {
    std::vector<std::size_t> gain(poses.size());
    for (std::size_t p = 0; p < poses.size(); ++p) gain[p] = fresh(coarse[p]), order[p] = p;
    const std::size_t k = std::min(kScreened, order.size());
    std::partial_sort(order.begin(), order.begin() + std::ptrdiff_t(k), order.end(),
                      [&](std::size_t l, std::size_t r) { return gain[l] > gain[r] || (gain[l] == gain[r] && l < r); });
    std::vector<Eigen::Isometry3d> screened;
    for (std::size_t i = 0; i < k; ++i) screened.push_back(poses[order[i]]);
    const std::vector<CellSet> dense = reveal.sets(screened, dense_rays);
    const auto best = std::max_element(dense.begin(), dense.end(),
                                       [&](const CellSet& l, const CellSet& r) { return fresh(l) < fresh(r); });
    take(*best);
    shares.push_back(double(count) / double(total));
  }
  return shares;
}

void run_scene(int n, const std::string& capmap, const std::string& urdf, int cols, int rows) {
  const sim::Scene scene = sim::scene_from("builtin:suite/" + std::to_string(n), "");
  const double deg = M_PI / 180.0;
  const auto& b = scene.info.bases.front();
  nbv::LoadedArm arm;
  nbv::load_arm(capmap, urdf, pose_from_xyz_rpy(b[0], b[1], b[2], b[3] * deg, b[4] * deg, b[5] * deg),
                "bench_clairvoyant", arm);
  const io::DepthCamera camera;  // fvx explore's default sensor
  const nbv::Config defaults;
  const Eigen::AlignedBox3d S = *scene.info.search_space;
  const session::SimulatedWorld world(scene, 0.025, S, std::nullopt, arm.T_world_base,
                                      S.center() - Eigen::Vector3d(0, 0, 0.1), arm.reach, camera,
                                      defaults.clearance_m, 1, 0, [](const std::string&) {});
  const sim::GroundTruth& gt = world.ground_truth();
  std::vector<Eigen::Isometry3d> poses = session::capmap_view_poses(*arm.reach, [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3i cell = gt.cell_of(p);
    return gt.contains(cell) && gt.solid(cell);
  });
  poses.push_back(world.start());
  const std::vector<Eigen::Vector3d> voids = world.score().observable_void_centres_m();
  if (voids.empty()) {
    std::printf("| suite/%d | 0 | - | - | - | - | - | - | - |\n", n);
    return;
  }
  const Reveal reveal(scene, gt, voids, camera);
  const std::vector<CellSet> coarse = reveal.sets(poses, viewpoints::ray_fan(camera.intrinsics, 20, 15));
  const std::vector<Eigen::Vector3d> dense_rays = viewpoints::ray_fan(camera.intrinsics, cols, rows);
  std::vector<char> any(voids.size(), 0);
  for (const CellSet& s : coarse)
    for (const std::uint32_t c : s) any[c] = 1;
  const double coverable = double(std::count(any.begin(), any.end(), 1)) / double(voids.size());
  const std::vector<double> shares = greedy_cover(reveal, poses, coarse, dense_rays, voids.size(), 15);
  const auto reached = std::find_if(shares.begin(), shares.end(), [](double s) { return s >= 0.95; });
  const std::string to95 = reached == shares.end() ? ">15" : std::to_string(reached - shares.begin() + 1);
  // The loop's own first view: the rendered frame integrated into a map, as fvx explore does.
  const session::Sensor kinect = world.kinect(sim::SensorConfig::of(camera, 1, 0));
  std::vector<Eigen::Vector3f> points_world;
  for (const Eigen::Vector3d& p : kinect(world.start(), 1)) points_world.push_back((world.start() * p).cast<float>());
  map::OccupancyMap map(0.025);
  map.integrate(points_world, world.start().translation().cast<float>(), camera.depth_max_m, false);
  std::size_t occupied = 0;
  for (const Eigen::Vector3d& c : voids) {
    const auto key = map.key_of(c);
    occupied += key && map.state(*key) == map::VoxelState::Occupied;
  }
  // Of the observable void cells still unknown after it, those U can count at all: void cells
  // of the map (in its own hull) in a void a frontier touches.
  const frontier_voids::Analysis a = frontier_voids::analyse_map(map, S, voids::ClusterConfig{});
  std::vector<map::VoxelKey> open;
  for (const auto& v : a.void_clusters)
    if (!a.frontier_voids[std::size_t(v.id)].enclosed()) open.insert(open.end(), v.cells.begin(), v.cells.end());
  std::sort(open.begin(), open.end());
  std::size_t unknown = 0, countable = 0;
  std::vector<map::VoxelKey> observable_keys;
  for (const Eigen::Vector3d& c : voids) {
    const auto key = map.key_of(c);
    if (!key) continue;
    observable_keys.push_back(*key);
    if (map.state(*key) != map::VoxelState::Unknown) continue;
    ++unknown;
    countable += std::binary_search(open.begin(), open.end(), *key);
  }
  // And what the open voids hold: observable void, solid in the ground truth, observable air
  // outside the scene's hull (the map's hull takes in the floor and walls, the metric's only
  // the surfaces in S), or neither (a sealed inside, space no pose measures).
  std::sort(observable_keys.begin(), observable_keys.end());
  std::vector<map::VoxelKey> air;  // every observable cell, in the hull or not
  for (const Eigen::Vector3d& c : world.score().observable_centres_m())
    if (const auto key = map.key_of(c)) air.push_back(*key);
  std::sort(air.begin(), air.end());
  std::size_t solid = 0, observable = 0, outside = 0;
  for (const map::VoxelKey& k : open) {
    if (std::binary_search(observable_keys.begin(), observable_keys.end(), k)) ++observable;
    else if (const Eigen::Vector3i cell = gt.cell_of(map.center_of(k)); gt.contains(cell) && gt.solid(cell)) ++solid;
    else outside += std::binary_search(air.begin(), air.end(), k);
  }
  std::printf("| suite/%d | %zu | %zu | %.3f | %.3f (map %.3f, %.3f occupied) | %.3f; %zu: %zu / %zu / %zu / %zu | %s "
              "| %.3f | %.3f |\n",
              n, voids.size(), poses.size(), coverable, shares[0], world.score().void_known_fraction(map),
              double(occupied) / double(voids.size()), unknown ? double(countable) / double(unknown) : 1.0, open.size(),
              observable, solid, outside, open.size() - observable - solid - outside, to95.c_str(), shares[6],
              shares[14]);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5 && argc != 7) {
    std::fprintf(stderr, "usage: bench_clairvoyant CAPMAP.fcm URDF FIRST LAST [FAN_COLS FAN_ROWS]\n");
    return 2;
  }
  const int first = std::atoi(argv[3]), last = std::atoi(argv[4]);
  const int cols = argc == 7 ? std::atoi(argv[5]) : 320, rows = argc == 7 ? std::atoi(argv[6]) : 240;
  if (first < 1 || last < first || cols < 1 || rows < 1) {
    std::fprintf(stderr, "bench_clairvoyant: FIRST >= 1, LAST >= FIRST, a fan of at least 1 x 1\n");
    return 2;
  }
  std::printf("fan %d x %d\n\n| scene | observable void cells | poses | any pose reveals "
              "| first view (every pixel; its frame integrated) "
              "| after it, the unknown observable void in the map's open voids; their cells: observable void / "
              "solid / observable air outside the hull / neither "
              "| views to 95 %% | after 7 views | after 15 views |\n|---|---|---|---|---|---|---|---|---|\n",
              cols, rows);
  try {
    for (int n = first; n <= last; ++n) run_scene(n, argv[1], argv[2], cols, rows);
  } catch (const std::exception& e) {  // a missing file, a scene the suite does not hold
    std::fprintf(stderr, "bench_clairvoyant: %s\n", e.what());
    return 1;
  }
  return 0;
}
