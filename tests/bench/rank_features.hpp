#pragma once
// bench_rank_features: a candidate view's features on the map, and how well each ranks the
// candidates by their true gain (a feature alone, or a ridge regression on all of them
// trained leave-one-scene-out, so that no scene is judged by a rule fitted to it).
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <vector>

#include "fvx/frontier_voids/frontier_voids.hpp"
#include "fvx/io/intrinsics.hpp"
#include "fvx/map/dense_grid.hpp"
#include "fvx/nbv/nbv.hpp"
#include "fvx/pipeline/pipeline.hpp"
#include "fvx/viewpoints/fov.hpp"

namespace fvx::bench {

/// A view's features: U and Algorithm 1's utility at the viewpoint (the search's); the void
/// cells its rays cross (each counted once, by its best ray) with no unknown cell before them,
/// with no void cell before them (the void's face the ray meets), with fewer than three, on a
/// ray that ends on a known occupied cell, with no unknown cell nearer than the minimum depth,
/// and weighed 0.9^(unknown cells before); their mean depth; the voids they lie in and the
/// sum of each void's share seen; the rays that end on a known surface, cross a void cell,
/// end on nothing the map knows, or meet an unknown cell within the minimum depth; unknown
/// cells outside the voids crossed (per ray); the eye's height above S and distance to its
/// centre; the optical axis's z.
inline constexpr std::array<const char*, 19> kFeatureNames = {
    "U", "utility_m3", "U_first", "U_void_surface", "U_void_depth3", "U_surface_rays", "U_far", "U_q0.9",
    "mean_depth_m", "voids_seen", "void_share_sum", "rays_on_surface", "rays_into_void", "rays_to_nothing",
    "rays_near_unknown", "unknown_other", "eye_above_S_m", "eye_to_S_centre_m", "axis_z"};
/// Features that count cells (U_first .. U_q0.9): the ridge also sees them as shares of U.
inline constexpr std::size_t kShareFirst = 2, kShareLast = 7;
/// Features that count (U .. unknown_other): the ridge sees them over the state's largest.
inline constexpr std::size_t kCountLast = 15;

struct Candidate {
  double gain = 0;
  std::vector<double> features;  ///< kFeatureNames
};

struct State {
  int scene = 0, view = 0;
  double clair = 0;       ///< the capability map's best pose's gain
  std::size_t chosen = 0;  ///< the candidate the loop took
  std::vector<Candidate> candidates;
};

/// Casts a candidate's 80 x 60 fan through the map and counts the void cells it crosses by
/// how they lie on the rays (kFeatureNames).
class FeatureCaster {
 public:
  FeatureCaster(const pipeline::State& state, const frontier_voids::Analysis& a, const std::vector<Eigen::Isometry3d>& poses,
                const Eigen::AlignedBox3d& S, const io::DepthCamera& camera)
      : S_(S), camera_(camera), grid_(state.map, box_of(S, poses)), label_(grid_.cell_count(), -1) {
    for (const auto& v : a.void_clusters)
      if (!a.frontier_voids[std::size_t(v.id)].enclosed()) {
        for (const map::VoxelKey& k : v.cells)
          if (grid_.contains(k)) label_[grid_.index(k)] = v.id;
        void_size_.resize(std::max(void_size_.size(), std::size_t(v.id) + 1), 0.0);
        void_size_[std::size_t(v.id)] = double(v.cells.size());
      }
    for (const map::VoxelKey& k : state.hidden_void_cells)
      if (grid_.contains(k)) label_[grid_.index(k)] = -1;
    rays_ = viewpoints::ray_fan(camera.intrinsics, 80, 60);
  }

