#pragma once
/// \file
/// The output folder of a session, written as the loop goes. An exploration's is a session
/// directory (man/fvx-session.5): per view the scan, the map after it and its report, then
/// the manifest that lists them, so that a manifest never names a file that is not complete
/// and a run cut short leaves a session that fvx replay reads up to its last view. A
/// replay's holds the per-view maps and reports (no scans: they are the recording's).
#include <string>

#include "fvx/io/intrinsics.hpp"
#include "fvx/map/occupancy_map.hpp"
#include "fvx/session/session.hpp"

namespace fvx::session {

/// "view007.ot" for view 7 and ".ot": the name of a view's file in a session folder.
std::string view_file_name(int view, const char* extension);

class Recorder {
 public:
  /// Creates dir/scans, dir/maps and dir/reports, writes the sensor file (manifest.sensor)
  /// and the manifest without views. `manifest.views` must be empty.
  Recorder(std::string dir, Manifest manifest, const io::DepthCamera& sensor);
  /// A replay's output: dir/maps and dir/reports, made with the first view written (a
  /// replay that fails at its first view leaves no folder); no manifest.
  explicit Recorder(std::string dir);

  /// The files of view `view`, relative to the session folder, with its poses and joints.
  ManifestView files_of(const ViewRecord& v) const;
  /// Writes v's scan (an organised PCD in the sensor frame, VIEWPOINT = the prior), `map`
  /// and `report_text` (its report, as it is), then the manifest listing the view.
  void add(const ViewRecord& v, const map::OccupancyMap& map, const std::string& report_text);
  /// A replay's view: its map as maps/viewNNN.ot, and its report as reports/viewNNN.json.
  void save_map(int view, const map::OccupancyMap& map) const;
  void save_report(int view, const std::string& report_text) const;
  const std::string& dir() const { return dir_; }

  const Manifest& manifest() const { return manifest_; }

 private:
  std::string dir_;
  Manifest manifest_;
  io::DepthCamera sensor_;
};

}  // namespace fvx::session
