#include "fvx/report/capmap.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

#include "fvx/io/visual.hpp"

namespace fvx::report {

namespace {

std::size_t bits_of(const std::vector<std::uint64_t>& words) {
  std::size_t n = 0;
  for (std::uint64_t w : words) n += std::size_t(__builtin_popcountll(w));
  return n;
}

}  // namespace

Json capmap_header_json(const capmap::CapabilityHeader& h) {
  Json j = {{"base_link", h.base_link},   {"tip_link", h.tip_link},   {"mount_xyz_rpy", h.mount_xyz_rpy},
          {"viewing_axis", vec_json(h.viewing_axis)},  {"urdf_hash", h.urdf_hash},
          {"voxel_m", h.voxel_m},       {"origin_m", vec_json(h.origin_m)},      {"dims", h.dims},
          {"directions", h.directions}, {"position_tolerance_m", h.position_tolerance_m},
          {"angle_tolerance_deg", h.angle_tolerance_rad * 180.0 / M_PI},      {"method", h.method},
          {"seed", h.seed},             {"shard_index", h.shard_index},     {"shard_count", h.shard_count},
          {"fvx_version", h.fvx_version}, {"layout", h.layout}};
  if (h.shard_split == "samples")
    j["shard_split"] = h.shard_split, j["target_recall"] = h.target_recall, j["fk_samples"] = h.fk_samples;
  if (h.layout == "turn")
    j["turn"] = {{"point_m", vec_json(h.turn.point_base)}, {"axis", vec_json(h.turn.axis_base)},
                 {"x_axis", vec_json(h.turn.x_base)},
                 {"limits_deg", {h.turn.lower_rad * 180.0 / M_PI, h.turn.upper_rad * 180.0 / M_PI}},
                 {"cell_m", h.turn.cell_m}, {"relative_directions", h.turn.relative_directions}};
  return j;
}

Json capmap_info_json(const capmap::CapabilityMap& map) {
  std::vector<std::size_t> histogram(10, 0);  // reachability index in 10 % bins
  std::size_t bits = 0;
  for (const auto& [voxel, words] : map.voxels()) {
    const std::size_t n = bits_of(words);
    bits += n;
    histogram[std::min<std::size_t>(9, n * 10 / std::size_t(map.header().directions))] += 1;
  }
  return {{"header", capmap_header_json(map.header())}, {"voxels", map.voxel_count()}, {"bits", bits},
          {"turn_witnesses", map.turn_witnesses().size()},
          {"reachability_index_histogram", {{"bin_width_percent", 10}, {"voxels", histogram}}}};
}

Json capmap_query_json(const capmap::CapabilityMap& map, const Eigen::Vector3d& p,
                       const std::optional<Eigen::Vector3d>& direction) {
  Json r = {{"point_m", vec_json(p)}, {"inside_grid", map.voxel_of(p) >= 0},
            {"reachability_index", map.reachability_index(p)}};
  if (direction) {
    r["direction"] = vec_json(*direction);
    r["reachable"] = map.reachable(p, *direction);
  }
  Json dirs = Json::array();
  for (int i : map.reachable_directions(p)) dirs.push_back(vec_json(map.directions()[std::size_t(i)]));
  r["reachable_directions"] = dirs;
  return r;
}

std::size_t write_capmap_cloud(const std::string& path, const capmap::CapabilityMap& map) {
  std::vector<Eigen::Vector3f> points;
  std::vector<io::Rgb> colors;
  for (const auto& [voxel, words] : map.voxels()) {
    const double ri = double(bits_of(words)) / map.header().directions;  // 0 … 1: blue (low) to red (high)
    points.push_back(map.center_of(voxel).cast<float>());
    colors.push_back({std::uint8_t(255 * std::min(1.0, 2 * ri)), 60, std::uint8_t(255 * std::max(0.0, 1 - 2 * ri))});
  }
  io::write_colored_cloud(path, points, colors);
  return points.size();
}

Json capmap_evaluation_json(const capmap::Evaluation& e, const std::string& method) {
  Json bands = Json::array();
  for (const auto& band : e.recall_by_height)
    if (band.recall.queries)
      bands.push_back({{"z_min_m", band.z_min_m},
                       {"z_max_m", band.z_max_m},
                       {"queries", band.recall.queries},
                       {"recall", band.recall.value()},
                       {"recall_interval_95", {band.recall.low(), band.recall.high()}}});
  return {{"bit_definition", method},
          {"precision", e.precision.value()},
          {"precision_interval_95", {e.precision.low(), e.precision.high()}},
          {"precision_queries", e.precision.queries},
          {"recall", e.recall.value()},
          {"recall_interval_95", {e.recall.low(), e.recall.high()}},
          {"recall_queries", e.recall.queries},
          {"recall_by_height", bands}};
}

Json capmap_first_joint_axis_json(const capmap::Arm& arm) {
  const auto& axis = arm.first_joint_axis();
  if (!axis) return nullptr;
  const Eigen::Vector3d& p = axis->point_base;
  const Eigen::Vector3d& d = axis->direction_base;
  return {{"joint", arm.joint_names().front()}, {"point_m", {p.x(), p.y(), p.z()}}, {"direction", {d.x(), d.y(), d.z()}},
          {"tilt_from_vertical_deg", axis->tilt_from_vertical_rad() * 180.0 / M_PI},
          {"limits_deg", {arm.lower_rad()[0] * 180.0 / M_PI, arm.upper_rad()[0] * 180.0 / M_PI}}};
}

Json capmap_build_config_json(const capmap::BuildConfig& c) {
  return {{"seed", c.seed}, {"method", capmap::to_string(c.method)}, {"fk_samples", c.fk_samples},
          {"target_recall", c.target_recall}, {"ik_restarts", c.ik_restarts}, {"threads", c.threads},
          {"turns_per_fk", c.turns_per_fk}, {"use_first_joint_turn", c.use_first_joint_turn},
          {"layout", capmap::to_string(c.layout)}, {"shard_split", capmap::to_string(c.shard_split)}};
}

Json capmap_build_json(const capmap::CapabilityMap& map, const capmap::BuildStats& stats, double seconds) {
  return {{"header", capmap_header_json(map.header())},
          {"voxels", map.voxel_count()},
          {"bits", stats.reached},
          {"candidates_checked", stats.candidates},
          {"ik_iterations", stats.ik_iterations},
          {"fk_samples", stats.fk_samples},
          {"fk_evaluations", stats.fk_evaluations},
          {"turn_witnesses", map.turn_witnesses().size()},
          {"estimated_recall", stats.estimated_recall},
          {"seconds", seconds}};
}

}  // namespace fvx::report
