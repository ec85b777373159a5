// The next best view on the closed box with one opening, scanned from six sides: the best
// view looks through the opening and reaches most of the exhaustive optimum; reachability,
// clearance, determinism and the empty answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>

#include "fvx/core/error.hpp"
#include "fvx/map/occupancy_map.hpp"
#include "fvx/nbv/nbv.hpp"
#include "fvx/sim/builtin_scenes.hpp"
#include "fvx/sim/depth_sensor.hpp"
#include "fvx/viewpoints/fov.hpp"
#include "../../../src/nbv/search.hpp"
#include "scan_scene.hpp"
#include "test_support.hpp"

namespace fvx::nbv {
namespace {

using test::source;

// The closed box (outer 0.52…1.02 × −0.27…0.23 × 0…0.40 m, walls 2 cm, a 16 cm opening in
// the middle of the lid) scanned from six sides at 1.3 m, 2 cm cells: every wall is known,
// the interior is unknown except what the first scans saw through the opening.
/// Views of the closed box's centre from `radius_m` away at each azimuth, `height_m` above it.
std::vector<Eigen::Isometry3d> views_of_the_box(double radius_m, double height_m, const std::vector<double>& azimuths_rad) {
  const Eigen::Vector3d centre(0.77, -0.02, 0.2);
  std::vector<Eigen::Isometry3d> views;
  for (const double a : azimuths_rad) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = centre + Eigen::Vector3d(radius_m * std::cos(a), radius_m * std::sin(a), height_m);
    T.linear() = viewpoints::look_along(centre - T.translation(), 0.0);
    views.push_back(T);
  }
  return views;
}

struct ClosedBox {
  map::OccupancyMap map{0.02};
  frontier_voids::Analysis analysis;
  ClosedBox() {
    std::vector<double> azimuths;
    for (int i = 0; i < 6; ++i) azimuths.push_back(2 * M_PI * i / 6);
    test::integrate_views(map, sim::builtin_scene("closed-box"), views_of_the_box(1.3, 0.7, azimuths));
    frontiers::FrontierSet frontier_set;
    frontier_set.rebuild(map);
    voids::VoidSet void_set;
    void_set.rebuild(map);
    analysis = frontier_voids::analyse(map, frontier_set, &void_set, std::nullopt, voids::ClusterConfig{});
  }
};

const ClosedBox& closed_box() {
  static const ClosedBox box;
  return box;
}

struct Arm {
  capmap::CapabilityMap capmap = capmap::CapabilityMap::load(source("data/arms/fvx-arm.fcm"));
  capmap::Arm arm = capmap::Arm::from_urdf(source("data/arms/fvx-arm.urdf"), capmap::arm_config_of(capmap.header()));
  Reach reach(const Eigen::Vector3d& base) const {
    Reach r{&capmap, Eigen::Isometry3d::Identity(), &arm, {}};
    r.T_world_base.translation() = base;
    r.ik.position_tolerance_m = capmap.header().position_tolerance_m;
    r.ik.angle_tolerance_rad = capmap.header().angle_tolerance_rad;
    return r;
  }
};

Config coarse() {
  Config c;
  c.ray_cols = 40;  // a quarter of the default rays: the exhaustive reference stays a few seconds
  c.ray_rows = 30;
  c.exhaustive_rolls = 1;
  return c;
}

TEST(Nbv, ClosedBoxTheBestViewLooksThroughTheOpening) {
  const ClosedBox& box = closed_box();
  ASSERT_GT(box.analysis.void_cells.size(), 5000u);
  const Arm arm;
  const Reach reach = arm.reach({0.2, 0.0, 0.0});
  const Result fv = select(box.map, box.analysis, reach, coarse());
  ASSERT_FALSE(fv.views.empty()) << fv.reason;
  EXPECT_EQ(fv.pruning.valid_poses, 50u);
  EXPECT_EQ(fv.poses_scored, 50u + fv.pruning.refinement_poses + fv.pruning.polish_poses);
  // The optical axis crosses the lid (z 0.38…0.40) inside the opening (x 0.69…0.85,
  // y −0.10…0.06), give or take one cell.
  const Eigen::Isometry3d& T = fv.views.front().T_world_sensor;
  const Eigen::Vector3d p = T.translation(), d = T.linear().col(2);
  ASSERT_GT(p.z(), 0.40);
  ASSERT_LT(d.z(), 0.0);
  const Eigen::Vector3d at_lid = p + d * ((0.39 - p.z()) / d.z());
  const double R = box.map.resolution_m();
  EXPECT_GT(at_lid.x(), 0.69 - R);
  EXPECT_LT(at_lid.x(), 0.85 + R);
  EXPECT_GT(at_lid.y(), -0.10 - R);
  EXPECT_LT(at_lid.y(), 0.06 + R);

  Config exhaustive = coarse();
  exhaustive.strategy = Strategy::Exhaustive;
  const Result ex = select(box.map, box.analysis, reach, exhaustive);
  ASSERT_FALSE(ex.views.empty()) << ex.reason;
  EXPECT_GT(ex.poses_scored, 1000u);
  EXPECT_GE(double(fv.views.front().void_cells_seen), 0.8 * double(ex.views.front().void_cells_seen))
      << "frontier-void " << fv.views.front().void_cells_seen << " vs exhaustive " << ex.views.front().void_cells_seen;
}

TEST(Nbv, EveryViewIsReachableInFreeSpaceOrAirAndClearWithItsJoints) {
  const ClosedBox& box = closed_box();
  const Arm arm;
  const Reach reach = arm.reach({0.2, 0.0, 0.0});
  Config config = coarse();
  config.top = 50;
  const Result r = select(box.map, box.analysis, reach, config);
  ASSERT_GE(r.views.size(), 5u);  // views with U > 0 among the 50 valid poses
  const auto occupied = box.map.occupied_centers();
  for (const View& v : r.views) {
    const Eigen::Vector3d p = v.T_world_sensor.translation(), d = v.T_world_sensor.linear().col(2);
    EXPECT_TRUE(arm.capmap.reachable(reach.T_world_base, p, d));
    ASSERT_EQ(v.joints_rad.size(), arm.arm.dof());
    const Eigen::Isometry3d T_base_sensor = arm.arm.fk(v.joints_rad);
    EXPECT_LT((reach.T_world_base * T_base_sensor.translation() - p).norm(), reach.ik.position_tolerance_m + 1e-9);
    EXPECT_LT(std::acos(std::min(1.0, arm.arm.viewing_direction(v.joints_rad).dot(d))), reach.ik.angle_tolerance_rad + 1e-9);
    // Free, or (Exterior::View, the default) unknown air outside the voids' hull.
    const map::VoxelKey eye = *box.map.key_of(p);
    if (box.map.state(eye) != map::VoxelState::Free) {
      EXPECT_EQ(box.map.state(eye), map::VoxelState::Unknown);
      EXPECT_FALSE(box.analysis.hull.contains(box.map.center_of(eye)));
    }
    double nearest = INFINITY;
    for (const auto& o : occupied) nearest = std::min(nearest, (o.cast<double>() - p).norm());
    EXPECT_GT(nearest, config.clearance_m - 1e-6);
    EXPECT_GT(v.void_cells_seen, 0u);
    EXPECT_FALSE(v.utility_from.empty());
    EXPECT_GT(v.accumulated_utility_m3, 0.0);
  }
  for (std::size_t i = 1; i < r.views.size(); ++i) EXPECT_GE(r.views[i - 1].void_cells_seen, r.views[i].void_cells_seen);
}

// The loops' searches pass over poses that repeat a view already taken (taken_views). The
// screened ranking rescores the first `top` + 10 poses in the coarse order with the full fan;
// with views taken it rescores the first that many new ones, a superset of the untaken
// search's new ones: its best view sees at least as much as the untaken search's best new one.
TEST(Nbv, TheLoopsSearchPassesOverViewsAlreadyTaken) {
  const ClosedBox& box = closed_box();
  const Arm arm;
  const Reach reach = arm.reach({0.2, 0.0, 0.0});
  const Config config = coarse();
  const Result free_choice = select(box.map, box.analysis, reach, config);
  ASSERT_GE(free_choice.views.size(), 3u) << free_choice.reason;
  EXPECT_EQ(free_choice.pruning.already_taken, 0u);
  const std::vector<Eigen::Isometry3d> taken = {free_choice.views[0].T_world_sensor,
                                                free_choice.views[1].T_world_sensor};
  const auto repeats = [&](const View& v) {
    return std::any_of(taken.begin(), taken.end(), [&](const auto& T) { return same_view(T, v.T_world_sensor); });
  };
  const auto first_new = std::find_if_not(free_choice.views.begin(), free_choice.views.end(), repeats);
  ASSERT_NE(first_new, free_choice.views.end());

  const Result r = select(box.map, box.analysis, reach, config, {}, taken);
  ASSERT_FALSE(r.views.empty()) << r.reason;
  EXPECT_GE(r.pruning.already_taken, 2u);
  for (const View& v : r.views) EXPECT_FALSE(repeats(v)) << "view " << v.pose_index << " repeats a taken one";
  EXPECT_GE(r.views[0].void_cells_seen, first_new->void_cells_seen);
  EXPECT_EQ(r.poses_scored, free_choice.poses_scored);  // the same poses were scored; only the ranking differs

  // Every pose the search scores taken: nothing new is left, and the reason says so.
  std::vector<Eigen::Isometry3d> all;
  for (const View& v : select(box.map, box.analysis, reach, [&] {
         Config every = config;
         every.top = 1000;
         return every;
       }()).views)
    all.push_back(v.T_world_sensor);
  const Result none = select(box.map, box.analysis, reach, config, {}, all);
  EXPECT_TRUE(none.views.empty());
  EXPECT_NE(none.reason.find("repeats one already taken"), std::string::npos) << none.reason;
}

// Refinement only adds poses: the best U never drops, the paper's N poses are unchanged, and
// each stepped-back view lies on the optical axis behind the pose it came from.
TEST(Nbv, SteppingBackAddsPosesBehindTheBestOnes) {
  const ClosedBox& box = closed_box();
  Config paper = coarse();  // free-flying: above the lid the arm reaches few steps back
  paper.refine_poses = 0;
  paper.polish_poses = 0;  // stepping back alone
  paper.climb_rounds = 0;
  paper.top = 100;
  Config refined = paper;
  refined.refine_poses = 10;
  const Result a = select(box.map, box.analysis, std::nullopt, paper),
               b = select(box.map, box.analysis, std::nullopt, refined);
  ASSERT_FALSE(a.views.empty());
  EXPECT_EQ(a.pruning.refinement_steps, 0u);
  EXPECT_EQ(a.pruning.valid_poses, b.pruning.valid_poses);
  EXPECT_GT(b.pruning.refinement_steps, 0u);
  EXPECT_EQ(b.poses_scored, a.poses_scored + b.pruning.refinement_poses);
  EXPECT_GE(b.views.front().void_cells_seen, a.views.front().void_cells_seen);
  std::size_t stepped = 0;
  for (const View& v : b.views) {
    if (!v.stepped_back_from) {
      EXPECT_LT(v.pose_index, b.pruning.valid_poses);
      continue;
    }
    ++stepped;
    EXPECT_GE(v.pose_index, b.pruning.valid_poses);
    const auto from = std::find_if(b.views.begin(), b.views.end(),
                                   [&](const View& o) { return o.pose_index == *v.stepped_back_from; });
    ASSERT_NE(from, b.views.end());  // it came from one of the best, which are listed (top 100)
    const Eigen::Vector3d back = from->T_world_sensor.translation() - v.T_world_sensor.translation();
    const Eigen::Vector3d axis = from->T_world_sensor.linear().col(2);
    const double along = back.dot(axis), R = box.map.resolution_m();
    EXPECT_GT(along, refined.refine_step_m - R);
    EXPECT_LT(along, refined.refine_max_m + R);
    EXPECT_LT((back - along * axis).norm(), R);  // snapped to a cell centre
  }
  EXPECT_GT(stepped, 0u) << "no stepped-back pose sees a void cell; steps " << b.pruning.refinement_steps
                         << ", poses " << b.pruning.refinement_poses;
  EXPECT_LE(stepped, b.pruning.refinement_poses);
}

TEST(Nbv, AFarBaseGivesNoViewAndSaysWhy) {
  const ClosedBox& box = closed_box();
  const Arm arm;
  const Result r = select(box.map, box.analysis, arm.reach({50.0, 0.0, 0.0}), coarse());
  EXPECT_TRUE(r.views.empty());
  EXPECT_NE(r.reason.find("pruning removed"), std::string::npos) << r.reason;
  EXPECT_GT(r.pruning.unreachable_position, 0u);
  EXPECT_EQ(r.pruning.candidate_cells, 0u);
  EXPECT_EQ(r.pruning.utility_cells, r.pruning.not_free + r.pruning.outside_view_bounds +
                                         r.pruning.too_close_to_obstacle + r.pruning.unreachable_position);
}

TEST(Nbv, TheSameSeedGivesTheSameViewsOnAnyThreadCount) {
  const ClosedBox& box = closed_box();
  Config one = coarse(), two = coarse();
  one.threads = 1;
  two.threads = 2;
  const Result a = select(box.map, box.analysis, std::nullopt, one), b = select(box.map, box.analysis, std::nullopt, two);
  ASSERT_FALSE(a.views.empty());
  ASSERT_EQ(a.views.size(), b.views.size());
  for (std::size_t i = 0; i < a.views.size(); ++i) {
    EXPECT_EQ(a.views[i].T_world_sensor.matrix(), b.views[i].T_world_sensor.matrix());
    EXPECT_EQ(a.views[i].void_cells_seen, b.views[i].void_cells_seen);
  }
  Config other = coarse();
  other.seed = 2;
  const Result c = select(box.map, box.analysis, std::nullopt, other);
  ASSERT_FALSE(c.views.empty());
  EXPECT_NE(a.views.front().T_world_sensor.matrix(), c.views.front().T_world_sensor.matrix());
}

// The sampled accumulation, forced to sample (a tenth of the exact vectors), against the exact
// one (its oracle), free-flying and on the arm: over seeds 1–8 its best views see on average
// at least 95 % of what the exact best views see (measured: 100 % and 103 %). One seed alone
// ranges 69–116 %: views into the box go through a 16 cm opening, and which candidate cells
// line up with it changes with any change of the field, up or down. With the climb on
// (Config::climb_rounds 4) the mean drops to 91 % free-flying: the exact field's candidates
// climb higher; that is why the climb is off by default.
TEST(Nbv, TheSampledFieldsBestViewsSeeWhatTheExactOnesDoOnAverage) {
  const ClosedBox& box = closed_box();
  const Arm arm;
  for (const bool on_arm : {false, true}) {
    const std::optional<Reach> reach = on_arm ? std::optional<Reach>(arm.reach({0.2, 0, 0})) : std::nullopt;
    double exact_sum = 0, sampled_sum = 0;
    for (const std::uint64_t seed : {1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u}) {
      Config exact = coarse();
      exact.seed = seed;
      exact.accumulation = utility::Accumulation::Exact;
      const Result e = select(box.map, box.analysis, reach, exact);
      ASSERT_FALSE(e.views.empty());
      ASSERT_GT(e.utility_vectors, 1000u);
      Config sampled = exact;
      sampled.accumulation = utility::Accumulation::Sampled;
      sampled.max_utility_vectors = e.utility_vectors / 10;
      const Result s = select(box.map, box.analysis, reach, sampled);
      ASSERT_FALSE(s.views.empty());
      EXPECT_LT(s.utility_vectors, e.utility_vectors / 5);
      EXPECT_EQ(s.exact_utility_vectors, e.exact_utility_vectors);
      exact_sum += double(e.views.front().void_cells_seen);
      sampled_sum += double(s.views.front().void_cells_seen);
      if (seed == 1 && !on_arm) {  // the same views on one thread
        sampled.threads = 1;
        const Result one = select(box.map, box.analysis, reach, sampled);
        EXPECT_EQ(one.views.front().T_world_sensor.matrix(), s.views.front().T_world_sensor.matrix());
      }
    }
    EXPECT_GE(sampled_sum, 0.95 * exact_sum) << (on_arm ? "arm" : "free-flying");
  }
}

/// Two first views of a paper replica (bench_nbv's): from above the arm's base and one side.
map::OccupancyMap replica(const std::string& name) {
  const sim::Scene scene = sim::builtin_scene(name);
  const Eigen::Vector3d target = scene.info.search_space->center() - Eigen::Vector3d(0, 0, 0.1);
  std::vector<Eigen::Isometry3d> views;
  for (const Eigen::Vector3d& eye : {Eigen::Vector3d(0.05, 0.0, 0.95), Eigen::Vector3d(0.3, 0.75, 0.85)}) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = eye;
    T.linear() = viewpoints::look_along(target - eye, 0.0);
    views.push_back(T);
  }
  map::OccupancyMap map(0.025);
  test::integrate_views(map, scene, views);
  return map;
}

