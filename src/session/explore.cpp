// The closed loop of the paper's §IV (steps 1–7) as its experiments (§V) ran it: scan,
// register, integrate, frontiers and voids, next best view, move there, until no reachable
// view sees a void.
#include <algorithm>
#include <cmath>
#include <random>

#include "fvx/core/error.hpp"
#include "fvx/core/pose.hpp"
#include "fvx/core/stopwatch.hpp"
#include "fvx/session/session.hpp"

namespace fvx::session {

namespace {


/// The prior a robot would record: the true pose off by Gaussian noise.
Eigen::Isometry3d perturbed(const Eigen::Isometry3d& T_true, double sigma_m, double sigma_deg, std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  const Eigen::Vector3d dt(normal(rng) * sigma_m, normal(rng) * sigma_m, normal(rng) * sigma_m);
  const Eigen::Vector3d rotation_vector =
      Eigen::Vector3d(normal(rng), normal(rng), normal(rng)) * (sigma_deg * M_PI / 180.0);
  Eigen::Isometry3d T = T_true;
  T.translation() += dt;
  if (rotation_vector.norm() > 0)
    T.linear() = Eigen::AngleAxisd(rotation_vector.norm(), rotation_vector.normalized()).toRotationMatrix() * T.linear();
  return T;
}

/// Where the arm puts the sensor for a view: FK of its IK configuration (the executed
/// motion, within the capability map's tolerances of the chosen pose); free-flying: the pose.
Eigen::Isometry3d executed(const nbv::View& view, const std::optional<nbv::Reach>& reach) {
  if (!reach || !reach->arm || view.joints_rad.size() == 0) return view.T_world_sensor;
  const Eigen::Isometry3d T_world_sensor = reach->T_world_base * reach->arm->fk(view.joints_rad);
  return T_world_sensor;
}

}  // namespace

std::optional<std::size_t> first_view_not_taken(const std::vector<nbv::View>& views,
                                                const std::vector<Eigen::Isometry3d>& taken) {
  for (std::size_t i = 0; i < views.size(); ++i)
    if (!nbv::repeats_taken(taken, views[i].T_world_sensor)) return i;
  return std::nullopt;
}

std::pair<Eigen::Isometry3d, Eigen::VectorXd> start_configuration(const std::optional<nbv::Reach>& reach,
                                                                   const Eigen::Isometry3d& T_world_sensor,
                                                                   std::uint64_t seed) {
  if (!reach) return {T_world_sensor, Eigen::VectorXd()};
  const Eigen::Vector3d p = T_world_sensor.translation(), d = T_world_sensor.linear().col(2);
  if (!reach->capmap->reachable(reach->T_world_base, p, d)) {
    throw Error("the start pose " + point_text(p) +
                " is out of the arm's reach: its capability map has no bit there for that direction");
  }
  if (!reach->arm) return {T_world_sensor, Eigen::VectorXd()};
  std::mt19937_64 rng(seed);
  const Eigen::Isometry3d T_base_world = reach->T_world_base.inverse();
  const capmap::IkResult ik = capmap::solve_in_bit(*reach->capmap, *reach->arm, T_base_world * p,
                                                   T_base_world.linear() * d, reach->ik, rng);
  if (!ik.reached) throw Error("the start pose is out of the arm's reach: IK finds no configuration there");
  return {reach->T_world_base * reach->arm->fk(ik.q), ik.q};
}

std::vector<std::string> ExploreConfig::validate() const {
  std::vector<std::string> problems = pipeline.validate();
  if (max_views < 1) problems.push_back("max_views must be >= 1");
  if (!(pose_noise_m >= 0.0 && pose_noise_m <= 1.0)) problems.push_back("pose_noise_m must be in [0, 1] m");
  if (!(pose_noise_deg >= 0.0 && pose_noise_deg <= 45.0)) problems.push_back("pose_noise_deg must be in [0, 45] degrees");
  if (!T_world_sensor_start.matrix().allFinite()) problems.push_back("T_world_sensor_start must be finite");
  return problems;
}

ExploreResult explore(const Sensor& sensor, const std::optional<nbv::Reach>& reach, const ExploreConfig& config,
                      const std::function<void(const ViewRecord&, const pipeline::State&)>& on_view) {
  const auto problems = config.validate();
  throw_if_problems("explore", problems);

  const auto [T_start, start_joints] = start_configuration(reach, config.T_world_sensor_start, config.seed);
  Eigen::Isometry3d T_true = T_start;
  Eigen::VectorXd joints = start_joints;

  pipeline::Pipeline pipeline(config.pipeline, reach);
  const pipeline::State& state = pipeline.state();
  std::mt19937_64 noise_rng(config.seed ^ 0x6A09E667F3BCC909ull);
  std::vector<map::VoxelKey> previous_voids;
  std::size_t previous_prediction = 0;
  std::vector<map::VoxelKey> expected;     // void cells the view about to be taken should reveal
  ExploreResult result;
  for (int view = 0; view < config.max_views; ++view) {
    ViewRecord record;
    record.view = view;
    record.T_world_sensor_true = T_true;
    record.joints_rad = joints;
    record.T_world_sensor_prior = view > 0 && (config.pose_noise_m > 0 || config.pose_noise_deg > 0)
                                      ? perturbed(T_true, config.pose_noise_m, config.pose_noise_deg, noise_rng)
                                      : T_true;
    Stopwatch t0;
    record.points_sensor = sensor(T_true, view);
    // The loop integrates what the session records: PCD stores single precision, so that
    // fvx replay of the session reads back exactly these points.
    for (Eigen::Vector3d& p : record.points_sensor) p = p.cast<float>().cast<double>();
    record.scan_s = t0.seconds();

    scan::Scan scan;
    scan.source = "view " + std::to_string(view);
    scan.points_sensor = record.points_sensor;
    scan.T_world_sensor = record.T_world_sensor_prior;
    pipeline.taken_at(T_true);  // the true pose: a ranked view this near repeats it
    record.step = pipeline.step(std::move(scan), view > 0 ? &expected : nullptr);

    record.previous_prediction = previous_prediction;
    map::StateReader read(state.map);  // the void cells are in key order: each look-up near the last
    for (const map::VoxelKey& k : previous_voids) record.revealed_void_cells += read(k) != map::VoxelState::Unknown;
    previous_voids = record.step.analysis.void_cells;
    const nbv::Result& next = record.step.nbv;
    // The best ranked view not taken yet (the search passed over those): one already taken
    // revealed what it could.
    record.chosen = first_view_not_taken(next.views, state.taken_views);
    on_view(record, state);
    result.views = view + 1;
    if (next.views.empty() && next.pruning.already_taken == 0) {
      result.end = "utility 0: " + next.reason;
      result.utility_exhausted = true;
      return result;
    }
    if (!record.chosen) {
      result.end = "every ranked view repeats one already taken";
      return result;
    }
    const nbv::View& fresh = next.views[*record.chosen];
    T_true = executed(fresh, reach);
    joints = fresh.joints_rad;
    expected = fresh.seen_void_cells;
    previous_prediction = fresh.void_cells_seen;
  }
  result.end = "the view limit (" + std::to_string(config.max_views) + ") was reached";
  return result;
}

}  // namespace fvx::session
