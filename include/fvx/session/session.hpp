#pragma once
/// \file
/// Stage `session` (paper §V): a session directory (man/fvx-session.5) — the scans of an
/// exploration, its manifest, the map and report after each view — and `explore`, the
/// closed loop of §IV steps 1–7 on a sensor that scans where it is told.
#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <optional>
#include <utility>
#include <string>
#include <vector>

#include "fvx/io/intrinsics.hpp"
#include "fvx/pipeline/pipeline.hpp"

namespace fvx::session {

constexpr int kSchemaVersion = 1;

/// One view of a session, paths relative to the session directory.
struct ManifestView {
  int view = 0;                                      ///< 0-based, in order
  std::string scan;                                  ///< PCD, sensor frame, VIEWPOINT = prior
  std::string map;                                   ///< .ot after integrating this view
  std::string report;                                ///< JSON: analysis and next best views
  Eigen::Isometry3d T_world_sensor_prior = Eigen::Isometry3d::Identity();  ///< as recorded
  /// Simulation only: where the sensor really was.
  std::optional<Eigen::Isometry3d> T_world_sensor_true;
  Eigen::VectorXd joints_rad;                        ///< the arm's configuration; empty without one
  double stamp_s = 0.0;                              ///< simulated: one second per view
};

struct Manifest {
  int schema_version = kSchemaVersion;
  std::string created_by;                            ///< "fvx explore 0.x"
  std::string scene;                                 ///< simulation: the scene's file
  std::string sensor = "sensor.json";                ///< io::read_depth_camera layout
  double resolution_m = 0.025;
  std::optional<Eigen::AlignedBox3d> search_space_m;
  std::optional<Eigen::AlignedBox3d> view_bounds_m;
  std::optional<Eigen::Isometry3d> T_world_base;     ///< with an arm
  std::string arm;                                   ///< URDF path as given; empty: free-flying
  std::string capmap;                                ///< capability map path as given
  std::string capmap_urdf_hash;
  std::string strategy = "frontier-void";           ///< nbv::Strategy; key "planner" in older sessions
  std::uint64_t seed = 1;
  double pose_noise_m = 0.0, pose_noise_deg = 0.0;   ///< σ of the recorded priors' error
  bool registration = false;
  /// The planner's U counted void cells nearer than the sensor's minimum depth
  /// (nbv::Config::count_near_void_cells; fvx explore --near-voids). Absent: false.
  bool near_voids = false;
  /// Only void cells that could hide an object this large counted (fvx explore
  /// --target-size; voids/width.hpp), metres. Absent: 0, every void cell.
  double target_size_m = 0.0;
  /// The voids' hull from the occupied cells in the search space only (pipeline::Config::
  /// hull_in_bounds; fvx explore --void-hull search-space). Absent: false.
  bool hull_in_bounds = false;
  /// U counted only the first N unknown cells of each ray (nbv::Config::unknown_depth_cells;
  /// fvx explore --unknown-depth). Absent: 0, every void cell.
  int unknown_depth_cells = 0;
  /// What an unknown cell nearer than the minimum depth did to a ray of U (nbv::Config::
  /// near_unknown; fvx explore --near-unknown). Absent: "ignore", as every session before
  /// the rule was searched.
  std::string near_unknown = "ignore";
  /// Scans hold rays without a surface as points beyond the depth limit, which clear their
  /// ray (pipeline::Config::clear_beyond_range; fvx explore --no-return free). Absent: false.
  bool clear_beyond_range = false;
  /// What the search took unknown cells outside the voids' hull for: "unknown", "view" or
  /// "free" (nbv::Config::exterior; fvx explore --exterior). Absent: "unknown".
  std::string exterior = "unknown";
  /// Scans were integrated by OctoMap's discretised insertion (pipeline::Config::discretize;
  /// fvx explore --discretize). Absent: false, exact insertion.
  bool discretize = false;
  /// Algorithm 1's accumulation (nbv::Config::accumulation) and its budget. Absent:
  /// "exact", as every session before the sampled accumulation was recorded.
  std::string accumulation = "exact";
  std::uint64_t max_utility_vectors = std::uint64_t(1) << 21;
  /// The coarse fan that screened poses (nbv::Config::coarse_ray_cols, rows). Absent: 0 × 0
  /// (off), as every session before screening was searched.
  int coarse_ray_cols = 0, coarse_ray_rows = 0;
  std::vector<ManifestView> views;
};

/// Writes <dir>/manifest.json atomically.
void write_manifest(const std::string& dir, const Manifest& manifest);
/// Reads <dir>/manifest.json; FileError naming the file and the problem (missing keys, an
/// unknown schema version, a view out of order).
Manifest read_manifest(const std::string& dir);
/// Writes the sensor file (io::read_depth_camera's layout) atomically.
void write_depth_camera(const std::string& path, const io::DepthCamera& camera);

/// A path from a manifest: as written (relative to where explore ran) when it exists, else
/// relative to the session folder `session_dir` when that exists, else as written.
std::string resolve_path(const std::string& path, const std::string& session_dir);

struct ExploreConfig {
  pipeline::Config pipeline;                 ///< the map, registration, and the planner (pipeline.nbv.strategy)
  Eigen::Isometry3d T_world_sensor_start = Eigen::Isometry3d::Identity();
  int max_views = 15;                        ///< the loop stops after this many scans
  /// Each recorded prior after the first is off its true pose by a Gaussian translation of
  /// σ = pose_noise_m per axis and a rotation of σ = pose_noise_deg about each axis. The
  /// first view defines the map frame and is exact.
  double pose_noise_m = 0.0;
  double pose_noise_deg = 0.0;
  std::uint64_t seed = 1;                    ///< pose noise
  std::vector<std::string> validate() const;
};

/// The loop's settings and the step's (pipeline::config_json), as a report echoes them.
Json config_json(const ExploreConfig& c);

/// What a session's manifest records of an explore run of `config` on the scene file `scene`,
/// without its views (the Recorder adds them): with `reach`, the arm's files as given
/// (`capmap_path`, `arm_path`, may be empty), its base and the map's URDF hash.
Manifest explore_manifest(const ExploreConfig& config, const std::string& scene, const std::optional<nbv::Reach>& reach,
                          const std::string& capmap_path, const std::string& arm_path);

/// The scan a sensor records at its true pose: sensor-frame points, NaN where a pixel has
/// no measurement.
using Sensor = std::function<std::vector<Eigen::Vector3d>(const Eigen::Isometry3d& T_world_sensor_true, int view)>;

struct ViewRecord {
  int view = 0;
  Eigen::Isometry3d T_world_sensor_true = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_world_sensor_prior = Eigen::Isometry3d::Identity();  ///< true + noise
  Eigen::VectorXd joints_rad;
  std::vector<Eigen::Vector3d> points_sensor;  ///< as recorded (NaN kept)
  double scan_s = 0.0;                         ///< the sensor's time (rendering)
  pipeline::StepResult step;
  /// The view of step.nbv.views the sensor moves to next: the best ranked one not taken
  /// already (within 5 cm and 10°). Empty when the loop ends here.
  std::optional<std::size_t> chosen;
  /// Of the void cells the previous view's analysis held, how many this scan made known;
  /// and what the previous view's chosen pose predicted (U). Zero for the first view.
  std::size_t previous_prediction = 0;
  std::size_t revealed_void_cells = 0;
};

struct ExploreResult {
  int views = 0;
  std::string end;   ///< why the loop stopped: the planner's reason, or the view limit
  bool utility_exhausted = false;  ///< the planner found no view with U > 0
};

/// The best ranked view (index into `views`) that is not the same view (nbv::same_view) as
/// one in `taken`. The loops' searches already pass over such poses (State::taken_views):
/// this is their guard.
std::optional<std::size_t> first_view_not_taken(const std::vector<nbv::View>& views,
                                                const std::vector<Eigen::Isometry3d>& taken);

/// Where the sensor really starts and the arm's configuration there: with an arm, the
/// capability map must reach the pose (Error otherwise) and, with its URDF, IK must solve it;
/// the sensor then stands at the forward kinematics of that solution.
std::pair<Eigen::Isometry3d, Eigen::VectorXd> start_configuration(const std::optional<nbv::Reach>& reach,
                                                                   const Eigen::Isometry3d& T_world_sensor,
                                                                   std::uint64_t seed);

/// Runs §IV steps 1–7 from the start pose until the planner finds no view (utility 0) or
/// max_views: scan, register (when pipeline.register_scans), integrate, frontiers and voids,
/// next best view, move there. With an arm, the sensor moves to the forward kinematics of
/// the chosen view's IK configuration. The start pose must be reachable (Error otherwise).
/// `on_view` sees each view and the state after it, in order.
ExploreResult explore(const Sensor& sensor, const std::optional<nbv::Reach>& reach, const ExploreConfig& config,
                      const std::function<void(const ViewRecord&, const pipeline::State&)>& on_view);

}  // namespace fvx::session