/// The best view of the sampled accumulation (defaults) against the exact one with the same
/// seed, both scored by the same field-of-view ray cast: at least `share` of its void cells.
/// Returns whether the default budget made it sample (below it the two are one field); adds
/// the ratio to `ratios` when given.
bool expect_sampled_sees_what_exact_sees(const map::OccupancyMap& map, const std::optional<Reach>& reach,
                                         std::uint64_t seed, double share, const std::string& what,
                                         std::vector<double>* ratios = nullptr) {
  voids::ClusterConfig clusters;
  clusters.seed = seed;
  const frontier_voids::Analysis a = frontier_voids::analyse_map(map, std::nullopt, clusters);
  Config config;
  config.seed = seed;
  const Result sampled = select(map, a, reach, config);
  config.accumulation = utility::Accumulation::Exact;  // the exact path: every pose with the full fan too
  config.coarse_ray_cols = config.coarse_ray_rows = 0;
  const Result exact = select(map, a, reach, config);
  EXPECT_FALSE(exact.views.empty()) << what;
  EXPECT_FALSE(sampled.views.empty()) << what;
  if (exact.views.empty() || sampled.views.empty()) return false;
  if (ratios) ratios->push_back(double(sampled.views.front().void_cells_seen) / double(exact.views.front().void_cells_seen));
  EXPECT_GE(double(sampled.views.front().void_cells_seen), share * double(exact.views.front().void_cells_seen))
      << what << " seed " << seed << ": sampled " << sampled.views.front().void_cells_seen << ", exact "
      << exact.views.front().void_cells_seen;
  return sampled.utility_vectors < exact.utility_vectors;
}

