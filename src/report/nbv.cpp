#include "fvx/report/nbv.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

#include "fvx/core/pose.hpp"
#include "fvx/report/analysis.hpp"

namespace fvx::report {

io::Rgb ramp(double t) {  // red → yellow → green, as the paper's Figure 4
  t = std::clamp(t, 0.0, 1.0);
  return t < 0.5 ? io::Rgb{230, std::uint8_t(230 * 2 * t), 30} : io::Rgb{std::uint8_t(230 * 2 * (1 - t)), 200, 30};
}

/// Each kept cell's utility as its rank among the kept cells, in [0, 1]: utility spans orders
/// of magnitude (it piles up next to the frontier), so a linear scale would paint nearly all
/// of it "low".
std::vector<double> utility_ranks(const nbv::Result& r) {
  std::vector<double> kept;
  for (const auto& c : r.utility_field)
    if (c.kept) kept.push_back(c.utility_m3);
  std::sort(kept.begin(), kept.end());
  std::vector<double> ranks;
  for (const auto& c : r.utility_field) {
    const auto below = std::lower_bound(kept.begin(), kept.end(), c.utility_m3) - kept.begin();
    ranks.push_back(kept.size() > 1 ? double(below) / double(kept.size() - 1) : 1.0);
  }
  return ranks;
}

void write_utility_cloud(const std::string& path, const nbv::Result& r) {
  const std::vector<double> rank = utility_ranks(r);
  std::vector<Eigen::Vector3f> points;
  std::vector<io::Rgb> colors;
  for (std::size_t i = 0; i < r.utility_field.size(); ++i) {
    const auto& c = r.utility_field[i];
    points.push_back(c.center_m.cast<float>());
    colors.push_back(c.kept ? ramp(rank[i]) : io::Rgb{170, 170, 170});
  }
  io::write_colored_cloud(path, points, colors);
}

void write_utility_picture(const std::string& path, const map::OccupancyMap& map, const frontier_voids::Analysis& a,
                           const nbv::Result& r) {
  // The whole map's occupied cells: viewpoints may lie outside the search space.
  const map::Stats stats = map.stats();
  std::vector<io::PictureLayer> layers = {
      occupied_layer(map, Eigen::AlignedBox3d(stats.known_min_m, stats.known_max_m)), void_layer(map, a)};
  const std::vector<double> rank = utility_ranks(r);
  io::PictureLayer pruned{"utility, pruned", {200, 200, 200}, {}, true, false};
  io::PictureLayer low{"utility, lowest third", ramp(0.0), {}, false, false},
      mid{"utility, middle third", ramp(0.5), {}, false, false}, high{"utility, highest third", ramp(1.0), {}, false, false};
  for (std::size_t i = 0; i < r.utility_field.size(); ++i) {
    const auto& c = r.utility_field[i];
    if (!c.kept) {
      pruned.centers_m.push_back(c.center_m);
      continue;
    }
    (rank[i] < 1.0 / 3 ? low : rank[i] < 2.0 / 3 ? mid : high).centers_m.push_back(c.center_m);
  }
  for (auto* layer : {&pruned, &low, &mid, &high}) layers.push_back(std::move(*layer));
  io::PictureLayer best{"best view", {30, 90, 230}, {}, false, false};
  if (!r.views.empty()) {
    // The viewpoint and its optical axis for half a metre.
    const Eigen::Isometry3d& T = r.views.front().T_world_sensor;
    for (double s = 0.0; s <= 0.5; s += map.resolution_m()) best.centers_m.push_back(T * Eigen::Vector3d(0, 0, s));
  }
  layers.push_back(std::move(best));
  io::write_top_view_png(path, map.resolution_m(), layers);
}

namespace {

Json view_json(const nbv::View& v, int rank, double R, const frontier_voids::Analysis& a,
               const std::vector<std::string>& joint_names, nbv::Strategy strategy) {
  const Eigen::Isometry3d& T = v.T_world_sensor;
  const Eigen::Vector3d rpy = rpy_of(T.linear()) * 180.0 / M_PI;
  Json j = {{"rank", rank}};
  const Json pose = pose_json(T);
  j["position_m"] = pose["position_m"];
  j["quaternion_xyzw"] = pose["quaternion_xyzw"];
  j["rpy_deg"] = vec_json(rpy);
  j["viewing_direction"] = vec_json(T.linear().col(2));
  if (v.joints_rad.size() > 0) {
    Json joints = Json::object();
    for (int i = 0; i < v.joints_rad.size(); ++i) joints[joint_names[std::size_t(i)]] = v.joints_rad[i];
    j["joints_rad"] = joints;
  } else {
    j["joints_rad"] = nullptr;
  }
  j["void_cells_seen"] = v.void_cells_seen;
  j["utility_dm3"] = frontier_voids::to_dm3(double(v.void_cells_seen) * R * R * R);  // as fvx voids
  if (strategy == nbv::Strategy::Frontier) {
    j["frontier_cells_seen"] = v.frontier_cells_seen;
    j["frontier_rays_through_cell"] = v.frontier_rays_through_cell;
  } else {
    j["accumulated_utility_dm3"] = frontier_voids::to_dm3(v.accumulated_utility_m3);
  }
  Json serves = Json::array();
  for (const auto& [void_id, cells] : v.voids_seen)
    serves.push_back({{"void_id", void_id}, {"cells_seen", cells},
                      {"void_cells", a.void_clusters[std::size_t(void_id)].cells.size()}});
  j["voids_seen"] = serves;
  Json from = Json::array();
  for (const int fv : v.utility_from)
    from.push_back({{"frontier_void", fv}, {"void_id", a.frontier_voids[std::size_t(fv)].void_id},
                    {"utility_dm3", frontier_voids::to_dm3(a.frontier_voids[std::size_t(fv)].utility_m3)}});
  j["utility_from"] = from;
  j["pose_index"] = v.pose_index;
  j["stepped_back_from"] = v.stepped_back_from ? Json(*v.stepped_back_from) : Json(nullptr);
  j["polished_from"] = v.polished_from ? Json(*v.polished_from) : Json(nullptr);
  return j;
}

Json pruning_json(const nbv::Pruning& p) {
  return {{"utility_cells", p.utility_cells},
          {"not_free", p.not_free},
          {"outside_view_bounds", p.outside_view_bounds},
          {"too_close_to_obstacle", p.too_close_to_obstacle},
          {"unreachable_position", p.unreachable_position},
          {"candidate_cells", p.candidate_cells},
          {"too_near_a_tried_cell", p.too_near_a_tried_cell},
          {"cells_tried", p.cells_tried},
          {"orientations_sampled", p.orientations_sampled},
          {"unreachable_orientation", p.unreachable_orientation},
          {"ik_failed", p.ik_failed},
          {"valid_poses", p.valid_poses},
          {"refinement_steps", p.refinement_steps},
          {"refinement_poses", p.refinement_poses},
          {"polish_poses", p.polish_poses},
          {"culled_no_void_in_frustum", p.culled},
          {"seeing_no_void", p.seeing_nothing},
          {"already_taken", p.already_taken}};
}

}  // namespace

/// The effective settings: the search's, then the analysis's and where the arm stands.
Json search_config_json(const nbv::Config& config, double target_size_m, int void_width, bool hull_in_bounds,
                 const std::optional<Eigen::AlignedBox3d>& bounds, const voids::ClusterConfig& cluster_config,
                 const std::optional<Eigen::Isometry3d>& T_world_base) {
  Json j = nbv::config_json(config);
  j["target_size_m"] = target_size_m;
  j["min_void_width_cells"] = void_width;
  j["hull_in_bounds"] = hull_in_bounds;
  j["bounds_m"] = bounds_json(bounds);
  j["min_fit_score"] = cluster_config.min_fit_score;
  j["T_world_base"] = T_world_base ? pose_json(*T_world_base) : Json(nullptr);
  return j;
}

Json nbv_results_json(const nbv::Result& r, const frontier_voids::Analysis& a, double R,
                      const std::vector<std::string>& joint_names, nbv::Strategy strategy, bool timing) {
  Json views = Json::array();
  for (std::size_t i = 0; i < r.views.size(); ++i)
    views.push_back(view_json(r.views[i], int(i + 1), R, a, joint_names, strategy));
  const std::size_t open = std::size_t(std::count_if(a.frontier_voids.begin(), a.frontier_voids.end(),
                                                     [](const auto& fv) { return !fv.enclosed(); }));
  Json results = {{"bounds_m", bounds_json(a.bounds_m)},
                  {"void_cells", a.void_cells.size()},
                  {"thin_void_cells", a.thin_void_cells},
                  {"void_clusters", a.void_clusters.size()},
                  {"frontier_cells", a.frontier_cells.size()},
                  {"frontier_voids_open", open},
                  {"utility_vectors", r.utility_vectors},
                  {"exact_utility_vectors", r.exact_utility_vectors},
                  {"poses_scored", r.poses_scored},
                  {"best_void_cells_seen", r.views.empty() ? 0 : r.views.front().void_cells_seen},
                  {"best_utility_dm3", r.views.empty() ? 0.0 : views.front()["utility_dm3"].get<double>()},
                  {"reason", r.reason.empty() ? Json(nullptr) : Json(r.reason)},
                  {"pruning", pruning_json(r.pruning)},
                  {"views", views}};
  if (timing) {
    const auto& t = r.timing;
    results["timing_s"] = {{"grid", t.grid_s},         {"accumulation", t.accumulation_s}, {"pruning", t.pruning_s},
                           {"sampling", t.sampling_s}, {"scoring", t.scoring_s},           {"total", t.total_s},
                           {"rays", t.rays},           {"cells_visited", t.cells_visited},
                           {"cells_per_s", t.scoring_s > 0 ? double(t.cells_visited) / t.scoring_s : 0.0}};
  }
  return results;
}

Json arm_json(const std::string& path, const std::string& urdf_path, const nbv::LoadedArm& in) {
  if (!in.capability_map) return nullptr;
  const capmap::CapabilityHeader& h = in.capability_map->header();
  return {{"file", path},
          {"base_link", h.base_link},
          {"tip_link", h.tip_link},
          {"urdf_hash", h.urdf_hash},
          {"voxel_m", h.voxel_m},
          {"directions", h.directions},
          {"T_world_base", pose_json(in.T_world_base)},
          {"arm", urdf_path.empty() ? Json(nullptr) : Json(urdf_path)}};
}

}  // namespace fvx::report
