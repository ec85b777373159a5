// One test per ray outcome, on a map built from a single known ray.
#include <gtest/gtest.h>

#include "fvx/map/occupancy_map.hpp"

namespace fvx::map {
namespace {

constexpr double kCell_m = 0.25;  // not R: a unity batch puts dense_grid.hpp's locals named R under it

/// A corridor along +x: cells x = 0..7 (metres 0..2) free, cell 8 ([2, 2.25)) occupied,
/// everything else unknown.
OccupancyMap corridor() {
  OccupancyMap map(kCell_m);
  map.integrate({Eigen::Vector3f(2.125f, 0.125f, 0.125f)}, Eigen::Vector3f(0.125f, 0.125f, 0.125f));
  return map;
}

TEST(RayCast, HitStopsAtTheOccupiedCell) {
  const OccupancyMap map = corridor();
  const RayCast cast = map.cast_ray({{0.125, 0.125, 0.125}, {1, 0, 0}});
  EXPECT_EQ(cast.outcome, RayOutcome::Hit);
  EXPECT_EQ(cast.key, *map.key_of({2.1, 0.1, 0.1}));
  EXPECT_NEAR(cast.distance_m, 2.0 - 0.125, 1e-9);  // entry into [2, 2.25)
}

TEST(RayCast, UnknownStopsAtTheFirstUnknownCell) {
  const OccupancyMap map = corridor();
  const RayCast cast = map.cast_ray({{0.125, 0.125, 0.125}, {-1, 0, 0}});
  EXPECT_EQ(cast.outcome, RayOutcome::Unknown);
  EXPECT_EQ(cast.key, *map.key_of({-0.1, 0.1, 0.1}));
  EXPECT_NEAR(cast.distance_m, 0.125, 1e-9);
  // Sideways out of the corridor, too.
  EXPECT_EQ(map.cast_ray({{1.125, 0.125, 0.125}, {0, 1, 0}}).outcome, RayOutcome::Unknown);
}

TEST(RayCast, MaxRangeInsideFreeSpace) {
  const OccupancyMap map = corridor();
  const RayCast cast = map.cast_ray({{0.125, 0.125, 0.125}, {2, 0, 0}, 1.0});
  EXPECT_EQ(cast.outcome, RayOutcome::MaxRange);
  EXPECT_DOUBLE_EQ(cast.distance_m, 1.0);
}

TEST(RayCast, PassingUnknownReachesMaxRangeOrOutOfBounds) {
  const OccupancyMap map = corridor();
  RayQuery query{{0.125, 0.125, 0.125}, {-1, 0, 0}, 3.0, true};
  EXPECT_EQ(map.cast_ray(query).outcome, RayOutcome::MaxRange);
  query.max_range_m = std::numeric_limits<double>::infinity();
  const RayCast cast = map.cast_ray(query);
  EXPECT_EQ(cast.outcome, RayOutcome::OutOfBounds);
  EXPECT_NEAR(cast.distance_m, 32768 * kCell_m + 0.125, 1e-6);  // the key space ends at -32768 cells
}

TEST(RayCast, OriginOutsideTheKeySpaceIsOutOfBounds) {
  const OccupancyMap map = corridor();
  const RayCast cast = map.cast_ray({{1e5, 0, 0}, {-1, 0, 0}});
  EXPECT_EQ(cast.outcome, RayOutcome::OutOfBounds);
  EXPECT_EQ(cast.distance_m, 0.0);
}

TEST(RayCast, StartingInsideAnOccupiedCellIsAHitAtZero) {
  const OccupancyMap map = corridor();
  const RayCast cast = map.cast_ray({{2.2, 0.1, 0.1}, {0, 0, 1}});
  EXPECT_EQ(cast.outcome, RayOutcome::Hit);
  EXPECT_EQ(cast.distance_m, 0.0);
}

}  // namespace
}  // namespace fvx::map