// The criterion on both paper replicas (2.5 cm, the fvx arm at (0.2, 0, 0)), over
// seeds 1-8. Setting 1 traces about 8 M exact vectors and samples; setting 2 about 1.1 M,
// under the default budget, where the sampled field is the exact one. The replica maps come
// from simulated scans, whose last bits differ between CPUs (Embree); on an Intel machine
// seeds 1-3 of setting 1 gave 98.4-101 %, on an AMD EPYC seeds 1-8 gave 0.83-1.05 (seeds 2
// and 7: 0.83 and 0.87; mean 0.97) and setting 2 1.000 each. So each seed is held to 80 %
// and the mean to the 95 %: one seed in four or five falls below 95 % (README).
TEST(Nbv, OnThePaperReplicasTheSampledBestViewSeesWhatTheExactOneSees) {
  const Arm arm;
  bool sampled = false;
  for (const std::string name : {"paper-setting-1", "paper-setting-2"}) {
    const map::OccupancyMap map = replica(name);
    std::vector<double> ratios;
    for (const std::uint64_t seed : {1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u})
      sampled |= expect_sampled_sees_what_exact_sees(map, arm.reach({0.2, 0, 0}), seed, 0.8, name, &ratios);
    double mean = 0;
    for (const double r : ratios) mean += r / double(ratios.size());
    EXPECT_GE(mean, 0.95) << name << ": the mean over seeds 1-8";
  }
  EXPECT_TRUE(sampled) << "no replica sampled: the test compares nothing";
}

