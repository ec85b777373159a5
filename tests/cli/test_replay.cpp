// fvx replay as users run it: a session fvx explore recorded replays to the same table and the
// same chosen views; twice gives the same outputs; a broken scan stops the replay naming its
// view with the earlier views' outputs intact; TUM folders and scan lists with trajectories;
// real recorded sequences run to the end.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "fvx/io/cloud_file.hpp"
#include "fvx/io/depth_image.hpp"
#include "fvx/map/occupancy_map.hpp"
#include "fvx/scan/load.hpp"
#include "fvx/session/session.hpp"
#include "fvx/sim/builtin_scenes.hpp"
#include "fvx/sim/depth_sensor.hpp"
#include "fvx/viewpoints/fov.hpp"

namespace fvx::test {
namespace {

using nlohmann::json;

const std::string kArm = " --capmap '" + source("data/arms/fvx-arm.fcm") + "' --base 0.2,0,0,0,0,0 --arm '" +
                         source("data/arms/fvx-arm.urdf") + "'";
const std::string kReplayScene = " '" + source("data/scenes/paper-setting-2.ply") + "'";

/// A 4-view explore session of paper-setting-2 in dir/session (recorded once per test binary
/// run would save time, but each test owns its folder).
json record(const TempDir& dir) {
  const RunResult r = run_fvx(dir, "explore" + kReplayScene + kArm + " --max-views 4 --format json -o session");
  EXPECT_EQ(r.status, 0) << r.err;
  return r.status == 0 ? json::parse(r.out) : json();
}

json report(const TempDir& dir, const std::string& path) { return json::parse(slurp(dir / path)); }

TEST(CliReplay, ATargetSizeIsRecordedAndReplayed) {
  const TempDir dir;
  const RunResult e = run_fvx(dir, "explore" + kReplayScene + kArm + " --target-size 0.1 --max-views 3 --format json -o session");
  ASSERT_EQ(e.status, 0) << e.err;
  const json explored = json::parse(e.out);
  EXPECT_EQ(explored["config"]["pipeline"]["min_void_width_cells"], 3);  // floor(0.1 / 0.025) - 1
  EXPECT_EQ(session::read_manifest(dir / "session").target_size_m, 0.1);
  // Slivers left out: the first view's map holds void cells no 3-cell cube of void holds.
  const json first = report(dir, "session/reports/view000.json")["results"];
  EXPECT_GT(first["thin_void_cells"].get<int>(), 0);
  const RunResult r = run_fvx(dir, "replay session -o out --format json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json replayed = json::parse(r.out);
  EXPECT_EQ(replayed["config"]["pipeline"]["target_size_m"], 0.1);
  ASSERT_EQ(replayed["results"]["rows"].size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    const json& a = explored["results"]["rows"][i];
    const json& b = replayed["results"]["rows"][i];
    EXPECT_EQ(b["void_cells"], a["void_cells"]) << "view " << i + 1;
    EXPECT_EQ(b["map_void_cells"], a["map_void_cells"]) << "view " << i + 1;
  }
  // The default counts every void cell: more of them in the same first map.
  const RunResult all = run_fvx(dir, "replay session -o out2 --target-size 0 --to 1 --format json");
  ASSERT_EQ(all.status, 0) << all.err;
  EXPECT_GT(json::parse(all.out)["results"]["rows"][0]["map_void_cells"].get<int>(),
            explored["results"]["rows"][0]["map_void_cells"].get<int>());
  const RunResult bad = run_fvx(dir, "replay session -o out3 --target-size -1");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("--target-size"), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out3"));
}

TEST(CliReplay, TheVoidHullAndUnknownDepthAreRecordedAndReplayed) {
  const TempDir dir;
  const RunResult e = run_fvx(dir, "explore" + kReplayScene + kArm +
                                       " --void-hull search-space --unknown-depth 1 --near-unknown any --coarse-rays 20x15"
                                       " --exterior view --max-views 3 --format json -o session");
  ASSERT_EQ(e.status, 0) << e.err;
  const json explored = json::parse(e.out);
  EXPECT_EQ(explored["config"]["pipeline"]["hull_in_bounds"], true);
  EXPECT_EQ(explored["config"]["pipeline"]["nbv"]["unknown_depth_cells"], 1);
  EXPECT_EQ(explored["config"]["pipeline"]["nbv"]["near_unknown"], "any");
  EXPECT_EQ(explored["config"]["pipeline"]["nbv"]["exterior"], "view");
  const session::Manifest m = session::read_manifest(dir / "session");
  EXPECT_EQ(m.exterior, "view");
  EXPECT_TRUE(m.hull_in_bounds);
  EXPECT_EQ(m.unknown_depth_cells, 1);
  EXPECT_EQ(m.near_unknown, "any");
  EXPECT_EQ(m.coarse_ray_cols, 20);
  EXPECT_EQ(m.coarse_ray_rows, 15);
  const RunResult r = run_fvx(dir, "replay session -o out --format json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json replayed = json::parse(r.out);
  EXPECT_EQ(replayed["config"]["pipeline"]["nbv"]["coarse_rays"], json({20, 15}));
  EXPECT_EQ(replayed["config"]["pipeline"]["nbv"]["near_unknown"], "any");
  EXPECT_EQ(replayed["config"]["pipeline"]["nbv"]["exterior"], "view");
  ASSERT_EQ(replayed["results"]["rows"].size(), explored["results"]["rows"].size());
  for (std::size_t i = 0; i < replayed["results"]["rows"].size(); ++i) {
    const json& a = explored["results"]["rows"][i];
    const json& b = replayed["results"]["rows"][i];
    EXPECT_EQ(b["void_cells"], a["void_cells"]) << "view " << i + 1;
    EXPECT_EQ(b["map_void_cells"], a["map_void_cells"]) << "view " << i + 1;
  }
  // The lab's floor and wall beyond S widen the whole map's hull: more void cells in the
  // same first map.
  const RunResult whole = run_fvx(dir, "replay session -o out2 --void-hull map --to 1 --format json");
  ASSERT_EQ(whole.status, 0) << whole.err;
  EXPECT_GT(json::parse(whole.out)["results"]["rows"][0]["map_void_cells"].get<int>(),
            explored["results"]["rows"][0]["map_void_cells"].get<int>());
  for (const std::string bad : {"--void-hull walls", "--unknown-depth -1", "--coarse-rays 20", "--near-unknown none",
                                "--exterior air"}) {
    const RunResult b = run_fvx(dir, "replay session -o out3 " + bad);
    EXPECT_EQ(b.status, 2) << bad;
    EXPECT_NE(b.err.find(bad.substr(0, bad.find(' '))), std::string::npos) << b.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "out3"));
  }
}

// Without walls a Kinect measures nothing above the scene; with --no-return free those rays
// clear space up to the depth limit. The scans carry them as far points, so replay agrees.
TEST(CliReplay, RaysWithoutASurfaceClearSpaceWhenAskedAndReplayAlike) {
  const TempDir dir;
  // A first view low across the scene, so that many of its rays leave the scene without a
  // surface (the default start depends on the capability map's reach).
  const std::string run = "explore builtin:suite/1" + kArm +
                          " --start -0.3006,0.0955,0.2999,0.643,-0.0845,0.0218 --max-views 2 --format json";
  const RunResult kinect = run_fvx(dir, run + " -o kinect");
  ASSERT_EQ(kinect.status, 0) << kinect.err;
  const RunResult laser = run_fvx(dir, run + " --no-return free -o laser");
  ASSERT_EQ(laser.status, 0) << laser.err;
  const json k = json::parse(kinect.out), l = json::parse(laser.out);
  EXPECT_EQ(k["config"]["pipeline"]["clear_beyond_range"], false);
  EXPECT_EQ(l["config"]["pipeline"]["clear_beyond_range"], true);
  EXPECT_TRUE(session::read_manifest(dir / "laser").clear_beyond_range);
  // The same first view (the start), more of the space known.
  EXPECT_GT(l["results"]["rows"][0]["known_dm3"].get<double>(), 1.5 * k["results"]["rows"][0]["known_dm3"].get<double>());
  const RunResult r = run_fvx(dir, "replay laser -o out --format json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json replayed = json::parse(r.out);
  ASSERT_EQ(replayed["results"]["rows"].size(), l["results"]["rows"].size());
  for (std::size_t i = 0; i < replayed["results"]["rows"].size(); ++i) {
    EXPECT_EQ(replayed["results"]["rows"][i]["known_dm3"], l["results"]["rows"][i]["known_dm3"]) << "view " << i + 1;
    EXPECT_EQ(replayed["results"]["rows"][i]["map_void_cells"], l["results"]["rows"][i]["map_void_cells"]);
  }
  const RunResult bad = run_fvx(dir, run + " --no-return maybe -o bad");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("--no-return"), std::string::npos) << bad.err;
}

// --discretize in the loop (the insertion fvx integrate --discretize makes, held to OctoMap's
// discretised insertion node for node elsewhere): recorded in the session, replayed alike.
TEST(CliReplay, DiscretisedInsertionIsRecordedAndReplayed) {
  const TempDir dir;
  const RunResult e = run_fvx(dir, "explore" + kReplayScene + kArm + " --discretize --max-views 2 --format json -o session");
  ASSERT_EQ(e.status, 0) << e.err;
  const json explored = json::parse(e.out);
  EXPECT_EQ(explored["config"]["pipeline"]["discretize"], true);
  EXPECT_TRUE(session::read_manifest(dir / "session").discretize);
  // The same first view (the start) gives another map than the exact insertion's.
  const RunResult exact = run_fvx(dir, "explore" + kReplayScene + kArm + " --max-views 1 -o exact");
  ASSERT_EQ(exact.status, 0) << exact.err;
  EXPECT_FALSE(slurp(dir / "session/maps/view000.ot") == slurp(dir / "exact/maps/view000.ot"));  // binary: not printed
  const RunResult r = run_fvx(dir, "replay session -o out --format json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(json::parse(r.out)["config"]["pipeline"]["discretize"], true);
  for (const std::string view : {"view000.ot", "view001.ot"})
    EXPECT_TRUE(slurp(dir / ("out/maps/" + view)) == slurp(dir / ("session/maps/" + view))) << view;
}

TEST(CliReplay, ASessionReplaysToTheSameTableAndTheSameViews) {
  const TempDir dir;
  const json explored = record(dir)["results"]["rows"];
  const RunResult r = run_fvx(dir, "replay session -o out --format json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json replayed = json::parse(r.out)["results"]["rows"];
  ASSERT_EQ(explored.size(), 4u);
  ASSERT_EQ(replayed.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(replayed[i]["void_cells"], explored[i]["void_cells"]) << "view " << i + 1;
    EXPECT_EQ(replayed[i]["map_void_cells"], explored[i]["map_void_cells"]) << "view " << i + 1;
    EXPECT_EQ(replayed[i]["revealed_void_cells"], explored[i]["revealed_void_cells"]) << "view " << i + 1;
    EXPECT_NEAR(replayed[i]["utility_dm3"].get<double>(), replayed[i]["void_cells"].get<double>() * 0.015625, 1e-9);
    // The ranked views, hence the chosen one, are the same poses.
    const json a = report(dir, "session/reports/view00" + std::to_string(i) + ".json")["results"]["views"];
    const json b = report(dir, "out/reports/view00" + std::to_string(i) + ".json")["results"]["views"];
    ASSERT_EQ(a.size(), b.size()) << "view " << i + 1;
    for (std::size_t k = 0; k < a.size(); ++k) EXPECT_EQ(a[k]["position_m"], b[k]["position_m"]);
    EXPECT_EQ(report(dir, "out/reports/view00" + std::to_string(i) + ".json")["results"]["chosen_rank"], 1);
    // Each logged next view was taken at the chosen one (FK within the map's tolerance).
    if (i < 3) {
      EXPECT_LT(replayed[i]["next_distance_m"].get<double>(), 0.006) << "view " << i + 1;
    }
  }
  EXPECT_TRUE(replayed[3]["next_distance_m"].is_null());
  const map::OccupancyMap last = map::OccupancyMap::load(dir / "out/maps/view003.ot");
  EXPECT_GT(last.stats().occupied_leaves, 1000u);
  EXPECT_GT(slurp(dir / "out/volumes.png").size(), 1000u);
}

TEST(CliReplay, TwiceGivesByteIdenticalOutputsWithoutTiming) {
  const TempDir dir;
  record(dir);
  const RunResult a = run_fvx(dir, "replay session -o out --format json");
  ASSERT_EQ(a.status, 0) << a.err;
  std::filesystem::rename(dir / "out", dir / "a");
  const RunResult b = run_fvx(dir, "replay session -o out --format json");
  ASSERT_EQ(b.status, 0) << b.err;
  EXPECT_EQ(a.out, b.out);
  EXPECT_EQ(a.out.find("timing_s"), std::string::npos);
  for (int i = 0; i < 4; ++i) {
    const std::string name = "view00" + std::to_string(i);
    EXPECT_EQ(slurp(dir / ("a/maps/" + name + ".ot")), slurp(dir / ("out/maps/" + name + ".ot"))) << name;
    EXPECT_EQ(slurp(dir / ("a/reports/" + name + ".json")), slurp(dir / ("out/reports/" + name + ".json"))) << name;
  }
  EXPECT_EQ(slurp(dir / "a/volumes.png"), slurp(dir / "out/volumes.png"));
  // --timing adds each stage's time to the rows and the views' reports.
  const RunResult timed = run_fvx(dir, "replay session -o timed --to 2 --timing --format json");
  ASSERT_EQ(timed.status, 0) << timed.err;
  const json row = json::parse(timed.out)["results"]["rows"][1];
  EXPECT_TRUE(row["timing_s"]["integration"].is_number());
  EXPECT_TRUE(row["timing_s"]["search"].is_number());
  EXPECT_TRUE(report(dir, "timed/reports/view001.json")["results"]["timing_s"]["total"].is_number());
}

TEST(CliReplay, ACorruptScanStopsAtItsViewAndKeepsTheViewsBefore) {
  const TempDir dir;
  record(dir);
  {
    std::ofstream broken(dir / "session/scans/view002.pcd", std::ios::trunc);
    broken << "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\n";
  }
  RunResult r = run_fvx(dir, "replay session -o out --format csv");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(line_count(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("view 2 ("), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("view002.pcd"), std::string::npos) << r.err;
  EXPECT_EQ(line_count(r.out), 3u) << r.out;  // header and the two views before it
  for (const char* name : {"view000", "view001"}) {
    EXPECT_GT(map::OccupancyMap::load(dir / ("out/maps/" + std::string(name) + ".ot")).stats().occupied_leaves, 100u);
    EXPECT_EQ(report(dir, "out/reports/" + std::string(name) + ".json")["command"], "replay");
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "out/maps/view002.ot"));
  // A missing scan, likewise.
  std::filesystem::remove(dir / "session/scans/view002.pcd");
  r = run_fvx(dir, "replay session -o out2");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("view 2 ("), std::string::npos) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "out2/maps/view001.ot"));
}

TEST(CliReplay, FromAndToChooseTheViews) {
  const TempDir dir;
  record(dir);
  const RunResult r = run_fvx(dir, "replay session -o out --from 2 --to 3 --format csv");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(line_count(r.out), 3u) << r.out;
  EXPECT_EQ(r.out.find("\n1,"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\n2,"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\n3,"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir / "out/maps/view000.ot"));
  EXPECT_TRUE(std::filesystem::exists(dir / "out/maps/view002.ot"));
  EXPECT_FALSE(std::filesystem::exists(dir / "out/maps/view003.ot"));
}

// The session's scans as a plain list with a TUM trajectory (no stamps): the same table.
/// Writes the poses as a TUM trajectory without stamps (frame i on line i).
void write_poses(const std::string& path, const std::vector<Eigen::Isometry3d>& poses) {
  std::ofstream out(path);
  out << std::setprecision(17);
  for (const auto& T : poses) {
    const Eigen::Quaterniond q(T.linear());
    const Eigen::Vector3d t = T.translation();
    out << t.x() << ' ' << t.y() << ' ' << t.z() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << ' ' << q.w() << '\n';
  }
}

TEST(CliReplay, ScansWithATrajectoryReplayLikeTheSession) {
  const TempDir dir;
  const json explored = record(dir)["results"]["rows"];
  const session::Manifest m = session::read_manifest(dir / "session");
  {
    std::ofstream poses(dir / "poses.txt");
    poses << std::setprecision(17);
    for (const auto& v : m.views) {
      const Eigen::Quaterniond q(v.T_world_sensor_prior.linear());
      const Eigen::Vector3d t = v.T_world_sensor_prior.translation();
      poses << t.x() << ' ' << t.y() << ' ' << t.z() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << ' ' << q.w()
            << '\n';
    }
  }
  const std::string S = " --bounds 0.35,-0.75,0,1.3,0.9,0.55";
  const RunResult r = run_fvx(dir, "replay --scans 'session/scans/*.pcd' --trajectory poses.txt --no-register" + kArm +
                                       S + " -o out --format json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json listed = json::parse(r.out)["results"]["rows"];
  ASSERT_EQ(listed.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(listed[i]["void_cells"], explored[i]["void_cells"]) << "view " << i + 1;
    EXPECT_EQ(listed[i]["map_void_cells"], explored[i]["map_void_cells"]) << "view " << i + 1;
  }
}

/// `a` equals `b`, numbers within 1e-9 relative: the same pose read from a PCD's VIEWPOINT
/// and from a trajectory line (a quaternion from a rotation matrix) differ in the last bits.
void expect_near(const json& a, const json& b, const std::string& at = "") {
  if (a.is_number() && b.is_number() && !(a.is_number_integer() && b.is_number_integer())) {
    const double x = a.get<double>(), y = b.get<double>();
    EXPECT_LE(std::abs(x - y), 1e-9 * std::max({1.0, std::abs(x), std::abs(y)})) << at;
  } else if (a.is_object() && b.is_object()) {
    ASSERT_EQ(a.size(), b.size()) << at;
    for (auto it = a.begin(); it != a.end(); ++it) {
      ASSERT_TRUE(b.contains(it.key())) << at << "/" << it.key();
      expect_near(it.value(), b[it.key()], at + "/" + it.key());
    }
  } else if (a.is_array() && b.is_array()) {
    ASSERT_EQ(a.size(), b.size()) << at;
    for (std::size_t i = 0; i < a.size(); ++i) expect_near(a[i], b[i], at + "/" + std::to_string(i));
  } else {
    EXPECT_EQ(a, b) << at;
  }
}

// The pose rule (issue 20): without --trajectory a folder of PCDs replays at each file's
// VIEWPOINT, and gives the same table as the same poses given as a trajectory.
TEST(CliReplay, PcdScansReplayFromTheirViewpointsAsFromATrajectory) {
  const TempDir dir;
  record(dir);
  std::vector<Eigen::Isometry3d> viewpoints;
  for (const auto& scan : scan::expand_glob(dir / "session/scans/*.pcd", "scans"))
    viewpoints.push_back(io::read_cloud(scan).viewpoint);
  ASSERT_EQ(viewpoints.size(), 4u);
  write_poses(dir / "viewpoints.txt", viewpoints);
  const std::string common = " --no-register --to 3" + kArm + " --format json";
  const RunResult own = run_fvx(dir, "replay --scans 'session/scans/*.pcd' -o own" + common);
  const RunResult given = run_fvx(dir, "replay --scans 'session/scans/*.pcd' --trajectory viewpoints.txt -o given" + common);
  ASSERT_EQ(own.status, 0) << own.err;
  ASSERT_EQ(given.status, 0) << given.err;
  const json a = json::parse(own.out)["results"]["rows"], b = json::parse(given.out)["results"]["rows"];
  ASSERT_EQ(a.size(), 3u);
  expect_near(a, b);
  EXPECT_GT(a[2]["void_cells"].get<int>(), 0);
}

/// Of the occupied cells of `a`, the share with an occupied cell of `b` within one cell.
double share_within_one_cell(const map::OccupancyMap& a, const map::OccupancyMap& b) {
  std::size_t near = 0, all = 0;
  for (const Eigen::Vector3f& c : a.occupied_centers()) {
    ++all;
    bool found = false;
    for (int dx = -1; dx <= 1 && !found; ++dx)
      for (int dy = -1; dy <= 1 && !found; ++dy)
        for (int dz = -1; dz <= 1 && !found; ++dz) {
          const auto k = b.key_of(c.cast<double>() + b.resolution_m() * Eigen::Vector3d(dx, dy, dz));
          found = k && b.state(*k) == map::VoxelState::Occupied;
        }
    near += found;
  }
  return all ? double(near) / double(all) : 0.0;
}

// A whole explore run with pose noise (2 cm, 2° per axis on every prior after the first):
// its final map, registered, against the same scans integrated at their true poses (the
// noise-free run of these views, by replay): at least 95 % of the occupied cells agree within
// one cell, more than for the same scans at their noisy priors without registration (how much
// more depends on the views: 100 against 96.7 % here).
TEST(CliReplay, RegistrationUnderPoseNoiseMatchesTheNoiseFreeMap) {
  const TempDir dir;
  const RunResult r = run_fvx(dir, "explore" + kReplayScene + kArm + " --max-views 8 --pose-noise 0.02,2 -o session");
  ASSERT_EQ(r.status, 0) << r.err;
  const session::Manifest m = session::read_manifest(dir / "session");
  ASSERT_TRUE(m.registration);
  std::vector<Eigen::Isometry3d> truth, priors;
  for (const auto& v : m.views) {
    ASSERT_TRUE(v.T_world_sensor_true.has_value());
    truth.push_back(*v.T_world_sensor_true);
    priors.push_back(v.T_world_sensor_prior);
  }
  ASSERT_GT((priors.back().translation() - truth.back().translation()).norm(), 0.005);  // the noise is there
  write_poses(dir / "truth.txt", truth);
  write_poses(dir / "priors.txt", priors);
  const std::string last = "maps/view00" + std::to_string(m.views.size() - 1) + ".ot";
  const std::string common = " --no-register --no-capmap --bounds 0.35,-0.75,0,1.3,0.9,0.55 --search-every 0";
  ASSERT_EQ(run_fvx(dir, "replay --scans 'session/scans/*.pcd' --trajectory truth.txt -o exact" + common).status, 0);
  ASSERT_EQ(run_fvx(dir, "replay --scans 'session/scans/*.pcd' --trajectory priors.txt -o noisy" + common).status, 0);
  const map::OccupancyMap exact = map::OccupancyMap::load(dir / ("exact/" + last));
  const double registered = share_within_one_cell(map::OccupancyMap::load(dir / ("session/" + last)), exact);
  const double unregistered = share_within_one_cell(map::OccupancyMap::load(dir / ("noisy/" + last)), exact);
  EXPECT_GE(registered, 0.95);
  EXPECT_GT(registered, unregistered);
  std::printf("occupied cells within one cell of the noise-free map: registered %.1f %%, unregistered %.1f %%\n",
              100 * registered, 100 * unregistered);
}

// fvx integrate is the pipeline's step without frontiers, voids and search: on the same scans
// and priors, registered (an explore run with pose noise), it writes the map that fvx replay
// --search-every 0 holds after the last view, byte for byte.
TEST(CliReplay, IntegrateAndReplayWithoutSearchWriteTheSameMap) {
  const TempDir dir;
  const RunResult r = run_fvx(dir, "explore" + kReplayScene + kArm + " --max-views 4 --pose-noise 0.02,2 -o session");
  ASSERT_EQ(r.status, 0) << r.err;
  const session::Manifest m = session::read_manifest(dir / "session");
  std::vector<Eigen::Isometry3d> priors;
  for (const auto& v : m.views) priors.push_back(v.T_world_sensor_prior);
  ASSERT_EQ(priors.size(), 4u);
  write_poses(dir / "priors.txt", priors);
  const RunResult replayed = run_fvx(dir, "replay --scans 'session/scans/*.pcd' --trajectory priors.txt --no-capmap "
                                          "--search-every 0 -r 0.025 --depth-min 0.5 --depth-max 4 -o out");
  ASSERT_EQ(replayed.status, 0) << replayed.err;
  const RunResult integrated =
      run_fvx(dir, "integrate session/scans/view000.pcd session/scans/view001.pcd session/scans/view002.pcd "
                   "session/scans/view003.pcd --trajectory priors.txt -r 0.025 --depth-min 0.5 --depth-max 4 "
                   "--max-range 4 -o map.ot");
  ASSERT_EQ(integrated.status, 0) << integrated.err;
  const json scans = json::parse(integrated.out)["results"]["scans"];
  ASSERT_EQ(scans.size(), 4u);
  EXPECT_TRUE(scans[3]["registration"]["attempted"].get<bool>());
  EXPECT_EQ(slurp(dir / "map.ot"), slurp(dir / "out/maps/view003.ot"));
}

// A TUM RGB-D folder (depth PNGs at 5000 per metre named by stamp, groundtruth.txt) of the
// closed box rendered from three poses: the replay finds the poses by stamp and its map
// holds the box's walls where they are.
TEST(CliReplay, ATumFolderReplaysByTimestamp) {
  const TempDir dir;
  std::filesystem::create_directories(dir / "tum/depth");
  const sim::Scene scene = sim::builtin_scene("closed-box");
  const auto caster = sim::make_ray_caster(scene.mesh);
  sim::SensorConfig sensor;
  sensor.intrinsics.width = 160, sensor.intrinsics.height = 120;
  sensor.intrinsics.fx = sensor.intrinsics.fy = 131.25, sensor.intrinsics.cx = 79.5, sensor.intrinsics.cy = 59.5;
  sensor.intrinsics.depth_scale = 5000;  // TUM's
  std::ofstream truth(dir / "tum/groundtruth.txt");
  std::ofstream associations(dir / "tum/associations.txt");  // rgb and depth; the second image left out
  truth << "# timestamp tx ty tz qx qy qz qw\n" << std::setprecision(17);
  for (int i = 0; i < 3; ++i) {
    const double a = -0.6 + 0.6 * i, stamp = 1305031102.0 + 0.5 * i;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(0.77 - 1.4 * std::cos(a), -0.02 - 1.4 * std::sin(a), 1.0);
    T.linear() = viewpoints::look_along(Eigen::Vector3d(0.77, -0.02, 0.2) - T.translation(), 0.0);
    const sim::Frame frame = sim::render(*caster, T, sensor, 1);
    char name[64];
    std::snprintf(name, sizeof name, "%.6f.png", stamp + 0.004);  // depth stamps lag the poses a little
    io::write_depth_png(dir / ("tum/depth/" + std::string(name)), frame.depth);
    if (i != 1) associations << name << " rgb/" << name << ' ' << name << " depth/" << name << '\n';
    const Eigen::Quaterniond q(T.linear());
    truth << stamp << ' ' << T.translation().x() << ' ' << T.translation().y() << ' ' << T.translation().z() << ' '
          << q.x() << ' ' << q.y() << ' ' << q.z() << ' ' << q.w() << '\n';
  }
  truth.close();
  associations.close();
  const RunResult r = run_fvx(dir, "replay --tum tum --fx 131.25 --fy 131.25 --cx 79.5 --cy 59.5 --width 160 "
                                   "--height 120 --no-register -o out --format csv");  // no arm: free-flying
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(line_count(r.out), 4u) << r.out;
  const map::OccupancyMap map = map::OccupancyMap::load(dir / "out/maps/view002.ot");
  // The box's lid (z 0.38–0.40 m) is occupied at its centre-left, beside the opening.
  const auto lid = map.key_of(Eigen::Vector3d(0.6, -0.02, 0.39));
  ASSERT_TRUE(lid.has_value());
  EXPECT_EQ(map.state(*lid), map::VoxelState::Occupied);
  // An associations file chooses the depth images (TUM's associate.py output).
  const RunResult listed = run_fvx(dir, "replay --tum tum --associations tum/associations.txt --fx 131.25 --fy 131.25 "
                                        "--cx 79.5 --cy 59.5 --width 160 --height 120 --no-register -o out2 --format csv");
  ASSERT_EQ(listed.status, 0) << listed.err;
  EXPECT_EQ(line_count(listed.out), 3u) << listed.out;
}

TEST(CliReplay, BadInputIsRefusedOnOneLine) {
  const TempDir dir;
  record(dir);
  std::filesystem::create_directories(dir / "full");
  std::ofstream(dir / "full/keep.txt") << "keep";
  std::filesystem::create_directories(dir / "session/d");
  std::ofstream(dir / "session/d/0.png") << "never read";
  const std::vector<std::pair<std::string, int>> cases = {
      {"replay -o out", 2},                                               // no input
      {"replay session --scans 'x/*.pcd' --trajectory t.txt -o out", 2},  // two inputs
      {"replay session", 2},                                              // no -o
      {"replay session -o full", 2},                                      // not empty
      {"replay session -o out --to 1 --from 2", 2},
      {"replay session -o out --from 9", 2},
      {"replay session -o out --format xml", 2},
      {"replay session -o out --trajectory t.txt", 2},
      {"replay --scans 'nothing/*.pcd' --trajectory t.txt --no-capmap -o out", 2},
      {"replay --scans 'session/d/*.png' --no-capmap -o out", 1},        // depth images state no pose
      {"replay --scans 'session/scans/*.pcd' --pose-format kitti --no-capmap -o out", 2},  // no trajectory
      {"replay nowhere -o out", 1},                                       // not a session
      {"replay --tum nowhere --no-capmap -o out", 1},
      {"replay session -o out --base 0,0,0,0,0,0", 2},                   // --base without --capmap
      {"replay session -o out --planner best", 2},
      {"replay session -o out --strategy best", 2},
      {"replay session -o out --strategy frontier --planner frontier", 2},
  };
  for (const auto& [args, status] : cases) {
    const RunResult r = run_fvx(dir, args);
    EXPECT_EQ(r.status, status) << args << "\n" << r.err;
    EXPECT_EQ(line_count(r.err), 1u) << args << "\n" << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "out")) << args;
  }
  EXPECT_EQ(slurp(dir / "full/keep.txt"), "keep");
  // An output folder that cannot be created (a file in the way) is named, with the reason.
  const RunResult blocked = run_fvx(dir, "replay session -o full/keep.txt/out");
  EXPECT_EQ(blocked.status, 1) << blocked.err;
  EXPECT_EQ(line_count(blocked.err), 1u) << blocked.err;
  EXPECT_NE(blocked.err.find("full/keep.txt/out: cannot write: 'full/keep.txt' is not a folder"), std::string::npos) << blocked.err;
}

