// session::replay runs each view's search while the next scan is integrated; the oracle is the
// explore loop, which runs pipeline::run_step() one view after the other. Replaying an
// explore run's scans must give its views, hidden cells and choices exactly, with the
// callbacks in view order.
#include <gtest/gtest.h>

#include <stdexcept>

#include "fvx/core/error.hpp"
#include "fvx/session/replay.hpp"
#include "fvx/session/session.hpp"
#include "fvx/sim/builtin_scenes.hpp"
#include "fvx/sim/depth_sensor.hpp"
#include "crates_explore.hpp"

namespace fvx::session {
namespace {

struct Recorded {
  std::vector<ViewRecord> records;
  std::vector<std::vector<map::VoxelKey>> hidden;  // State::hidden_void_cells after each view
};

Recorded explore_crates(const ExploreConfig& config, const sim::Scene& scene) {
  const auto caster = sim::make_ray_caster(scene.mesh);
  const Sensor kinect = test::kinect_on(*caster);
  Recorded out;
  explore(kinect, std::nullopt, config, [&](const ViewRecord& v, const pipeline::State& s) {
    out.records.push_back(v);
    out.hidden.push_back(s.hidden_void_cells);
  });
  return out;
}

std::vector<RecordedScan> as_recording(const std::vector<ViewRecord>& records, int failing_view = -1) {
  std::vector<RecordedScan> scans;
  for (const ViewRecord& r : records) {
    RecordedScan s;
    s.name = "view " + std::to_string(r.view);
    s.T_world_sensor_true = r.T_world_sensor_true;
    s.load = [r, failing_view] {
      if (r.view == failing_view) throw std::runtime_error("unreadable");
      scan::Scan scan;
      scan.points_sensor = r.points_sensor;
      scan.T_world_sensor = r.T_world_sensor_prior;
      return scan;
    };
    scans.push_back(std::move(s));
  }
  return scans;
}

TEST(Replay, AnExploreRunReplaysToItsOwnViewsWhileSearchesOverlapTheNextScan) {
  const sim::Scene scene = sim::builtin_scene("crates");
  const ExploreConfig explore_config = test::crates_explore(scene, 5);
  const Recorded truth = explore_crates(explore_config, scene);
  ASSERT_GE(truth.records.size(), 3u);

  ReplayConfig config;
  config.pipeline = explore_config.pipeline;
  std::vector<std::string> events;
  std::vector<ReplayView> views;
  replay(
      as_recording(truth.records), std::nullopt, config,
      [&](int view, const pipeline::State& state) {
        events.push_back("map " + std::to_string(view));
        EXPECT_EQ(state.steps, view + 1);
        EXPECT_EQ(state.hidden_void_cells, truth.hidden[std::size_t(view)]) << "view " << view;
      },
      [&](const ReplayView& v) {
        events.push_back("view " + std::to_string(v.view));
        views.push_back(v);
      });

  ASSERT_EQ(views.size(), truth.records.size());
  for (std::size_t i = 0; i < views.size(); ++i) {
    // on_map(i) comes before on_view(i), which comes before on_map(i + 1).
    EXPECT_EQ(events[2 * i], "map " + std::to_string(i));
    EXPECT_EQ(events[2 * i + 1], "view " + std::to_string(i));
    const pipeline::StepResult &got = views[i].step, &want = truth.records[i].step;
    EXPECT_EQ(got.analysis.void_cells, want.analysis.void_cells) << "view " << i;
    EXPECT_EQ(got.expected_hidden, want.expected_hidden) << "view " << i;
    EXPECT_EQ(views[i].at_choice, i > 0) << "view " << i;
    EXPECT_EQ(views[i].revealed_void_cells, truth.records[i].revealed_void_cells) << "view " << i;
    EXPECT_EQ(views[i].chosen, truth.records[i].chosen) << "view " << i;
    ASSERT_TRUE(got.searched);
    ASSERT_EQ(got.nbv.views.size(), want.nbv.views.size()) << "view " << i;
    EXPECT_EQ(got.nbv.reason, want.nbv.reason);
    for (std::size_t j = 0; j < got.nbv.views.size(); ++j) {
      EXPECT_TRUE(got.nbv.views[j].T_world_sensor.isApprox(want.nbv.views[j].T_world_sensor, 0.0));
      EXPECT_EQ(got.nbv.views[j].seen_void_cells, want.nbv.views[j].seen_void_cells);
    }
  }
  // Some view left expected cells unknown, so the hidden cells were exercised.
  EXPECT_FALSE(truth.hidden.back().empty());
}

TEST(Replay, AScanThatFailsToLoadStopsAtItsViewAfterTheViewsBefore) {
  const sim::Scene scene = sim::builtin_scene("crates");
  const ExploreConfig explore_config = test::crates_explore(scene, 3);
  const Recorded truth = explore_crates(explore_config, scene);
  ASSERT_EQ(truth.records.size(), 3u);
  ReplayConfig config;
  config.pipeline = explore_config.pipeline;
  std::vector<int> maps, views;
  try {
    replay(
        as_recording(truth.records, 2), std::nullopt, config, [&](int view, const pipeline::State&) { maps.push_back(view); },
        [&](const ReplayView& v) { views.push_back(v.view); });
    FAIL() << "an unreadable scan was replayed";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("view 2 (view 2): unreadable"), std::string::npos) << e.what();
  }
  EXPECT_EQ(maps, (std::vector<int>{0, 1}));
  EXPECT_EQ(views, (std::vector<int>{0, 1}));
}

}  // namespace
}  // namespace fvx::session