// The same on the real slambook map (5 cm, 374-451 M exact vectors: 35-40 s each), free-flying,
// one seed (seeds 1-3 gave 0.960, 0.992, 0.990; scripts/bench-nbv-scale.sh measures more).
TEST(NbvRealData, OnTheSlambookMapTheSampledBestViewSeesWhatTheExactOneSees) {
  FVX_REAL_DATA_OR_SKIP(path, "octomap-maps/slambook_ch13/octomap.bt");
  const map::OccupancyMap map = map::OccupancyMap::load(path);
  EXPECT_TRUE(expect_sampled_sees_what_exact_sees(map, std::nullopt, 1, 0.95, "slambook")) << "must sample";
}

/// U of a pose with the default full fan, from the map and the analysis alone: the void
/// cells of voids a frontier touches, on a grid over the known cells (the search's grid when
/// neither the search space nor the view bounds are given).
std::size_t full_fan_U(const map::OccupancyMap& map, const frontier_voids::Analysis& a, const Eigen::Isometry3d& T,
                       std::vector<map::VoxelKey>* seen_keys = nullptr, const Config& c = Config{}) {
  const map::Stats stats = map.stats();
  // The known cells' box and the eye's cell: under Exterior::View it may stand outside.
  Eigen::AlignedBox3d box(stats.known_min_m, stats.known_max_m);
  const Eigen::Vector3d cell = Eigen::Vector3d::Constant(map.resolution_m());
  box.extend(T.translation() - cell).extend(T.translation() + cell);
  const map::DenseGrid grid(map, box);
  core::LargeVector<std::uint8_t> mask(grid.cell_count(), 0);
  for (const auto& v : a.void_clusters)
    if (!a.frontier_voids[std::size_t(v.id)].enclosed())
      for (const map::VoxelKey& k : v.cells)
        if (grid.contains(k)) mask[grid.index(k)] = 1;
  viewpoints::FovScorer scorer(grid, std::move(mask), viewpoints::ray_fan(c.sensor.intrinsics, c.ray_cols, c.ray_rows),
                               c.sensor.depth_max_m, c.sensor.depth_min_m, c.count_near_void_cells);
  scorer.set_unknown_depth(c.unknown_depth_cells);  // U as the search's config defines it
  scorer.set_near_unknown(c.near_unknown);
  viewpoints::FovScorer::Workspace ws;
  std::vector<std::size_t> seen;
  const std::size_t U = scorer.score(T, ws, &seen).targets_seen;
  if (seen_keys) {
    seen_keys->clear();
    for (const std::size_t i : seen) seen_keys->push_back(grid.key(i));
  }
  return U;
}

/// The screened search (defaults) against the unscreened one (coarse fan off), same seed:
/// the screened views carry the full fan's U and seen cells (full_fan_U is the oracle) in
/// descending order. Adds both best views' U to the sums.
Result compare_screened(const map::OccupancyMap& map, const frontier_voids::Analysis& a,
                        const std::optional<Reach>& reach, std::uint64_t seed, double& screened_sum, double& full_sum,
                        const Config& base = Config{}) {
  Config screened = base, full = base;
  screened.seed = full.seed = seed;
  full.coarse_ray_cols = full.coarse_ray_rows = 0;
  const Result s = select(map, a, reach, screened), f = select(map, a, reach, full);
  if (s.views.empty() || f.views.empty()) {
    ADD_FAILURE() << "no view: " << s.reason << " / " << f.reason;
    return s;
  }
  EXPECT_LT(s.timing.rays, f.timing.rays) << "the coarse fan traces fewer rays";
  for (std::size_t i = 0; i < s.views.size(); ++i) {
    if (i > 0) {
      EXPECT_GE(s.views[i - 1].void_cells_seen, s.views[i].void_cells_seen);
    }
    if (i < 3) {  // and the cells: their keys in key order, counted per void
      std::vector<map::VoxelKey> keys;
      EXPECT_EQ(s.views[i].void_cells_seen, full_fan_U(map, a, s.views[i].T_world_sensor, &keys, base)) << "view " << i;
      EXPECT_EQ(s.views[i].seen_void_cells, keys) << "view " << i;
      std::size_t per_void = 0;
      for (const auto& [id, cells] : s.views[i].voids_seen) per_void += cells;
      EXPECT_EQ(per_void, keys.size()) << "view " << i;
    }
  }
  EXPECT_EQ(f.views.front().void_cells_seen, full_fan_U(map, a, f.views.front().T_world_sensor, nullptr, base));
  screened_sum += double(s.views.front().void_cells_seen);
  full_sum += double(f.views.front().void_cells_seen);
  return s;
}