  std::vector<double> features(const Eigen::Isometry3d& T, const nbv::View& view) const {
    std::vector<Cell> cells;  // sorted by grid index once all rays are cast
    std::array<double, 5> rays{};  // on surface, into void, to nothing, near unknown, unknown other
    for (const Eigen::Vector3d& ray : rays_) cast(T, ray, cells, rays);
    std::sort(cells.begin(), cells.end(), [](const Cell& l, const Cell& r) { return l.index < r.index; });
    std::vector<Cell> merged;
    for (const Cell& c : cells) {
      if (merged.empty() || merged.back().index != c.index) { merged.push_back(c); continue; }
      Cell& m = merged.back();
      m.unknown_before = std::min(m.unknown_before, c.unknown_before);
      m.void_before = std::min(m.void_before, c.void_before);
      m.on_surface_ray |= c.on_surface_ray;
      m.far |= c.far;
      m.depth_m = std::min(m.depth_m, c.depth_m);
    }
    std::vector<double> x(kFeatureNames.size(), 0.0);
    x[0] = double(view.void_cells_seen);
    x[1] = view.accumulated_utility_m3;
    std::vector<double> per_void(void_size_.size(), 0.0);
    for (const Cell& c : merged) {
      x[2] += c.unknown_before == 0;
      x[3] += c.void_before == 0;
      x[4] += c.void_before < 3;
      x[5] += c.on_surface_ray;
      x[6] += c.far;
      x[7] += std::pow(0.9, c.unknown_before);
      x[8] += c.depth_m / double(merged.size());
      per_void[std::size_t(c.void_id)] += 1;
    }
    for (std::size_t v = 0; v < per_void.size(); ++v)
      if (per_void[v] > 0) x[9] += 1, x[10] += per_void[v] / void_size_[v];
    std::copy(rays.begin(), rays.end(), x.begin() + 11);
    const Eigen::Vector3d eye = T.translation();
    x[16] = eye.z() - S_.min().z();
    x[17] = (eye - S_.center()).norm();
    x[18] = (T.linear() * Eigen::Vector3d::UnitZ()).z();
    return x;
  }

 private:
  struct Cell {
    std::size_t index;
    int void_id, unknown_before, void_before;
    bool on_surface_ray, far;
    double depth_m;
  };

  static Eigen::AlignedBox3d box_of(const Eigen::AlignedBox3d& S, const std::vector<Eigen::Isometry3d>& poses) {
    Eigen::AlignedBox3d box = S;
    for (const Eigen::Isometry3d& T : poses) box.extend(T.translation());
    return Eigen::AlignedBox3d(box.min() - Eigen::Vector3d::Constant(0.3), box.max() + Eigen::Vector3d::Constant(0.3));
  }

  void cast(const Eigen::Isometry3d& T, const Eigen::Vector3d& ray, std::vector<Cell>& cells, std::array<double, 5>& rays) const {
    const Eigen::Vector3d eye = T.translation(), d = (T.linear() * ray).normalized();
    const double min_m = camera_.depth_min_m * ray.norm();
    int unknown = 0, in_void = 0;
    double first_unknown_m = INFINITY;
    const std::size_t from = cells.size();
    const map::RayOutcome end = grid_.walk(eye, d, camera_.depth_max_m * ray.norm(), [&](std::size_t i, map::VoxelState s) {
      if (s == map::VoxelState::Occupied) return false;
      if (s != map::VoxelState::Unknown) return true;
      const double t = (grid_.center_of(grid_.key(i)) - eye).dot(d);
      first_unknown_m = std::min(first_unknown_m, t);
      if (label_[i] >= 0)
        cells.push_back({i, label_[i], unknown, in_void++, false, first_unknown_m >= min_m, t});
      else
        ++rays[4];
      ++unknown;
      return true;
    });
    const bool surface = end == map::RayOutcome::Hit;
    for (std::size_t c = from; c < cells.size(); ++c) cells[c].on_surface_ray = surface;
    rays[0] += surface;
    rays[1] += cells.size() > from;
    rays[2] += !surface;  // out to the depth limit or out of the grid: no surface the map knows
    rays[3] += first_unknown_m < min_m;
  }

