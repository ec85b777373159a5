// Where does the frontier-void loop lose views against a planner that knows the scene? At each
// view of `fvx explore`'s own loop on a suite scene (its defaults, the arm at the scene's base),
// the next view's true gain (the observable void cells still unknown in the map that it reveals,
// by the Kinect's rule on the mesh: reveal.hpp) is set beside:
//   clair      the best gain of any pose of the capability map (a 20 x 15 fan screens them all,
//              the best 64 are cast with the dense fan);
//   chosen     the view the loop takes;
//   ranked     the best of the views the search ranked (all valid poses it scored): is a good
//              view among its candidates, and U ranks it lower?
//   variants   the first view of other searches on the same map (same seed): the exhaustive
//              strategy (U over every pose) and U's other rules;
//   predictors the ranked views ranked again by U's cells weighed otherwise (computed here on
//              the map's grid), and a calibration: of the void cells U's rays cross, the share
//              the view reveals, by the unknown cells before them on the ray.
// A ratio to clair near 1 means the view was as good as any; issue 17, README "Exploration
// over a scene suite".
//
//   bench_regret CAPMAP.fcm URDF FIRST LAST [VIEWS]
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <string>
#include <unordered_map>

#include "fvx/frontier_voids/frontier_voids.hpp"
#include "fvx/viewpoints/fov.hpp"
#include "suite_loop.hpp"

namespace {

using namespace fvx;
using bench::CellSet;

struct Variant {
  const char* label;
  std::function<void(nbv::Config&)> apply;
  bool hull_in_bounds = false;  ///< the voids' hull from the occupied cells in S (--void-hull search-space)
};

const std::vector<Variant>& variants() {
  static const std::vector<Variant> all = {
      {"exhaustive", [](nbv::Config& c) { c.strategy = nbv::Strategy::Exhaustive; }},
      {"near-void", [](nbv::Config& c) { c.near_unknown = viewpoints::NearUnknown::Void; }},
      {"hull-in-S", [](nbv::Config&) {}, true},
  };
  return all;
}

/// Sums over the states of one column: gain, and the clairvoyant's gain where it had any.
struct Column {
  double gain = 0, ratio_sum = 0;
  int states = 0;
};

class Scene : public bench::SuiteLoop {
 public:
  Scene(int n, const std::string& capmap, const std::string& urdf) : SuiteLoop(n, capmap, urdf, "bench_regret") {
    const map::OccupancyMap keys(0.025);
    for (const Eigen::Vector3d& c : world_->score().observable_centres_m())
      if (const auto key = keys.key_of(c)) observable_air_.push_back(*key);
    std::sort(observable_air_.begin(), observable_air_.end());
    for (const Eigen::Vector3d& c : centres_)
      if (const auto key = keys.key_of(c)) observable_void_.push_back(*key);
    std::sort(observable_void_.begin(), observable_void_.end());
  }

  /// Runs the loop for `views` views; one table row per view after the first's search.
  void run(int n, int views, std::vector<Column>& columns) {
    explore(views, [&](const session::ViewRecord& v, const pipeline::State& state, const session::ExploreConfig& config) {
      if (!v.chosen) return;
      std::vector<double> gains = {clairvoyant(state.map)};
      const std::vector<nbv::View>& ranked = v.step.nbv.views;
      const CellSet chosen = reveal_->sets({ranked[*v.chosen].T_world_sensor}, dense_rays_)[0];
      gains.push_back(double(unknown_of(state.map, chosen)));
      std::vector<Eigen::Isometry3d> all;
      for (const nbv::View& r : ranked) all.push_back(r.T_world_sensor);
      gains.push_back(best_gain(state.map, all));
      for (const Variant& variant : variants()) {
        nbv::Config c = config.pipeline.nbv;
        c.seed = config.pipeline.nbv.seed + std::uint64_t(v.view);
        variant.apply(c);
        const frontier_voids::Analysis own =
            variant.hull_in_bounds ? frontier_voids::analyse_map(state.map, S_, config.pipeline.clusters, 1, true, true)
                                   : frontier_voids::Analysis{};
        const nbv::Result r = nbv::select(state.map, variant.hull_in_bounds ? own : v.step.analysis, arm_.reach, c,
                                          state.hidden_void_cells);
        gains.push_back(r.views.empty() ? 0.0 : gain(state.map, r.views.front().T_world_sensor));
      }
      for (const double g : rescored(state, v.step.analysis, all)) gains.push_back(g);
      print_row(n, v.view, gains, columns, why(state.map, ranked[*v.chosen], chosen));
    });
  }