// Screening (Config::coarse_ray_cols): poses are scored with 40 × 30 rays and the best 20
// again with the full 80 × 60 fan, which ranks the views. The best view sees at least 95 %
// of what the unscreened search's best view sees: seed by seed on both replicas (the fvx
// arm), on average over seeds 1–8 on the closed box (free-flying and on the arm; its views
// go through a 16 cm opening, where one seed alone moves a lot either way).
TEST(Nbv, ScreenedPosesAreRankedByTheFullFanAndKeepTheBestView) {
  const Arm arm;
  for (const std::string name : {"paper-setting-1", "paper-setting-2"}) {
    const map::OccupancyMap map = replica(name);
    for (const std::uint64_t seed : {1u, 2u, 3u}) {
      voids::ClusterConfig clusters;
      clusters.seed = seed;
      const frontier_voids::Analysis a = frontier_voids::analyse_map(map, std::nullopt, clusters);
      double screened = 0, full = 0;
      compare_screened(map, a, arm.reach({0.2, 0, 0}), seed, screened, full);
      EXPECT_GE(screened, 0.95 * full) << name << " seed " << seed;
    }
  }
  const ClosedBox& box = closed_box();
  for (const bool on_arm : {false, true}) {
    const std::optional<Reach> reach = on_arm ? std::optional<Reach>(arm.reach({0.2, 0, 0})) : std::nullopt;
    double screened = 0, full = 0;
    for (std::uint64_t seed = 1; seed <= 8; ++seed) compare_screened(box.map, box.analysis, reach, seed, screened, full);
    EXPECT_GE(screened, 0.95 * full) << (on_arm ? "arm" : "free-flying");
  }
}

// The same invariants when near unknown cells block rays of U (--near-unknown void or any):
// the screened views are ranked by, and carry, the full fan's U under that rule.
TEST(Nbv, ScreenedPosesCarryTheFullFansUUnderEveryNearUnknownRule) {
  const Arm arm;
  const map::OccupancyMap map = replica("paper-setting-2");
  const frontier_voids::Analysis a = frontier_voids::analyse_map(map, std::nullopt, voids::ClusterConfig{});
  for (const auto mode : {viewpoints::NearUnknown::Void, viewpoints::NearUnknown::Any}) {
    Config base;
    base.near_unknown = mode;
    double screened = 0, full = 0;
    compare_screened(map, a, arm.reach({0.2, 0, 0}), 1, screened, full, base);
    EXPECT_GT(full, 0.0) << viewpoints::to_string(mode) << ": no view sees a void cell, the test compares nothing";
  }
}

// The exhaustive strategy is screened as frontier-void is: reachable poses with the coarse
// fan (above 1 024 poses the best quarter by a fan half as fine), the best again with the full
// one. Here with 40 x 30 rays screened by 20 x 15 and 10 x 7 (the default's ratios; one roll)
// to keep the unscreened reference short: the reported views carry the full fan's U, and the
// best sees at least 95 % of what the unscreened best view sees, on the closed box and on
// paper-setting-2, where the optimum looks through holes (both saw the same best U when
// written, as did paper-setting-1).
TEST(Nbv, TheScreenedExhaustiveStrategyKeepsTheBestView) {
  const Arm arm;
  Config base = coarse();
  base.strategy = Strategy::Exhaustive;
  base.coarse_ray_cols = 20;
  base.coarse_ray_rows = 15;
  auto expect_kept = [&](const map::OccupancyMap& map, const frontier_voids::Analysis& a, const std::string& name) {
    double screened = 0, full = 0;
    const Result s = compare_screened(map, a, arm.reach({0.2, 0, 0}), 1, screened, full, base);
    EXPECT_GE(screened, 0.95 * full) << name;
    // Above 1 024 poses a fan half as fine as the coarse one picks those the coarse fan scores.
    EXPECT_GT(s.poses_scored, 1024u) << name << ": the pre-screen is not exercised";
  };
  expect_kept(closed_box().map, closed_box().analysis, "closed box");
  const map::OccupancyMap map = replica("paper-setting-2");
  expect_kept(map, frontier_voids::analyse_map(map, std::nullopt, voids::ClusterConfig{}), "paper-setting-2");
}

// The polish and the climb only add poses: the best view never sees less than without them.
TEST(Nbv, ThePolishAndTheClimbNeverLowerTheBestView) {
  const ClosedBox& box = closed_box();
  const Arm arm;
  for (const bool on_arm : {false, true}) {
    const std::optional<Reach> reach = on_arm ? std::optional<Reach>(arm.reach({0.2, 0, 0})) : std::nullopt;
    Config plain = coarse();
    plain.polish_poses = 0;
    Config polished = coarse();
    polished.climb_rounds = 4;
    const Result before = select(box.map, box.analysis, reach, plain);
    const Result after = select(box.map, box.analysis, reach, polished);
    ASSERT_FALSE(before.views.empty());
    ASSERT_FALSE(after.views.empty());
    EXPECT_GE(after.views.front().void_cells_seen, before.views.front().void_cells_seen);
    EXPECT_GT(after.pruning.polish_poses, 0u);
    EXPECT_EQ(before.pruning.polish_poses, 0u);
    if (after.views.front().polished_from) {  // a polished pose came from a pose scored before it
      EXPECT_LT(*after.views.front().polished_from, after.views.front().pose_index);
    }
  }
}

TEST(Nbv, WithoutOpenVoidsTheAnswerIsEmptyWithAReason) {
  const ClosedBox& box = closed_box();
  frontier_voids::Analysis none = box.analysis;
  none.void_cells.clear();
  none.void_clusters.clear();
  none.frontier_voids.clear();
  Result r = select(box.map, none, std::nullopt, coarse());
  EXPECT_TRUE(r.views.empty());
  EXPECT_NE(r.reason.find("no void cell"), std::string::npos) << r.reason;
  frontier_voids::Analysis enclosed = box.analysis;
  for (auto& fv : enclosed.frontier_voids) fv.frontier_ids.clear();
  r = select(box.map, enclosed, std::nullopt, coarse());
  EXPECT_TRUE(r.views.empty());
  EXPECT_NE(r.reason.find("enclosed"), std::string::npos) << r.reason;
}

