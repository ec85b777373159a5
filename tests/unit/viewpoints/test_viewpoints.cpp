// The field of view against an exact oracle (every cell a ray's segment enters, by slab
// tests over the whole grid), the look-at rotation, and orientation sampling.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <random>
#include <set>

#include "fvx/core/error.hpp"
#include "fvx/viewpoints/fov.hpp"
#include "fvx/viewpoints/orientations.hpp"

namespace fvx::viewpoints {
namespace {

TEST(RayFan, SpansTheImageThroughDecimatedPixelCentres) {
  const io::Intrinsics K;  // Kinect v1
  const auto rays = ray_fan(K, 80, 60);
  ASSERT_EQ(rays.size(), 4800u);
  for (const auto& r : rays) EXPECT_EQ(r.z(), 1.0);
  // Band centres of 8×8 pixels: the first at pixel 3.5, the last at 635.5 (u), 475.5 (v).
  EXPECT_NEAR(rays.front().x(), (3.5 - 319.5) / 525.0, 1e-12);
  EXPECT_NEAR(rays.front().y(), (3.5 - 239.5) / 525.0, 1e-12);
  EXPECT_NEAR(rays.back().x(), (635.5 - 319.5) / 525.0, 1e-12);
  EXPECT_NEAR(rays.back().y(), (475.5 - 239.5) / 525.0, 1e-12);
  const auto one = ray_fan(K, 1, 1);  // the image centre
  EXPECT_NEAR(one[0].x(), 0.0, 1e-12);
  EXPECT_NEAR(one[0].y(), 0.0, 1e-12);
}

TEST(LookAlong, PointsTheOpticalAxisAndKeepsTheImageUpright) {
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d d = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    const double roll = 3.0 * g(rng);
    const Eigen::Matrix3d R = look_along(d * 2.5, roll);
    ASSERT_NEAR((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12);
    ASSERT_NEAR(R.determinant(), 1.0, 1e-12);
    ASSERT_NEAR((R.col(2) - d).norm(), 0.0, 1e-12);
    // Roll 0: image up (−y) points up as far as the axis allows, image x is level.
    const Eigen::Matrix3d R0 = look_along(d, 0.0);
    EXPECT_NEAR(R0.col(0).z(), 0.0, 1e-12);
    EXPECT_GE(-R0.col(1).z(), 0.0);
    // Roll turns about the axis by the given angle.
    EXPECT_NEAR(std::acos(std::clamp(R0.col(0).dot(R.col(0)), -1.0, 1.0)),
                std::abs(std::remainder(roll, 2 * M_PI)), 1e-9);
  }
  const Eigen::Matrix3d down = look_along(-Eigen::Vector3d::UnitZ(), 0.0);  // degenerate: still a rotation
  EXPECT_NEAR((down.col(2) + Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(down.determinant(), 1.0, 1e-12);
}

TEST(SampleOrientations, AimAtTheTargetsWithinTheJitter) {
  std::mt19937_64 rng(9);
  const Eigen::Vector3d p(0.1, 0.2, 0.3);
  const std::vector<Eigen::Vector3d> targets = {{1, 0, 0}, {0, 2, 0}, {0.1, 0.2, 0.3}, {0, 0, -1}};
  const double jitter = 10.0 * M_PI / 180.0;
  const auto R = sample_orientations(p, targets, 30, jitter, rng);
  ASSERT_EQ(R.size(), 30u);
  std::vector<Eigen::Vector3d> dirs;  // the target at the position itself is skipped
  for (const auto& t : targets)
    if ((t - p).norm() > 1e-9) dirs.push_back((t - p).normalized());
  ASSERT_EQ(dirs.size(), 3u);
  for (std::size_t k = 0; k < R.size(); ++k) {
    const double angle = std::acos(std::clamp(R[k].col(2).dot(dirs[k % 3]), -1.0, 1.0));
    if (k < 3) {
      EXPECT_NEAR(angle, 0.0, 1e-9) << k;  // the first sample of each target is exact
    }
    EXPECT_LE(angle, jitter + 1e-9) << k;
  }
  std::mt19937_64 again(9);
  const auto R2 = sample_orientations(p, targets, 30, jitter, again);
  for (std::size_t k = 0; k < R.size(); ++k) EXPECT_EQ(R[k], R2[k]);
  std::mt19937_64 r3(1);
  EXPECT_TRUE(sample_orientations(p, {p}, 5, jitter, r3).empty());
}

// A random 14×12×10 grid of free, unknown and occupied cells, with random targets.
struct RandomGrid {
  map::OccupancyMap map{0.1};
  std::unique_ptr<map::DenseGrid> grid;
  core::LargeVector<std::uint8_t> target;
  /// Targets only in `target_box` (all cells when it is empty); the grid over `grid_box`
  /// (cells beyond the 14 × 12 × 10 known ones are unknown).
  explicit RandomGrid(std::uint32_t seed, const Eigen::AlignedBox3d& target_box = Eigen::AlignedBox3d(),
                      const Eigen::AlignedBox3d& grid_box = Eigen::AlignedBox3d(Eigen::Vector3d(0.0, 0.0, 0.0),
                                                                                Eigen::Vector3d(1.4, 1.2, 1.0))) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    for (int z = 0; z < 10; ++z)
      for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 14; ++x) {
          const double r = u(rng);
          const map::VoxelKey k{std::uint16_t(32768 + x), std::uint16_t(32768 + y), std::uint16_t(32768 + z)};
          if (r < 0.04) map.set_state(k, map::VoxelState::Occupied);
          else if (r < 0.6) map.set_state(k, map::VoxelState::Free);
        }
    grid = std::make_unique<map::DenseGrid>(map, grid_box);
    target.resize(grid->cell_count());
    for (std::size_t i = 0; i < target.size(); ++i)
      target[i] = u(rng) < 0.3 && (target_box.isEmpty() || target_box.contains(grid->center_of(grid->key(i))));
  }
};

// The oracle: the cells whose boxes the segment [0, range] enters, in order of entry; walk
// them until an occupied one. An occupied cell whose centre's depth along `axis` is below
// depth_min gives no measurement: nothing on that ray counts.
std::set<std::size_t> oracle_seen(const RandomGrid& g, const Eigen::Vector3d& o, const Eigen::Vector3d& dir,
                                  double range, double depth_min = 0.0,
                                  const Eigen::Vector3d& axis = Eigen::Vector3d::UnitZ(), int unknown_depth = 0,
                                  NearUnknown near_unknown = NearUnknown::Ignore,
                                  const std::set<std::size_t>& blocking = {}) {
  const Eigen::Vector3d d = dir.normalized();
  std::vector<std::pair<double, std::size_t>> entered;
  for (std::size_t i = 0; i < g.grid->cell_count(); ++i) {
    const Eigen::Vector3d c = g.grid->center_of(g.grid->key(i));
    double t0 = 0.0, t1 = range;
    for (int a = 0; a < 3; ++a) {
      const double lo = c[a] - 0.05, hi = c[a] + 0.05;
      if (std::abs(d[a]) < 1e-15) {
        if (o[a] < lo || o[a] >= hi) t0 = INFINITY;
        continue;
      }
      double ta = (lo - o[a]) / d[a], tb = (hi - o[a]) / d[a];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    if (t0 < t1) entered.push_back({t0, i});
  }
  std::sort(entered.begin(), entered.end());
  std::set<std::size_t> seen;
  int unknown = 0;  // with unknown_depth > 0, the cell after that many unknown ones ends the ray as a surface does
  for (const auto& [t, i] : entered) {
    // An unknown cell nearer than depth_min (a void one, or any) may hide the ray's end.
    const bool may_block = near_unknown == NearUnknown::Any || (near_unknown == NearUnknown::Void && g.target[i]) ||
                           (near_unknown == NearUnknown::Hidden && blocking.count(i));
    if (may_block && g.grid->state_at(i) == map::VoxelState::Unknown &&
        (g.grid->center_of(g.grid->key(i)) - o).dot(axis) < depth_min)
      return {};
    const bool last_trusted = unknown_depth > 0 && g.grid->state_at(i) == map::VoxelState::Unknown && ++unknown > unknown_depth;
    if (g.grid->state_at(i) == map::VoxelState::Occupied || last_trusted) {
      if (depth_min > 0.0 && (g.grid->center_of(g.grid->key(i)) - o).dot(axis) < depth_min) return {};
      break;
    }
    if (g.target[i]) seen.insert(i);
  }
  return seen;
}

/// A pose in the random grids' box (1.4 x 1.2 x 1.0 m), looking any way, rolled by up to 6 rad.
Eigen::Isometry3d random_pose(std::mt19937& rng, std::uniform_real_distribution<double>& u) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() << 1.4 * u(rng), 1.2 * u(rng), 1.0 * u(rng);
  T.linear() = look_along(Eigen::Vector3d(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5), 6.0 * u(rng));
  return T;
}

// On the known cells' own grid a pose sees many cells per word of the scorer's bits, which
// it reads off in order; on a grid 340 times larger, few, which it sorts: both ascending.
TEST(FovScorer, CountsTheDistinctTargetCellsTheRaysCross) {
  const Eigen::AlignedBox3d large(Eigen::Vector3d(-5.3, -5.4, -1.5), Eigen::Vector3d(6.7, 6.6, 2.5));
  for (std::uint32_t seed : {1u, 2u, 3u, 4u}) {
    const RandomGrid g = seed < 4 ? RandomGrid(seed) : RandomGrid(seed, Eigen::AlignedBox3d(), large);
    std::mt19937 rng(seed + 100);
    std::uniform_real_distribution<double> u(0.05, 0.95);
    io::Intrinsics K;
    K.width = 64;
    K.height = 48;
    K.fx = K.fy = 52.5;
    K.cx = 31.5;
    K.cy = 23.5;
    const auto rays = ray_fan(K, 8, 6);
    const double depth_max = 0.9;
    FovScorer scorer(*g.grid, g.target, rays, depth_max);
    FovScorer::Workspace ws;
    for (int pose = 0; pose < (seed < 4 ? 20 : 6); ++pose) {  // the oracle tests every cell
      const Eigen::Isometry3d T = random_pose(rng, u);
      std::set<std::size_t> expected;
      for (const auto& r : rays) {
        const auto s = oracle_seen(g, T.translation(), T.linear() * r, depth_max * r.norm());
        expected.insert(s.begin(), s.end());
      }
      std::vector<std::size_t> seen;
      const auto score = scorer.score(T, ws, &seen);
      ASSERT_EQ(score.targets_seen, expected.size()) << "seed " << seed << " pose " << pose;
      ASSERT_EQ(seen, std::vector<std::size_t>(expected.begin(), expected.end()));
      ASSERT_GT(score.cells_visited, 0u);
    }
  }
}

// Targets gathered in one corner of the grid: the scorer walks a ray only while it can still
// cross one (and, with a minimum depth, at least that far, where a surface voids the ray).
// It must count what the oracle counts over the whole ray, with and without a minimum
// depth, and walk fewer cells than with targets everywhere.
TEST(FovScorer, RaysStopWhereNoTargetIsLeftAndCountAsTheWholeRay) {
  const Eigen::AlignedBox3d corner(Eigen::Vector3d(0.8, 0.6, 0.5), Eigen::Vector3d(1.3, 1.1, 0.9));
  for (std::uint32_t seed : {5u, 6u}) {
    const RandomGrid g(seed, corner), everywhere(seed);
    std::mt19937 rng(seed + 7);
    std::uniform_real_distribution<double> u(0.05, 0.95);
    const auto rays = ray_fan(io::Intrinsics{}, 8, 6);
    for (const double depth_min : {0.0, 0.35, 0.7}) {
      const FovScorer scorer(*g.grid, g.target, rays, 0.9, depth_min);
      const FovScorer whole(*everywhere.grid, everywhere.target, rays, 0.9, depth_min);
      FovScorer::Workspace ws;
      std::size_t total = 0;
      std::uint64_t walked = 0, walked_whole = 0;
      for (int pose = 0; pose < 30; ++pose) {
        // Half the poses anywhere, half beside the targets (rays leave their box early).
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.translation() << 1.4 * u(rng), 1.2 * u(rng), 1.0 * u(rng);
        const Eigen::Vector3d from_middle = T.translation() - Eigen::Vector3d(0.7, 0.6, 0.5);
        if (pose % 2) T.translation() = corner.center() + 0.8 * from_middle.cwiseProduct(Eigen::Vector3d(0.5, 0.5, 0.6));
        T.linear() = look_along(Eigen::Vector3d(u(rng) - 0.2, u(rng) - 0.3, u(rng) - 0.4), 6.0 * u(rng));
        std::set<std::size_t> expected;
        for (const auto& r : rays) {
          const auto s = oracle_seen(g, T.translation(), T.linear() * r, 0.9 * r.norm(), depth_min, T.linear().col(2));
          expected.insert(s.begin(), s.end());
        }
        std::vector<std::size_t> seen;
        const auto score = scorer.score(T, ws, &seen);
        ASSERT_EQ(seen, std::vector<std::size_t>(expected.begin(), expected.end()))
            << "seed " << seed << " pose " << pose << " depth_min " << depth_min;
        total += seen.size();
        walked += score.cells_visited;
        walked_whole += whole.score(T, ws).cells_visited;
      }
      EXPECT_GT(total, 0u);
      EXPECT_LT(walked, walked_whole);
    }
  }
}

// Without near targets, a pose counts exactly the targets it counts with them whose cell
// centre lies at the minimum depth or beyond (the oracle: the full set, filtered by depth).
// The ray-ending rule is the same in both, so with depth_min 0 both count alike.
TEST(FovScorer, FarTargetsOnlyDropsTheCellsNearerThanTheMinimumDepth) {
  const RandomGrid g(4);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  const auto rays = ray_fan(io::Intrinsics{}, 8, 6);
  const double depth_min = 0.3;
  const FovScorer all(*g.grid, g.target, rays, 0.9, depth_min), far(*g.grid, g.target, rays, 0.9, depth_min, false);
  FovScorer::Workspace ws;
  std::size_t dropped = 0;
  for (int pose = 0; pose < 30; ++pose) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() << 1.4 * u(rng), 1.2 * u(rng), 1.0 * u(rng);
    T.linear() = look_along(Eigen::Vector3d(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5), 0.0);
    std::vector<std::size_t> seen_all, seen_far, expected;
    all.score(T, ws, &seen_all);
    far.score(T, ws, &seen_far);
    for (const std::size_t i : seen_all)
      if ((g.grid->center_of(g.grid->key(i)) - T.translation()).dot(T.linear().col(2)) >= depth_min) expected.push_back(i);
    ASSERT_EQ(seen_far, expected) << "pose " << pose;
    dropped += seen_all.size() - seen_far.size();
  }
  EXPECT_GT(dropped, 0u);
}

// U counting only the first N unknown cells of each ray: the oracle walks the whole ray and
// stops after N unknown cells; a ray stopped nearer than the minimum depth counts nothing.
TEST(FovScorer, UnknownDepthCountsOnlyTheFirstUnknownCellsOfEachRay) {
  const RandomGrid g(8);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  const auto rays = ray_fan(io::Intrinsics{}, 8, 6);
  for (const double depth_min : {0.0, 0.35}) {
    const FovScorer all(*g.grid, g.target, rays, 0.9, depth_min);
    for (const int depth : {1, 2}) {
      FovScorer shallow(*g.grid, g.target, rays, 0.9, depth_min);
      shallow.set_unknown_depth(depth);
      FovScorer::Workspace ws;
      std::size_t counted = 0, counted_all = 0;
      for (int pose = 0; pose < 30; ++pose) {
        const Eigen::Isometry3d T = random_pose(rng, u);
        std::set<std::size_t> expected;
        for (const auto& r : rays) {
          const auto s = oracle_seen(g, T.translation(), T.linear() * r, 0.9 * r.norm(), depth_min, T.linear().col(2), depth);
          expected.insert(s.begin(), s.end());
        }
        std::vector<std::size_t> seen;
        shallow.score(T, ws, &seen);
        ASSERT_EQ(seen, std::vector<std::size_t>(expected.begin(), expected.end()))
            << "pose " << pose << " depth " << depth << " depth_min " << depth_min;
        counted += seen.size();
        counted_all += all.score(T, ws).targets_seen;
      }
      EXPECT_GT(counted, 0u);
      EXPECT_LT(counted, counted_all);
    }
  }
}

// A ray that crosses an unknown cell nearer than the minimum depth counts nothing (a void
// cell there with NearUnknown::Void, any unknown cell with Any), against the oracle; what
// Any counts is within what Void counts, and that within what Ignore counts.
TEST(FovScorer, AnUnknownCellNearerThanTheMinimumDepthLeavesItsRayCountingNothing) {
  const RandomGrid g(12);
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  const auto rays = ray_fan(io::Intrinsics{}, 8, 6);
  const double depth_min = 0.35;
  FovScorer::Workspace ws;
  std::map<NearUnknown, std::size_t> counted;
  for (int pose = 0; pose < 30; ++pose) {
    const Eigen::Isometry3d T = random_pose(rng, u);
    std::vector<std::size_t> before;  // the previous mode's cells, a superset of this one's
    for (const NearUnknown mode : {NearUnknown::Ignore, NearUnknown::Void, NearUnknown::Any}) {
      FovScorer scorer(*g.grid, g.target, rays, 0.9, depth_min);
      scorer.set_near_unknown(mode);
      std::set<std::size_t> expected;
      for (const auto& r : rays) {
        const auto s = oracle_seen(g, T.translation(), T.linear() * r, 0.9 * r.norm(), depth_min, T.linear().col(2), 0,
                                   mode);
        expected.insert(s.begin(), s.end());
      }
      std::vector<std::size_t> seen;
      scorer.score(T, ws, &seen);
      ASSERT_EQ(seen, std::vector<std::size_t>(expected.begin(), expected.end()))
          << "pose " << pose << " mode " << to_string(mode);
      EXPECT_TRUE(std::includes(before.begin(), before.end(), seen.begin(), seen.end()) || mode == NearUnknown::Ignore);
      before = seen;
      counted[mode] += seen.size();
    }
  }
  EXPECT_GT(counted[NearUnknown::Any], 0u);
  EXPECT_LT(counted[NearUnknown::Any], counted[NearUnknown::Void]);
  EXPECT_LT(counted[NearUnknown::Void], counted[NearUnknown::Ignore]);
}

// NearUnknown::Hidden: only the cells set_blocking names block a ray nearer than the minimum
// depth (while unknown), against the oracle; without them it counts what Ignore counts, and
// with every unknown cell named what Any counts.
TEST(FovScorer, UnderHiddenOnlyTheBlockingCellsNearerThanTheMinimumDepthLeaveTheRayCountingNothing) {
  const RandomGrid g(14);
  std::mt19937 rng(15);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  const auto rays = ray_fan(io::Intrinsics{}, 8, 6);
  const double depth_min = 0.35;
  std::set<std::size_t> some, every_unknown;
  for (std::size_t i = 0; i < g.grid->cell_count(); ++i)
    if (g.grid->state_at(i) == map::VoxelState::Unknown) {
      every_unknown.insert(i);
      if (u(rng) < 0.3) some.insert(i);
    }
  ASSERT_FALSE(some.empty());
  FovScorer::Workspace ws;
  std::size_t counted_some = 0, counted_ignore = 0;
  for (int pose = 0; pose < 30; ++pose) {
    const Eigen::Isometry3d T = random_pose(rng, u);
    auto seen_with = [&](NearUnknown mode, const std::set<std::size_t>& blocking) {
      FovScorer scorer(*g.grid, g.target, rays, 0.9, depth_min);
      scorer.set_near_unknown(mode);
      if (mode == NearUnknown::Hidden) scorer.set_blocking(std::vector<std::size_t>(blocking.begin(), blocking.end()));
      std::vector<std::size_t> seen;
      scorer.score(T, ws, &seen);
      return seen;
    };
    std::set<std::size_t> expected;
    for (const auto& r : rays) {
      const auto s = oracle_seen(g, T.translation(), T.linear() * r, 0.9 * r.norm(), depth_min, T.linear().col(2), 0,
                                 NearUnknown::Hidden, some);
      expected.insert(s.begin(), s.end());
    }
    const auto hidden = seen_with(NearUnknown::Hidden, some);
    ASSERT_EQ(hidden, std::vector<std::size_t>(expected.begin(), expected.end())) << "pose " << pose;
    const auto ignore = seen_with(NearUnknown::Ignore, {});
    EXPECT_EQ(seen_with(NearUnknown::Hidden, {}), ignore) << "pose " << pose;
    EXPECT_EQ(seen_with(NearUnknown::Hidden, every_unknown), seen_with(NearUnknown::Any, {})) << "pose " << pose;
    counted_some += hidden.size();
    counted_ignore += ignore.size();
  }
  EXPECT_GT(counted_some, 0u);
  EXPECT_LT(counted_some, counted_ignore);  // some rays were blocked
}

TEST(FovScorer, NearUnknownModesReadAsTheyAreWritten) {
  for (const NearUnknown mode : {NearUnknown::Ignore, NearUnknown::Void, NearUnknown::Any, NearUnknown::Hidden})
    EXPECT_EQ(parse_near_unknown(to_string(mode), "--near-unknown"), mode);
  EXPECT_THROW(parse_near_unknown("none", "--near-unknown"), UsageError);
}

// The coarse fan's estimate of the full fan's U (CoarseFan): a 1 m square slab of void cells,
// 25 cm deep, in unknown space at 2.5 cm, seen from 0.4 to 3 m with the Kinect's fans
// (40 x 30 for 80 x 60), the view tilted and rolled so that no ray runs along the grid. Near,
// both fans cross every cell; far, the coarse fan crosses about a quarter of what the full
// one does (the plain count ranked far poses low), and the estimate stays near the full U.
TEST(CoarseFan, EstimatesTheFullFansUAtEveryDistance) {
  const double R = 0.025;
  const map::OccupancyMap empty(R);
  const map::DenseGrid grid(empty, Eigen::AlignedBox3d(Eigen::Vector3d(-1.0, -1.0, -0.1), Eigen::Vector3d(1.0, 1.0, 3.8)));
  const io::Intrinsics K;
  const CoarseFan coarse = coarse_fan(K, 40, 30, 80, 60, R);
  // Shadow factors |d_x| + |d_y| + |d_z| of a ray along an axis and along the diagonal.
  const double along_z = 1.0, diagonal = Eigen::Vector3d::Ones().normalized().cwiseAbs().sum();
  EXPECT_DOUBLE_EQ(coarse.full_hits_per_hit(0.3, along_z), 1.0);  // both fans cross every cell
  EXPECT_NEAR(coarse.full_hits_per_hit(3.0, along_z), 4.0, 1e-12);  // neither: the ratio of ray counts
  for (double z = 0.2; z < 4.0; z += 0.1) {
    EXPECT_LE(coarse.full_hits_per_hit(z, along_z), coarse.full_hits_per_hit(z + 0.1, along_z));
    // A cell's shadow is widest across the diagonal (√3 c²): the coarse fan misses fewer.
    EXPECT_LE(coarse.full_hits_per_hit(z, diagonal), coarse.full_hits_per_hit(z, along_z));
  }
  for (const double depth_m : {0.4, 1.0, 1.5, 2.0, 3.0}) {
    core::LargeVector<std::uint8_t> slab(grid.cell_count());
    for (std::size_t i = 0; i < slab.size(); ++i) {
      const Eigen::Vector3d c = grid.center_of(grid.key(i));
      slab[i] = std::abs(c.x()) < 0.5 && std::abs(c.y()) < 0.5 && c.z() >= depth_m && c.z() < depth_m + 0.25;
    }
    const FovScorer scorer(grid, std::move(slab), ray_fan(K, 80, 60), 4.0);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() << -0.11 * depth_m, 0.07 * depth_m, 0.0;  // the axis meets the slab near its centre
    T.linear() = look_along(Eigen::Vector3d(0.11, -0.07, 1.0), 0.3);
    FovScorer::Workspace ws;
    const double full = double(scorer.score(T, ws).targets_seen);
    const FovScorer::Score screened = scorer.score(T, ws, nullptr, &coarse);
    ASSERT_GT(full, 1000.0) << depth_m;
    EXPECT_NEAR(screened.full_fan_estimate / full, 1.0, 0.06) << "slab at " << depth_m << " m";
    if (depth_m >= 2.0) {
      EXPECT_LT(double(screened.targets_seen), 0.5 * full) << "slab at " << depth_m << " m";
    }
    std::printf("slab at %.1f m: full %.0f, coarse %zu, estimate %.0f\n", depth_m, full, screened.targets_seen,
                screened.full_fan_estimate);
  }
}

}  // namespace
}  // namespace fvx::viewpoints
