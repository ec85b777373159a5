#pragma once
/// \file
/// What `fvx replay` reads: a session directory (fvx-session.5) with the loop's settings as
/// recorded, or scan files with pose priors. Scans are loaded when their turn comes.
#include <string>
#include <vector>

#include "fvx/scan/load.hpp"
#include "fvx/session/replay.hpp"

namespace fvx::session {

/// A session directory's recording.
struct SessionRecording {
  std::vector<RecordedScan> scans;  ///< each at its recorded prior, with the true pose
  /// The arm's files as the manifest names them, resolved against the directory (empty: the
  /// session was free-flying), and where its base stood.
  std::string capmap_path, arm_path;
  Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();
};

/// Reads `dir`'s manifest and sets the loop's settings in `config` as recorded: the sensor,
/// resolution, search space and view bounds, strategy, seed, registration, near voids,
/// target size and accumulation. FileError for a bad manifest or sensor file; Error for a
/// session without views.
SessionRecording read_session(const std::string& dir, ReplayConfig& config);

/// Scan files with the pose priors `load` assigns them (scan::plan_scans), each loaded with
/// `load` when its turn comes; the plan's warnings are appended to `warnings`.
std::vector<RecordedScan> recorded_scans(const std::vector<std::string>& paths, const scan::LoadConfig& load,
                                         std::vector<std::string>& warnings);
/// The scans of a plan (files or a bag's messages), each loaded with `load` when its turn comes.
std::vector<RecordedScan> recorded_scans(const scan::ScanPlan& plan, const scan::LoadConfig& load);

}  // namespace fvx::session