// Hidden void cells (a taken view looked at them and they stayed unknown) leave u_i as well
// as U: a void hidden whole draws no utility vector, the others draw the same as before.
TEST(Nbv, HiddenVoidCellsLeaveAlgorithmOnesUtility) {
  const ClosedBox& box = closed_box();
  Config config = coarse();
  config.accumulation = utility::Accumulation::Exact;  // counts Algorithm 1's vectors one by one
  const Result all_visible = select(box.map, box.analysis, std::nullopt, config);
  ASSERT_GT(all_visible.utility_vectors, 0u);
  const auto largest = std::max_element(box.analysis.frontier_voids.begin(), box.analysis.frontier_voids.end(),
                                        [](const auto& l, const auto& r) { return l.utility_m3 < r.utility_m3; });
  ASSERT_FALSE(largest->enclosed());
  std::size_t its_vectors = 0;  // Algorithm 1: one vector per corner and frontier cell
  for (const int id : largest->frontier_ids) its_vectors += 7 * box.analysis.frontier_clusters[std::size_t(id)].cells.size();
  std::vector<map::VoxelKey> hidden = box.analysis.void_clusters[std::size_t(largest->void_id)].cells;
  const Result one_hidden = select(box.map, box.analysis, std::nullopt, config, hidden);
  EXPECT_EQ(one_hidden.utility_vectors, all_visible.utility_vectors - its_vectors);
  hidden.clear();
  for (const auto& fv : box.analysis.frontier_voids)
    if (!fv.enclosed())
      for (const auto& k : box.analysis.void_clusters[std::size_t(fv.void_id)].cells) hidden.push_back(k);
  std::sort(hidden.begin(), hidden.end());
  const Result all_hidden = select(box.map, box.analysis, std::nullopt, config, hidden);
  EXPECT_EQ(all_hidden.utility_vectors, 0u);
  EXPECT_TRUE(all_hidden.views.empty());
}

/// U of pose T on the closed box's search grid, cast independently of the search: targets are
/// the void cells of voids a frontier touches except `hidden`; under `mode` == Hidden the
/// hidden cells and every cell of a void that holds one block rays nearer than the minimum
/// depth.
std::size_t U_with_hidden(const ClosedBox& box, const Config& c, const std::vector<map::VoxelKey>& hidden,
                          viewpoints::NearUnknown mode, const Eigen::Isometry3d& T) {
  const map::Stats stats = box.map.stats();
  const map::DenseGrid grid(box.map, Eigen::AlignedBox3d(stats.known_min_m, stats.known_max_m));
  core::LargeVector<std::uint8_t> mask(grid.cell_count(), 0);
  for (const auto& v : box.analysis.void_clusters)
    if (!box.analysis.frontier_voids[std::size_t(v.id)].enclosed())
      for (const map::VoxelKey& k : v.cells)
        if (grid.contains(k)) mask[grid.index(k)] = 1;
  std::vector<std::size_t> blocking;
  for (const map::VoxelKey& k : hidden)
    if (grid.contains(k)) {
      mask[grid.index(k)] = 0;
      blocking.push_back(grid.index(k));
    }
  for (const auto& v : box.analysis.void_clusters) {
    const bool holds_hidden = std::any_of(v.cells.begin(), v.cells.end(), [&](const map::VoxelKey& k) {
      return std::binary_search(hidden.begin(), hidden.end(), k);
    });
    if (holds_hidden && !box.analysis.frontier_voids[std::size_t(v.id)].enclosed())
      for (const map::VoxelKey& k : v.cells)
        if (grid.contains(k)) blocking.push_back(grid.index(k));
  }
  viewpoints::FovScorer scorer(grid, std::move(mask), viewpoints::ray_fan(c.sensor.intrinsics, c.ray_cols, c.ray_rows),
                               c.sensor.depth_max_m, c.sensor.depth_min_m, c.count_near_void_cells);
  scorer.set_near_unknown(mode);
  scorer.set_blocking(blocking);
  viewpoints::FovScorer::Workspace ws;
  return scorer.score(T, ws).targets_seen;
}

// --near-unknown hidden: the void cells a taken view left unknown (the loop's hidden cells),
// and every cell of their voids, block the rays that cross them nearer than the minimum depth.
// Hidden here: the cells of the closed box's best view (ignore) nearer than 0.5 m, as if that
// view had come back blank there. Every view then carries the U of an independent cast under
// the rule, and the old best pose sees fewer void cells under it than with the rule off.
TEST(Nbv, UnderHiddenTheVoidCellsAViewLeftUnknownBlockNearRays) {
  const ClosedBox& box = closed_box();
  Config config = coarse();
  const Result before = select(box.map, box.analysis, std::nullopt, config);
  ASSERT_FALSE(before.views.empty()) << before.reason;
  const nbv::View& best = before.views.front();
  std::vector<map::VoxelKey> hidden;
  for (const map::VoxelKey& k : best.seen_void_cells) {
    const double depth_m = (box.map.center_of(k) - best.T_world_sensor.translation()).dot(best.T_world_sensor.linear().col(2));
    if (depth_m < config.sensor.depth_min_m) hidden.push_back(k);
  }
  ASSERT_FALSE(hidden.empty()) << "the best view sees no void cell nearer than the minimum depth";
  std::sort(hidden.begin(), hidden.end());
  config.near_unknown = viewpoints::NearUnknown::Hidden;
  const Result after = select(box.map, box.analysis, std::nullopt, config, hidden);
  ASSERT_FALSE(after.views.empty()) << after.reason;
  for (const nbv::View& v : after.views)
    EXPECT_EQ(v.void_cells_seen, U_with_hidden(box, config, hidden, viewpoints::NearUnknown::Hidden, v.T_world_sensor));
  EXPECT_LT(U_with_hidden(box, config, hidden, viewpoints::NearUnknown::Hidden, best.T_world_sensor),
            U_with_hidden(box, config, hidden, viewpoints::NearUnknown::Ignore, best.T_world_sensor));
}