 private:
  /// What the chosen view's U cells are in the ground truth: observable void (and how many of
  /// those its true view, `revealed`, reveals), solid, or empty but not observable void.
  std::string why(const map::OccupancyMap& map, const nbv::View& view, const CellSet& revealed) const {
    const std::vector<map::VoxelKey>& observable = observable_void_;
    std::vector<map::VoxelKey> revealed_keys;
    for (const std::uint32_t c : revealed) revealed_keys.push_back(*map.key_of(centres_[c]));
    std::sort(revealed_keys.begin(), revealed_keys.end());
    std::size_t obs = 0, obs_revealed = 0, solid = 0, outside = 0;
    Eigen::AlignedBox3d other_box;
    const sim::GroundTruth& gt = world_->ground_truth();
    for (const map::VoxelKey& k : view.seen_void_cells) {
      if (std::binary_search(observable.begin(), observable.end(), k)) {
        ++obs;
        obs_revealed += std::binary_search(revealed_keys.begin(), revealed_keys.end(), k);
      } else if (const Eigen::Vector3i cell = gt.cell_of(map.center_of(k)); gt.contains(cell) && gt.solid(cell)) {
        ++solid;
      } else {
        outside += std::binary_search(observable_air_.begin(), observable_air_.end(), k);
        other_box.extend(map.center_of(k));
      }
    }
    const auto depths = reveal_->depths(view.T_world_sensor, viewpoints::ray_fan(camera_.intrinsics, 80, 60));
    char line[300];
    std::snprintf(line, sizeof line,
                  "U %zu: obs %zu (revealed %zu), solid %zu, other %zu (observable, outside the hull %zu); rays measure / too near / none "
                  "%zu / %zu / %zu; eye %s; other in %s-%s",
                  view.void_cells_seen, obs, obs_revealed, solid, view.seen_void_cells.size() - obs - solid, outside,
                  depths[0], depths[1], depths[2], point_text(view.T_world_sensor.translation()).c_str(),
                  point_text(other_box.min()).c_str(), point_text(other_box.max()).c_str());
    return line;
  }

  /// The ranked views chosen again by other predictions of what a view reveals, computed
  /// here on the map: the true gain of each predictor's first view.
  std::vector<double> rescored(const pipeline::State& state, const frontier_voids::Analysis& a,
                               const std::vector<Eigen::Isometry3d>& candidates) {
    const map::OccupancyMap& map = state.map;
    Eigen::AlignedBox3d box = S_;
    for (const Eigen::Isometry3d& T : candidates) box.extend(T.translation());
    const map::DenseGrid grid(map, box);
    std::vector<char> target(grid.cell_count(), 0), revealed(grid.cell_count(), 0);
    for (const auto& v : a.void_clusters)
      if (!a.frontier_voids[std::size_t(v.id)].enclosed())
        for (const map::VoxelKey& k : v.cells)
          if (grid.contains(k)) target[grid.index(k)] = 1;
    for (const map::VoxelKey& k : state.hidden_void_cells)
      if (grid.contains(k)) target[grid.index(k)] = 0;
    const std::vector<Eigen::Vector3d> rays = viewpoints::ray_fan(camera_.intrinsics, 80, 60);
    const std::vector<CellSet> truth = reveal_->sets(candidates, dense_rays_);
    std::vector<std::vector<double>> scores(candidates.size());
    for (std::size_t p = 0; p < candidates.size(); ++p) {
      std::vector<std::size_t> marked;
      for (const std::uint32_t c : truth[p])
        if (const auto key = map.key_of(centres_[c]); key && grid.contains(*key)) {
          revealed[grid.index(*key)] = 1;
          marked.push_back(grid.index(*key));
        }
      scores[p] = predict(grid, target, revealed, candidates[p], rays);
      for (const std::size_t i : marked) revealed[i] = 0;
    }
    std::vector<double> gains;
    for (std::size_t k = 0; k < scores.front().size(); ++k) {
      std::size_t best = 0;
      for (std::size_t p = 1; p < candidates.size(); ++p)
        if (scores[p][k] > scores[best][k]) best = p;
      gains.push_back(double(unknown_of(map, truth[best])));
    }
    return gains;
  }

  /// The predictors of one pose (kPredictors), and the calibration counts: per count of
  /// unknown cells a ray crossed before a target cell, and whether an unknown cell lay
  /// nearer than the minimum depth, how many target cells it crossed and how many of those
  /// the view revealed.
  std::vector<double> predict(const map::DenseGrid& grid, const std::vector<char>& target,
                              const std::vector<char>& revealed, const Eigen::Isometry3d& T,
                              const std::vector<Eigen::Vector3d>& rays) {
    std::vector<std::unordered_map<std::size_t, double>> best(kPredictors.size());
    const Eigen::Vector3d eye = T.translation();
    for (const Eigen::Vector3d& ray : rays) {
      const Eigen::Vector3d d = (T.linear() * ray).normalized();
      const double min_range = camera_.depth_min_m * ray.norm();
      int j = 0;
      double first_unknown = INFINITY;
      grid.walk(eye, d, camera_.depth_max_m * ray.norm(), [&](std::size_t i, map::VoxelState s) {
        if (s == map::VoxelState::Occupied) return false;
        if (s != map::VoxelState::Unknown) return true;
        const double t = (grid.center_of(grid.key(i)) - eye).dot(d);
        if (first_unknown == INFINITY) first_unknown = t;
        if (target[i]) {
          const bool near = first_unknown < min_range;
          auto& bin = calibration_[std::size_t(near)][std::size_t(std::min(j, 63))];
          ++bin[0];
          bin[1] += revealed[i];
          for (std::size_t k = 0; k < kPredictors.size(); ++k) {
            const double w = kPredictors[k].weight(j, near);
            double& b = best[k][i];
            b = std::max(b, w);
          }
        }
        ++j;
        return true;
      });
    }
    std::vector<double> out;
    for (const auto& m : best) {
      double sum = 0;
      for (const auto& [i, w] : m) sum += w;
      out.push_back(sum);
    }
    return out;
  }