  Eigen::AlignedBox3d S_;
  io::DepthCamera camera_;
  map::DenseGrid grid_;
  std::vector<int> label_;
  std::vector<double> void_size_;
  std::vector<Eigen::Vector3d> rays_;
};

/// Each candidate's inputs to the ridge: the features, the counts over the state's largest,
/// the cell counts as shares of U, and 1 (the intercept).
inline std::vector<Eigen::VectorXd> ridge_inputs(const State& s) {
  const std::size_t n = kFeatureNames.size(), shares = kShareLast - kShareFirst + 1;
  std::vector<double> largest(n, 1e-9);
  for (const Candidate& c : s.candidates)
    for (std::size_t k = 0; k <= kCountLast; ++k) largest[k] = std::max(largest[k], c.features[k]);
  std::vector<Eigen::VectorXd> out;
  for (const Candidate& c : s.candidates) {
    const std::vector<double>& f = c.features;
    Eigen::VectorXd x(n + shares + 1);
    for (std::size_t k = 0; k < n; ++k) x[Eigen::Index(k)] = k <= kCountLast ? f[k] / largest[k] : f[k];
    for (std::size_t k = 0; k < shares; ++k) x[Eigen::Index(n + k)] = f[kShareFirst + k] / std::max(1.0, f[0]);
    x[Eigen::Index(n + shares)] = 1.0;
    out.push_back(std::move(x));
  }
  return out;
}

/// A ridge regression (alpha on standardised inputs) of each candidate's gain over its
/// state's best.
struct Ridge {
  Eigen::VectorXd w, mean, scale;
  double predict(const Eigen::VectorXd& x) const { return w.dot((x - mean).cwiseQuotient(scale)); }
};

/// The ridge fitted on the states of every scene but `scene` (0: on all states); none when
/// no state is left to fit on.
inline std::optional<Ridge> fit_ridge(const std::vector<State>& states, const std::vector<std::vector<Eigen::VectorXd>>& inputs,
                                      int scene, double alpha) {
  std::vector<const Eigen::VectorXd*> xs;
  std::vector<double> ys;
  for (std::size_t i = 0; i < states.size(); ++i) {
    if (states[i].scene == scene) continue;
    double best = 1.0;
    for (const Candidate& c : states[i].candidates) best = std::max(best, c.gain);
    for (std::size_t c = 0; c < states[i].candidates.size(); ++c)
      xs.push_back(&inputs[i][c]), ys.push_back(states[i].candidates[c].gain / best);
  }
  if (xs.empty()) return std::nullopt;
  const Eigen::Index p = xs.front()->size();
  Ridge r{Eigen::VectorXd(), Eigen::VectorXd::Zero(p), Eigen::VectorXd::Ones(p)};
  for (const auto* x : xs) r.mean += *x / double(xs.size());
  Eigen::VectorXd var = Eigen::VectorXd::Zero(p);
  for (const auto* x : xs) var += (*x - r.mean).cwiseAbs2() / double(xs.size());
  for (Eigen::Index k = 0; k + 1 < p; ++k) r.scale[k] = var[k] > 1e-12 ? std::sqrt(var[k]) : 1.0;
  r.mean[p - 1] = 0.0;  // the intercept stays 1
  Eigen::MatrixXd A = alpha * Eigen::MatrixXd::Identity(p, p);
  A(p - 1, p - 1) = 0.0;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(p);
  for (std::size_t i = 0; i < xs.size(); ++i) {
    const Eigen::VectorXd z = (*xs[i] - r.mean).cwiseQuotient(r.scale);
    A += z * z.transpose();
    b += z * ys[i];
  }
  r.w = A.ldlt().solve(b);
  return r;
}

/// What a rule's picks reveal: summed over the states as a share of the best pose's, and the
/// mean ratio over the states where the best pose reveals anything.
inline void print_rule(const char* label, const std::vector<State>& states, const std::vector<std::size_t>& pick) {
  double gain = 0, clair = 0, ratio = 0;
  int n = 0;
  for (std::size_t i = 0; i < states.size(); ++i) {
    gain += states[i].candidates[pick[i]].gain;
    clair += states[i].clair;
    if (states[i].clair > 0) ratio += states[i].candidates[pick[i]].gain / states[i].clair, ++n;
  }
  std::printf("| %s | %.3f | %.3f |\n", label, gain / std::max(1.0, clair), ratio / std::max(1, n));
}

template <typename Score>
std::vector<std::size_t> argmax_per_state(const std::vector<State>& states, Score score) {
  std::vector<std::size_t> pick;
  for (std::size_t i = 0; i < states.size(); ++i) {
    std::size_t best = 0;
    for (std::size_t c = 1; c < states[i].candidates.size(); ++c)
      if (score(i, c) > score(i, best)) best = c;
    pick.push_back(best);
  }
  return pick;
}

/// Spearman's rank correlation of two equally long lists (ties by order).
inline double spearman(const std::vector<double>& a, const std::vector<double>& b) {
  auto ranks = [](const std::vector<double>& v) {
    std::vector<std::size_t> order(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t l, std::size_t r) { return v[l] < v[r]; });
    std::vector<double> r(v.size());
    for (std::size_t p = 0; p < order.size(); ++p) r[order[p]] = double(p);
    return r;
  };
  const std::vector<double> ra = ranks(a), rb = ranks(b);
  const double m = double(a.size() - 1) / 2.0;
  double num = 0, da = 0, db = 0;
  for (std::size_t i = 0; i < a.size(); ++i) num += (ra[i] - m) * (rb[i] - m), da += (ra[i] - m) * (ra[i] - m), db += (rb[i] - m) * (rb[i] - m);
  return da > 0 && db > 0 ? num / std::sqrt(da * db) : 0.0;
}

