// run_step(), the loop body of explore and replay: its incremental frontiers and voids equal
// a from-scratch analysis of the same map; a blank scan changes nothing; void cells a chosen
// view left unknown leave U; registration undoes perturbed priors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "fvx/core/error.hpp"
#include "fvx/pipeline/pipeline.hpp"
#include "fvx/sim/builtin_scenes.hpp"
#include "fvx/sim/depth_sensor.hpp"
#include "fvx/viewpoints/fov.hpp"
#include "fvx/voids/width.hpp"

namespace fvx::pipeline {
namespace {

Eigen::Isometry3d looking(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = eye;
  T.linear() = viewpoints::look_along(target - eye, 0.0);
  return T;
}

scan::Scan render(const sim::RayCaster& caster, const Eigen::Isometry3d& T, int view) {
  const sim::Frame frame = sim::render(caster, T, sim::SensorConfig{}, std::uint64_t(view));
  scan::Scan s;
  s.source = "view " + std::to_string(view);
  for (const auto& p : frame.points_sensor) s.points_sensor.push_back(p.cast<double>());
  s.T_world_sensor = T;
  return s;
}

struct Crates {
  sim::Scene scene = sim::builtin_scene("crates");
  std::unique_ptr<sim::RayCaster> caster = sim::make_ray_caster(scene.mesh);
  Eigen::Vector3d target = scene.info.search_space->center() - Eigen::Vector3d(0, 0, 0.1);
  std::vector<Eigen::Isometry3d> views = {looking({0.05, 0.0, 0.95}, target), looking({0.3, 0.75, 0.85}, target),
                                          looking({0.3, -0.75, 0.85}, target)};
  Config config() const {
    Config c;
    c.bounds_m = scene.info.search_space;
    c.nbv.ray_cols = 40;
    c.nbv.ray_rows = 30;
    return c;
  }
};

TEST(Pipeline, IncrementalAnalysisEqualsFromScratch) {
  const Crates crates;
  const Config config = crates.config();
  State state(config.resolution_m);
  StepResult last;
  for (std::size_t i = 0; i < crates.views.size(); ++i)
    last = run_step(state, render(*crates.caster, crates.views[i], int(i)), std::nullopt, config);
  EXPECT_EQ(state.steps, 3);
  frontiers::FrontierSet fs;
  fs.rebuild(state.map);
  voids::VoidSet vs;
  vs.rebuild(state.map);
  const auto scratch = frontier_voids::analyse(state.map, fs, &vs, config.bounds_m, config.clusters);
  ASSERT_GT(scratch.void_cells.size(), 1000u);
  EXPECT_EQ(last.analysis.frontier_cells, scratch.frontier_cells);
  EXPECT_EQ(last.analysis.void_cells, scratch.void_cells);
  EXPECT_EQ(last.analysis.void_clusters.size(), scratch.void_clusters.size());
  ASSERT_FALSE(last.nbv.views.empty()) << last.nbv.reason;
  EXPECT_GT(last.integration.changed_cells, 0u);
}

TEST(Pipeline, AWideVoidCountsOnlyCellsThatCouldHideTheTarget) {
  const Crates crates;
  Config config = crates.config();
  config.target_size_m = 0.075;  // floor(0.075 / 0.025) - 1 = 2 cells
  ASSERT_EQ(config.min_void_width_cells(), 2);
  State state(config.resolution_m);
  StepResult last;
  for (std::size_t i = 0; i < crates.views.size(); ++i)
    last = run_step(state, render(*crates.caster, crates.views[i], int(i)), std::nullopt, config);
  voids::VoidSet vs;
  vs.rebuild(state.map);
  const std::vector<map::VoxelKey> all = vs.cells(state.map, config.bounds_m);
  EXPECT_EQ(last.analysis.void_cells, voids::cells_in_full_cubes(all, 2));
  EXPECT_GT(last.analysis.thin_void_cells, 0u);
  EXPECT_EQ(last.analysis.thin_void_cells + last.analysis.void_cells.size(), all.size());
  for (const auto& c : last.analysis.void_clusters)
    for (const map::VoxelKey& k : c.cells)
      EXPECT_TRUE(std::binary_search(last.analysis.void_cells.begin(), last.analysis.void_cells.end(), k));
  config.target_size_m = -0.1;
  EXPECT_FALSE(config.validate().empty());
}

TEST(Pipeline, ABlankScanChangesNothing) {
  const Crates crates;
  const Config config = crates.config();
  State state(config.resolution_m);
  const StepResult first = run_step(state, render(*crates.caster, crates.views[0], 0), std::nullopt, config);
  const std::size_t leaves = state.map.stats().occupied_leaves;
  scan::Scan blank;
  blank.source = "blank";
  blank.points_sensor.assign(100, Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()));
  blank.T_world_sensor = crates.views[1];
  const StepResult second = run_step(state, blank, std::nullopt, config);
  EXPECT_EQ(second.filtered.kept, 0u);
  EXPECT_EQ(second.integration.changed_cells, 0u);
  EXPECT_EQ(state.map.stats().occupied_leaves, leaves);
  EXPECT_EQ(second.analysis.void_cells, first.analysis.void_cells);
}

// The cells a chosen view was expected to reveal and did not (a blank scan reveals none)
// become hidden and no longer count: that view's U drops to zero.
TEST(Pipeline, VoidCellsAViewLeftUnknownLeaveU) {
  const Crates crates;
  const Config config = crates.config();
  State state(config.resolution_m);
  const StepResult first = run_step(state, render(*crates.caster, crates.views[0], 0), std::nullopt, config);
  ASSERT_FALSE(first.nbv.views.empty());
  const nbv::View& best = first.nbv.views.front();
  ASSERT_EQ(best.seen_void_cells.size(), best.void_cells_seen);
  scan::Scan blank;
  blank.source = "blank";
  blank.points_sensor.assign(10, Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()));
  blank.T_world_sensor = best.T_world_sensor;
  const StepResult second = run_step(state, blank, std::nullopt, config, &best.seen_void_cells);
  EXPECT_EQ(second.expected_hidden, best.void_cells_seen);
  EXPECT_EQ(second.expected_revealed, 0u);
  EXPECT_EQ(state.hidden_void_cells, best.seen_void_cells);
  for (const nbv::View& v : second.nbv.views) {
    for (const auto& k : v.seen_void_cells)
      EXPECT_FALSE(std::binary_search(best.seen_void_cells.begin(), best.seen_void_cells.end(), k));
  }
}