 public:
  struct Predictor {
    const char* label;
    std::function<double(int unknown_before, bool near)> weight;
  };
  static inline const std::vector<Predictor> kPredictors = {
      {"U", [](int, bool) { return 1.0; }},
      {"q0.9", [](int j, bool) { return std::pow(0.9, j); }},
      {"q0.8", [](int j, bool) { return std::pow(0.8, j); }},
      {"q0.6", [](int j, bool) { return std::pow(0.6, j); }},
      {"near0", [](int, bool near) { return near ? 0.0 : 1.0; }},
      {"near0.3", [](int, bool near) { return near ? 0.3 : 1.0; }},
      {"near0+q0.8", [](int j, bool near) { return near ? 0.0 : std::pow(0.8, j); }},
  };
  static inline std::array<std::array<std::array<std::size_t, 2>, 64>, 2> calibration_{};

 private:
  static void print_row(int n, int view, const std::vector<double>& gains, std::vector<Column>& columns,
                        const std::string& why) {
    std::printf("| suite/%d | %d | %.0f", n, view + 1, gains[0]);
    for (std::size_t i = 1; i < gains.size(); ++i) std::printf(" | %.0f (%.2f)", gains[i], gains[i] / std::max(1.0, gains[0]));
    std::printf(" | %s |\n", why.c_str());
    std::fflush(stdout);
    for (std::size_t i = 0; i < gains.size(); ++i) {
      columns[i].gain += gains[i];
      if (gains[0] > 0) columns[i].ratio_sum += gains[i] / gains[0], ++columns[i].states;
    }
  }

  std::vector<map::VoxelKey> observable_air_;  ///< every observable cell, hull or not, key order
  std::vector<map::VoxelKey> observable_void_;  ///< the observable void cells (centres_), key order
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5 && argc != 6) {
    std::fprintf(stderr, "usage: bench_regret CAPMAP.fcm URDF FIRST LAST [VIEWS]\n");
    return 2;
  }
  const int first = std::atoi(argv[3]), last = std::atoi(argv[4]), views = argc == 6 ? std::atoi(argv[5]) : 8;
  if (first < 1 || last < first || views < 2) {
    std::fprintf(stderr, "bench_regret: FIRST >= 1, LAST >= FIRST, VIEWS >= 2\n");
    return 2;
  }
  std::printf("| scene | after view | clair | chosen | best ranked");
  for (const Variant& v : variants()) std::printf(" | %s", v.label);
  for (const auto& p : Scene::kPredictors) std::printf(" | %s", p.label);
  std::printf(" | the chosen view's U cells |\n|---|---|---|---|---");
  for (std::size_t i = 0; i <= variants().size() + Scene::kPredictors.size(); ++i) std::printf("|---");
  std::printf("|\n");
  std::vector<Column> columns(3 + variants().size() + Scene::kPredictors.size());
  try {
    for (int n = first; n <= last; ++n) {
      Scene scene(n, argv[1], argv[2]);
      if (!scene.empty()) scene.run(n, views, columns);
    }
  } catch (const std::exception& e) {  // a missing file, a scene the suite does not hold
    std::fprintf(stderr, "bench_regret: %s\n", e.what());
    return 1;
  }
  std::printf("\n| column | gain summed over the states (of clair's) | mean ratio to clair |\n|---|---|---|\n");
  const char* fixed[] = {"clair", "chosen", "best ranked"};
  for (std::size_t i = 0; i < columns.size(); ++i)
    std::printf("| %s | %.0f (%.3f) | %.3f |\n",
                i < 3 ? fixed[i] : i < 3 + variants().size() ? variants()[i - 3].label
                                                              : Scene::kPredictors[i - 3 - variants().size()].label,
                columns[i].gain,
                columns[i].gain / std::max(1.0, columns[0].gain), columns[i].ratio_sum / std::max(1, columns[i].states));
  std::printf("\n| unknown cells before | target cells crossed, far | revealed | crossed, an unknown cell within "
              "the minimum depth | revealed |\n|---|---|---|---|---|\n");
  for (const std::size_t j : {0, 1, 2, 3, 5, 8, 12, 16, 24, 32, 48, 63}) {
    const auto& f = Scene::calibration_[0][j];
    const auto& nr = Scene::calibration_[1][j];
    if (f[0] + nr[0] == 0) continue;
    std::printf("| %zu | %zu | %.3f | %zu | %.3f |\n", j, f[0], double(f[1]) / double(std::max<std::size_t>(1, f[0])),
                nr[0], double(nr[1]) / double(std::max<std::size_t>(1, nr[0])));
  }
  return 0;
}