TEST(Nbv, TheSensorStaysInsideTheViewBounds) {
  const ClosedBox& box = closed_box();
  Config config = coarse();
  config.top = 50;
  // Only the half of the room on the −y side of the opening, above the lid.
  config.view_bounds_m = Eigen::AlignedBox3d(Eigen::Vector3d(0.0, -1.5, 0.45), Eigen::Vector3d(1.6, -0.05, 1.5));
  const Result r = select(box.map, box.analysis, std::nullopt, config);
  ASSERT_FALSE(r.views.empty()) << r.reason;
  for (const View& v : r.views) EXPECT_TRUE(config.view_bounds_m->contains(v.T_world_sensor.translation()));
}

// The closed box scanned from three sides at its own height: the air above it stays
// unknown (a ray that meets nothing records nothing), so no known free cell looks down
// through the lid's opening.
struct BoxSeenFromItsSides {
  map::OccupancyMap map{0.02};
  frontier_voids::Analysis analysis;
  BoxSeenFromItsSides() {
    test::integrate_views(map, sim::builtin_scene("closed-box"), views_of_the_box(1.0, 0.05, {-M_PI / 2, M_PI, M_PI / 2}));
    analysis = frontier_voids::analyse_map(map, std::nullopt, voids::ClusterConfig{});
  }
};

// Config::exterior View and Free: views may stand in the unknown cells outside the voids'
// hull, never inside it, still clear of occupied cells and reachable, and they see only the
// analysis' void cells. View keeps the paper's field (in the same sensor box); Free's rays
// run on through the air.
TEST(Nbv, UnderViewAndFreeTheSensorMayStandInTheUnknownAirOutsideTheHull) {
  const BoxSeenFromItsSides box;
  const frontier_voids::Analysis& a = box.analysis;
  ASSERT_GT(a.void_cells.size(), 1000u);
  ASSERT_FALSE(a.hull.empty());
  const Arm arm;
  const Reach reach = arm.reach({0.2, 0.0, 0.0});
  Config paper = coarse();
  paper.exterior = Exterior::Unknown;
  paper.top = 50;
  // The same sensor box for all: Algorithm 1 reads the field only in it (the candidate box),
  // and without view bounds View and Free widen it to the arm's reach.
  paper.view_bounds_m = Eigen::AlignedBox3d(Eigen::Vector3d(-0.5, -1.2, 0.0), Eigen::Vector3d(1.6, 1.2, 1.3));
  const Result known = select(box.map, a, reach, paper);
  for (const View& v : known.views)
    EXPECT_EQ(box.map.state(*box.map.key_of(v.T_world_sensor.translation())), map::VoxelState::Free);
  const auto occupied = box.map.occupied_centers();
  for (const Exterior mode : {Exterior::View, Exterior::Free}) {
    Config exterior = paper;
    exterior.exterior = mode;
    const Result air = select(box.map, a, reach, exterior);
    ASSERT_FALSE(air.views.empty()) << air.reason;
    std::size_t in_unknown = 0;
    for (const View& v : air.views) {
      const Eigen::Vector3d p = v.T_world_sensor.translation();
      const std::optional<map::VoxelKey> k = box.map.key_of(p);
      ASSERT_TRUE(k);
      if (box.map.state(*k) == map::VoxelState::Unknown) {
        ++in_unknown;
        EXPECT_FALSE(a.hull.contains(box.map.center_of(*k))) << "an eye in the hull, where voids lie";
      } else {
        EXPECT_EQ(box.map.state(*k), map::VoxelState::Free);
      }
      double nearest = INFINITY;
      for (const auto& o : occupied) nearest = std::min(nearest, (o.cast<double>() - p).norm());
      EXPECT_GT(nearest, exterior.clearance_m - 1e-6);
      EXPECT_TRUE(arm.capmap.reachable(reach.T_world_base, p, v.T_world_sensor.linear().col(2)));
      EXPECT_EQ(v.joints_rad.size(), arm.arm.dof());
      for (const map::VoxelKey& c : v.seen_void_cells)  // the voids are the analysis' own
        EXPECT_TRUE(std::binary_search(a.void_cells.begin(), a.void_cells.end(), c));
    }
    EXPECT_GT(in_unknown, 0u) << to_string(mode);
    // Free-flying, the random strategy draws its positions from the cells an eye may stand in.
    Config random = exterior, random_known = paper;
    random.strategy = random_known.strategy = Strategy::Random;
    const Result r = select(box.map, a, std::nullopt, random), r_known = select(box.map, a, std::nullopt, random_known);
    EXPECT_GT(r.pruning.candidate_cells, r_known.pruning.candidate_cells) << to_string(mode);
    if (mode == Exterior::View) {  // the paper's field: the same vectors and cells with utility
      EXPECT_EQ(air.utility_vectors, known.utility_vectors);
      EXPECT_EQ(air.pruning.utility_cells, known.pruning.utility_cells);
    } else {
      EXPECT_GT(air.pruning.utility_cells, known.pruning.utility_cells) << "Free: rays pass the air";
    }
  }
}

// Under View the sensor's default box grows into the arm's reach sideways and upwards, not
// below the lowest known cell: there lies what the scene stands on (the suite's exhaustive
// planner took views from under the floor, up through its unseen cells, that measured
// nothing). Under Unknown it is the known cells' box.
TEST(Nbv, UnderViewTheSensorsBoxDoesNotGoBelowTheLowestKnownCell) {
  const BoxSeenFromItsSides box;
  const Arm arm;
  const Reach reach = arm.reach({0.2, 0.0, 0.0});
  const map::Stats stats = box.map.stats();
  const Eigen::AlignedBox3d known(stats.known_min_m, stats.known_max_m);
  ASSERT_LT(arm.capmap.reachable_box_base().min().z(), known.min().z() - 0.2) << "the arm reaches below";
  Config c = coarse();
  const detail::Search view(box.map, box.analysis, reach, c, {});
  EXPECT_DOUBLE_EQ(view.view_bounds_m.min().z(), known.min().z());
  EXPECT_TRUE(view.view_bounds_m.contains(known));
  EXPECT_GT(view.view_bounds_m.volume(), 1.5 * known.volume()) << "the reach widens it";
  c.exterior = Exterior::Unknown;
  const detail::Search paper(box.map, box.analysis, reach, c, {});
  EXPECT_TRUE(paper.view_bounds_m.isApprox(known));
}