inline double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[std::size_t(q * double(v.size() - 1) + 0.5)];
}

/// How U ranks within a state: its rank correlation with the gain, where the best candidate's
/// U stands, and what the best of U's first K reveals.
inline void print_u_ranking(const std::vector<State>& states) {
  std::vector<double> rho, u_of_best;
  std::array<double, 4> top_k{};
  const std::array<std::size_t, 4> ks = {1, 3, 5, 10};
  for (const State& s : states) {
    std::vector<double> u, g;
    for (const Candidate& c : s.candidates) u.push_back(c.features[0]), g.push_back(c.gain);
    const double best_gain = *std::max_element(g.begin(), g.end());
    if (best_gain <= 0 || s.candidates.size() < 2) continue;
    rho.push_back(spearman(u, g));
    u_of_best.push_back(u[std::size_t(std::max_element(g.begin(), g.end()) - g.begin())] / std::max(1.0, *std::max_element(u.begin(), u.end())));
    std::vector<std::size_t> order(u.size());
    for (std::size_t i = 0; i < u.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t l, std::size_t r) { return u[l] > u[r]; });
    for (std::size_t k = 0; k < ks.size(); ++k) {
      double best = 0;
      for (std::size_t i = 0; i < std::min(ks[k], order.size()); ++i) best = std::max(best, g[order[i]]);
      top_k[k] += best / best_gain / double(states.size());
    }
  }
  std::printf("\nU against the true gain within a state (%zu states where a candidate reveals anything): Spearman "
              "rho median %.2f (quartiles %.2f, %.2f); the best candidate's U over the largest U: median %.2f "
              "(quartiles %.2f, %.2f); the best of U's first 1 / 3 / 5 / 10 reveals %.2f / %.2f / %.2f / %.2f of the "
              "best candidate's gain (mean over all states).\n",
              rho.size(), quantile(rho, 0.5), quantile(rho, 0.25), quantile(rho, 0.75), quantile(u_of_best, 0.5),
              quantile(u_of_best, 0.25), quantile(u_of_best, 0.75), top_k[0], top_k[1], top_k[2], top_k[3]);
}

inline void print_evaluation(const std::vector<State>& states) {
  if (states.empty()) return;
  std::size_t candidates = 0;
  for (const State& s : states) candidates += s.candidates.size();
  std::printf("%zu states, %zu candidates\n\n| pick | true gain summed, share of the best pose's | mean ratio to the best pose |\n|---|---|---|\n",
              states.size(), candidates);
  std::vector<std::size_t> chosen;
  for (const State& s : states) chosen.push_back(s.chosen);
  print_rule("the view the loop takes", states, chosen);
  print_rule("the best candidate (knowing the gains)", states, argmax_per_state(states, [&](std::size_t i, std::size_t c) { return states[i].candidates[c].gain; }));
  for (std::size_t k = 0; k < kFeatureNames.size(); ++k)
    print_rule(kFeatureNames[k], states, argmax_per_state(states, [&](std::size_t i, std::size_t c) { return states[i].candidates[c].features[k]; }));
  std::vector<std::vector<Eigen::VectorXd>> inputs;
  for (const State& s : states) inputs.push_back(ridge_inputs(s));
  const auto pick_by = [&](const std::vector<std::optional<Ridge>>& model_of_state) {
    return argmax_per_state(states, [&](std::size_t i, std::size_t c) { return model_of_state[i]->predict(inputs[i][c]); });
  };
  std::map<int, std::optional<Ridge>> held_out;  // per scene, the ridge fitted without it
  for (const State& s : states)
    if (!held_out.count(s.scene)) held_out[s.scene] = fit_ridge(states, inputs, s.scene, 1.0);
  std::vector<std::optional<Ridge>> models;
  for (const State& s : states) models.push_back(held_out[s.scene]);
  if (held_out.size() > 1)
    print_rule("ridge on all features, leave one scene out", states, pick_by(models));
  else
    std::printf("| ridge on all features, leave one scene out | (needs two scenes) | |\n");
  models.assign(states.size(), fit_ridge(states, inputs, 0, 1.0));
  print_rule("ridge on all features, fitted to every scene (in-sample)", states, pick_by(models));
  print_u_ranking(states);
}

}  // namespace fvx::bench
