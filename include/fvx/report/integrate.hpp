#pragma once
/// \file
/// What `fvx integrate` reports: its effective settings, each scan (points kept, pose prior,
/// registration, the pose used, what changed in the map) and the map written.
#include "fvx/core/json.hpp"
#include "fvx/map/occupancy_map.hpp"
#include "fvx/pipeline/integrate_files.hpp"

namespace fvx::report {

/// The step's settings, then how scans are read (`load`) and the map's sensor model.
Json integrate_config_json(const pipeline::Config& config, const scan::LoadConfig& load, const map::OccupancyMap& map);
/// Node and leaf counts, volumes and the known cells' box of a map.
Json map_json(const map::Stats& s);
Json registration_json(const registration::Result& r);
Json integration_json(const map::IntegrationCounts& c);
/// One scan's entry; `registering`: registration was asked for (says why a scan has none);
/// its times only with `timing`.
Json integrated_scan_json(const pipeline::IntegratedScan& s, bool registering, bool timing);

}  // namespace fvx::report
