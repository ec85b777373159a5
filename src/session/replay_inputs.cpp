#include "fvx/session/replay_inputs.hpp"

#include <filesystem>

#include "fvx/core/error.hpp"
#include "fvx/io/intrinsics.hpp"
#include "fvx/session/session.hpp"

namespace fvx::session {

namespace {

/// The loop's settings a manifest records.
void apply_manifest(const Manifest& m, const std::string& dir, ReplayConfig& config) {
  pipeline::Config& pc = config.pipeline;
  nbv::Config& nc = pc.nbv;
  nc.sensor = io::read_depth_camera((std::filesystem::path(dir) / m.sensor).string());
  pc.resolution_m = m.resolution_m;
  pc.bounds_m = m.search_space_m;
  nc.view_bounds_m = m.view_bounds_m;
  nc.strategy = nbv::parse_strategy(m.strategy, dir + "/manifest.json: strategy");
  nc.seed = m.seed;
  pc.register_scans = m.registration;
  nc.count_near_void_cells = m.near_voids;
  pc.target_size_m = m.target_size_m;
  pc.hull_in_bounds = m.hull_in_bounds;
  pc.clear_beyond_range = m.clear_beyond_range;
  pc.discretize = m.discretize;
  nc.unknown_depth_cells = m.unknown_depth_cells;
  nc.near_unknown = viewpoints::parse_near_unknown(m.near_unknown, dir + "/manifest.json: near_unknown");
  nc.exterior = nbv::parse_exterior(m.exterior, dir + "/manifest.json: exterior");
  nc.accumulation = utility::parse_accumulation(m.accumulation, dir + "/manifest.json: accumulation");
  nc.max_utility_vectors = std::size_t(m.max_utility_vectors);
  nc.coarse_ray_cols = m.coarse_ray_cols;
  nc.coarse_ray_rows = m.coarse_ray_rows;
}

}  // namespace

SessionRecording read_session(const std::string& dir, ReplayConfig& config) {
  const Manifest m = read_manifest(dir);
  if (m.views.empty()) throw Error("fvx replay: " + dir + ": the session holds no view");
  apply_manifest(m, dir, config);
  SessionRecording out;
  if (!m.capmap.empty()) {
    out.capmap_path = resolve_path(m.capmap, dir);
    out.arm_path = resolve_path(m.arm, dir);
    out.T_world_base = m.T_world_base.value_or(Eigen::Isometry3d::Identity());
  }
  for (const ManifestView& v : m.views) {
    RecordedScan r;
    r.name = (std::filesystem::path(dir) / v.scan).string();
    r.T_world_sensor_true = v.T_world_sensor_true;
    const Eigen::Isometry3d prior = v.T_world_sensor_prior;
    r.load = [path = r.name, prior]() {
      scan::ScanSource source{path, prior, scan::PoseSource::Trajectory, std::nullopt};
      std::vector<std::string> warnings;
      return scan::load_scan(source, scan::LoadConfig{}, warnings);
    };
    out.scans.push_back(std::move(r));
  }
  return out;
}

std::vector<RecordedScan> recorded_scans(const std::vector<std::string>& paths, const scan::LoadConfig& load,
                                         std::vector<std::string>& warnings) {
  const scan::ScanPlan plan = scan::plan_scans(paths, load);
  warnings.insert(warnings.end(), plan.warnings.begin(), plan.warnings.end());
  return recorded_scans(plan, load);
}

std::vector<RecordedScan> recorded_scans(const scan::ScanPlan& plan, const scan::LoadConfig& load) {
  std::vector<RecordedScan> scans;
  for (const scan::ScanSource& source : plan.scans) {
    RecordedScan r;
    r.name = source.path;
    r.load = [source, load]() {
      std::vector<std::string> ignored;
      return scan::load_scan(source, load, ignored);
    };
    scans.push_back(std::move(r));
  }
  return scans;
}

}  // namespace fvx::session