// An eye off its cell's centre (an IK snap, a capability-map voxel) is clear only if no
// occupied cell centre lies within the clearance of the eye itself, nor of the cell's centre
// (the cell test). Brute force over the grid's occupied cells, at eyes scattered around them.
TEST(Nbv, AnEyeOffItsCellsCentreKeepsTheClearance) {
  const ClosedBox& box = closed_box();
  Config c = coarse();
  c.clearance_m = 0.095;  // 4.75 cells: no cell centre is at exactly the clearance
  const detail::Search s(box.map, box.analysis, std::nullopt, c, {});
  std::vector<Eigen::Vector3d> occupied;
  for (std::size_t i = 0; i < s.grid.cell_count(); ++i)
    if (s.grid.state_at(i) == map::VoxelState::Occupied) occupied.push_back(s.grid.center_of(s.grid.key(i)));
  ASSERT_GT(occupied.size(), 100u);
  const auto clear = [&](const Eigen::Vector3d& p) {
    for (const auto& o : occupied)
      if ((o - p).norm() <= c.clearance_m) return false;
    return true;
  };
  std::mt19937_64 rng(7);
  // Eyes about the clearance away from an occupied cell, where the cell test and the eye's
  // own distance can disagree.
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> distance_m(c.clearance_m - 0.01, c.clearance_m + 0.02);
  std::size_t eyes = 0, only_the_eye_too_close = 0;
  for (int i = 0; i < 4000; ++i) {
    const Eigen::Vector3d direction = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
    const Eigen::Vector3d p = occupied[rng() % occupied.size()] + distance_m(rng) * direction;
    const std::optional<map::VoxelKey> cell = s.grid.cell_of(p);
    if (!cell) continue;
    ++eyes;
    const bool centre_clear = clear(s.grid.center_of(*cell)), eye_clear = clear(p);
    if (centre_clear && !eye_clear) ++only_the_eye_too_close;
    EXPECT_EQ(s.clear_of_occupied(*cell, p), centre_clear && eye_clear) << p.transpose();
  }
  EXPECT_GT(eyes, 2000u);
  EXPECT_GT(only_the_eye_too_close, 20u) << "the eyes must test the band the cell's centre misses";
}

// The exhaustive strategy scores every pose in known free cells under View as well, and with
// the same U (the scorer neither counts nor stops at unknown cells outside the voids): the
// best view can only gain. Free adds no pose to View's and changes no U. Unscreened, so that
// each pose's U is the full fan's.
TEST(Nbv, UnderViewTheExhaustiveStrategysBestViewCanOnlyGain) {
  const BoxSeenFromItsSides box;
  const Arm arm;
  const Reach reach = arm.reach({0.2, 0.0, 0.0});
  Config c = coarse();
  c.strategy = Strategy::Exhaustive;
  c.coarse_ray_cols = c.coarse_ray_rows = 0;
  c.ray_cols = 16;  // 66 000 poses with the air: a coarse fan keeps it short
  c.ray_rows = 12;
  c.exterior = Exterior::Unknown;
  Config view = c, free = c;
  view.exterior = Exterior::View;
  free.exterior = Exterior::Free;
  const Result known = select(box.map, box.analysis, reach, c), air = select(box.map, box.analysis, reach, view),
               freed = select(box.map, box.analysis, reach, free);
  ASSERT_FALSE(known.views.empty()) << known.reason;
  ASSERT_FALSE(air.views.empty()) << air.reason;
  ASSERT_FALSE(freed.views.empty()) << freed.reason;
  EXPECT_GT(air.poses_scored, known.poses_scored);
  EXPECT_GE(air.views.front().void_cells_seen, known.views.front().void_cells_seen);
  EXPECT_EQ(freed.poses_scored, air.poses_scored);
  EXPECT_EQ(freed.views.front().void_cells_seen, air.views.front().void_cells_seen);
  std::printf("exhaustive best U: %zu in known free cells (%zu poses), %zu with the air (%zu poses)\n",
              known.views.front().void_cells_seen, known.poses_scored, air.views.front().void_cells_seen,
              air.poses_scored);
}

TEST(Nbv, TheFrontierStrategyViewsTheLargestFrontierCluster) {
  const ClosedBox& box = closed_box();
  Config config = coarse();
  config.strategy = Strategy::Frontier;
  const Result r = select(box.map, box.analysis, std::nullopt, config);
  ASSERT_FALSE(r.views.empty()) << r.reason;
  EXPECT_GT(r.views.front().frontier_cells_seen, 0u);
  for (std::size_t i = 1; i < r.views.size(); ++i)
    EXPECT_GE(r.views[i - 1].frontier_cells_seen, r.views[i].frontier_cells_seen);
  // Its field is a ray count, and it says so: no Algorithm 1 utility in m³.
  for (const View& v : r.views) {
    EXPECT_GT(v.frontier_rays_through_cell, 0.0);
    EXPECT_EQ(v.frontier_rays_through_cell, std::floor(v.frontier_rays_through_cell));
    EXPECT_EQ(v.accumulated_utility_m3, 0.0);
  }
}

TEST(Nbv, ConfigValidationListsTheProblems) {
  Config c;
  c.top = 0;
  c.valid_poses = 0;
  c.sensor.intrinsics.fx = 0.0;
  const auto problems = c.validate();
  EXPECT_EQ(problems.size(), 3u);
  EXPECT_THROW(select(closed_box().map, closed_box().analysis, std::nullopt, c), UsageError);
  Config ex;
  ex.strategy = Strategy::Exhaustive;
  EXPECT_THROW(select(closed_box().map, closed_box().analysis, std::nullopt, ex), UsageError);
}

}  // namespace
}  // namespace fvx::nbv