// Real recorded data: both sequences run to the end, and the utility column is the void-cell
// column times R³ in dm³ (the paper's tables obey the same rule).
void expect_paper_rule(const json& rows, double R) {
  const double cell_dm3 = R * R * R * 1000.0;
  for (const auto& row : rows)
    EXPECT_NEAR(row["utility_dm3"].get<double>(), row["void_cells"].get<double>() * cell_dm3, 1e-6) << row.dump();
}

TEST(CliReplayRealData, SlambookFiveFramesRunToTheEnd) {
  FVX_REAL_DATA_OR_SKIP(root, "slambook-joinmap-5kf");
  const TempDir dir;
  const RunResult r = run_fvx(dir, "replay --scans '" + root + "/depth/*.pgm' --trajectory '" + root +
                                       "/pose.txt' --fx 518 --fy 519 --cx 325.5 --cy 253.5 --no-capmap -r 0.05 "
                                       "-o out --format json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json rows = json::parse(r.out)["results"]["rows"];
  ASSERT_EQ(rows.size(), 5u);
  expect_paper_rule(rows, 0.05);
  for (const auto& row : rows) EXPECT_GT(row["void_cells"].get<int>(), 0) << row.dump();
  for (std::size_t i = 1; i < rows.size(); ++i)  // registered by default, to the scans before
    EXPECT_FALSE(rows[i]["registration_fitness_m"].is_null()) << rows[i].dump();
  EXPECT_GT(rows[4]["known_dm3"].get<double>(), rows[0]["known_dm3"].get<double>());
}

/// fvx replay of the Redwood living-room frames in `root` with their trajectory, then `options`.
std::string redwood_replay(const std::string& root, const std::string& options) {
  return "replay --scans '" + root + "/depth/*.png' --trajectory '" + root + "/trajectory_open3d_estimated.log' " +
         options;
}

TEST(CliReplayRealData, RedwoodFirstThirtyFramesRunToTheEnd) {
  FVX_REAL_DATA_OR_SKIP(root, "redwood-livingroom1-micro");
  const TempDir dir;
  const RunResult r = run_fvx(dir, redwood_replay(root, "--no-capmap --no-register -r 0.05 --to 30 -o out --format json"));
  ASSERT_EQ(r.status, 0) << r.err;
  const json rows = json::parse(r.out)["results"]["rows"];
  ASSERT_EQ(rows.size(), 30u);
  expect_paper_rule(rows, 0.05);
  EXPECT_TRUE(std::filesystem::exists(dir / "out/maps/view029.ot"));
  EXPECT_FALSE(std::filesystem::exists(dir / "out/maps/view030.ot"));
}

// The 211 Redwood frames at 2.5 cm, integrated without registration (the poses of the
// trajectory): every per-view map is byte for byte the one recorded in
// tests/data/redwood-211-maps.sha256. Integration is exact (OctoMap's insertPointCloud, bit
// for bit: test_integrate), so a faster integration must keep these bytes. Recorded with the
// binary of 3a891ed by the command below and `sha256sum view*.ot` in out/maps.
TEST(CliReplayRealData, Redwood211FramesGiveTheRecordedMaps) {
  FVX_REAL_DATA_OR_SKIP(root, "redwood-livingroom1-micro");
  const TempDir dir;
  const RunResult r = run_fvx(dir, redwood_replay(root, "--fx 525 --fy 525 --cx 319.5 --cy 239.5 -r 0.025 --no-capmap "
                                                        "--no-register --search-every 0 -o out --format csv"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(line_count(r.out), 212u);  // the header and 211 views
  const std::string sums = source("tests/data/redwood-211-maps.sha256");
  const std::string check = "cd '" + (dir / "out/maps") + "' && sha256sum --quiet -c '" + sums + "' > '" +
                            (dir / "check.txt") + "' 2>&1";
  EXPECT_EQ(std::system(check.c_str()), 0) << slurp(dir / "check.txt");
}

}  // namespace
}  // namespace fvx::test