// Priors off by 2 cm and 2° per axis: with registration the map's occupied cells stay within
// one cell of those of the exact run for at least 95 % of them.
TEST(Pipeline, RegistrationUndoesPoseNoise) {
  const sim::Scene scene = sim::builtin_scene("paper-setting-2");
  const auto caster = sim::make_ray_caster(scene.mesh);
  const Eigen::Vector3d target = scene.info.search_space->center() - Eigen::Vector3d(0, 0, 0.1);
  const std::vector<Eigen::Isometry3d> views = {looking({0.05, 0.0, 0.95}, target), looking({0.3, 0.75, 0.85}, target),
                                                looking({0.3, -0.75, 0.85}, target), looking({0.45, 0.0, 1.2}, target)};
  Config exact = Crates().config();
  exact.bounds_m = scene.info.search_space;
  Config noisy = exact;
  noisy.register_scans = true;
  State a(exact.resolution_m), b(noisy.resolution_m), c(exact.resolution_m);  // c: noisy, unregistered
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  double worst_prior_error_m = 0.0;
  for (std::size_t i = 0; i < views.size(); ++i) {
    run_step(a, render(*caster, views[i], int(i)), std::nullopt, exact);
    scan::Scan s = render(*caster, views[i], int(i));
    if (i > 0) {
      s.T_world_sensor.translation() += 0.02 * Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
      const Eigen::Vector3d rv = (2.0 * M_PI / 180.0) * Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
      s.T_world_sensor.linear() = Eigen::AngleAxisd(rv.norm(), rv.normalized()).toRotationMatrix() * s.T_world_sensor.linear();
      worst_prior_error_m = std::max(worst_prior_error_m, (s.T_world_sensor.translation() - views[i].translation()).norm());
    }
    run_step(c, s, std::nullopt, exact);
    const StepResult r = run_step(b, std::move(s), std::nullopt, noisy);
    if (i > 0) {
      ASSERT_TRUE(r.registration.has_value());
      EXPECT_TRUE(r.registration->converged) << "view " << i << ": " << r.registration->problem;
      EXPECT_LT((r.T_world_sensor.translation() - views[i].translation()).norm(), 0.01) << "view " << i;
    }
  }
  EXPECT_GT(worst_prior_error_m, 0.02);
  const auto reference = a.map.occupied_centers();
  // Occupied cells of `m` with an occupied cell of the exact run within one cell (26-neighbourhood).
  auto near_exact = [&](const map::OccupancyMap& m) {
    std::size_t near = 0;
    for (const Eigen::Vector3f& centre : m.occupied_centers()) {
      const auto key = m.key_of(centre.cast<double>());
      bool found = false;
      for (int dx = -1; dx <= 1 && !found; ++dx)
        for (int dy = -1; dy <= 1 && !found; ++dy)
          for (int dz = -1; dz <= 1 && !found; ++dz) {
            map::VoxelKey k = *key;
            k.x = std::uint16_t(k.x + dx);
            k.y = std::uint16_t(k.y + dy);
            k.z = std::uint16_t(k.z + dz);
            found = a.map.state(k) == map::VoxelState::Occupied;
          }
      near += found;
    }
    return near;
  };
  const auto registered = b.map.occupied_centers();
  const std::size_t near = near_exact(b.map);
  // Without registration the same priors smear the surfaces: the check can fail.
  const std::size_t near_unregistered = near_exact(c.map);
  EXPECT_LT(double(near_unregistered), 0.95 * double(c.map.occupied_centers().size()));
  ASSERT_GT(reference.size(), 1000u);
  std::printf("occupied cells within one cell of the exact run's: registered %zu of %zu (%.1f %%), unregistered "
              "%zu of %zu; worst prior error %.3f m\n",
              near, registered.size(), 100.0 * double(near) / double(registered.size()), near_unregistered,
              c.map.occupied_centers().size(), worst_prior_error_m);
  EXPECT_GE(double(near), 0.95 * double(registered.size())) << near << " of " << registered.size();
}

// A bad config is input, not a bug: the step throws, naming every problem on one line, and
// a stage called directly with a bad config throws too (it used to abort).
TEST(Pipeline, ABadConfigNamesEveryProblemAtOnce) {
  Config config;
  config.resolution_m = -1.0;
  config.target_size_m = -1.0;
  config.filter.depth_min_m = 3.0;
  config.filter.depth_max_m = 1.0;
  State state(0.025);
  try {
    run_step(state, scan::Scan{}, std::nullopt, config);
    FAIL() << "a bad config was run";
  } catch (const UsageError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    for (const char* field : {"resolution_m", "target_size_m", "filter: "})
      EXPECT_NE(message.find(field), std::string::npos) << field << " missing from: " << message;
  }
  scan::Scan scan;
  EXPECT_THROW(scan::filter(scan, config.filter), UsageError);
}

}  // namespace
}  // namespace fvx::pipeline
