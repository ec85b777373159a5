#pragma once
/// \file
/// Stage `capmap`, part 4: a capability map stored in the coordinates of its first joint's
/// turn (RM4D, ICRA 2025). When the arm's first movable joint is revolute, every sensor pose
/// is a turn of a pose with that joint at 0, FK(q₀, q₁…) = R(q₀) · FK(0, q₁…), so reachability
/// depends on (radius from the axis, height along it, viewing direction relative to the
/// radial plane) and the turn's limits only. The layout keeps one witness per reduced cell —
/// (radius, height) cells of half a voxel and 4N relative directions — at q₀ = 0, exactly as
/// forward kinematics gave it (float32). Expanding it paints every turn of each witness within
/// the joint's limits into the voxel grid: each bit painted is a real pose of the arm (up to
/// float32 rounding), so the grid keeps the fk-witness definition (man fvx-capmap.5).
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace fvx::capmap {

class Arm;
class CapabilityMap;
class DirectionSet;

/// The first joint's frame: origin on its axis, z along it, x a fixed perpendicular; the
/// turn's limits. Written in the map's header, so that expanding needs no URDF.
struct TurnFrame {
  Eigen::Vector3d point_base = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_base = Eigen::Vector3d::UnitZ();  ///< unit
  Eigen::Vector3d x_base = Eigen::Vector3d::UnitX();     ///< unit, perpendicular to the axis
  double lower_rad = -M_PI, upper_rad = M_PI;            ///< the first joint's limits
  double cell_m = 0.025;          ///< radius and height cells (half the voxel)
  int relative_directions = 800;  ///< relative-direction cells (4 × the map's directions)

  /// The frame of an arm whose first movable joint is revolute; Error otherwise.
  static TurnFrame of(const Arm& arm, double voxel_m, int directions);
  /// Sub-cells per voxel edge and relative directions per map direction: measured on the
  /// youBot, SO-101 and fvx arm at 5 cm (README): 2 and 4 keep recall within 0.01 of the
  /// full-grid build at half the witnesses of 4 and 1.
  static constexpr int kCellsPerVoxel = 2, kDirectionsPerDirection = 4;
};

/// A sensor pose at q₀ = 0 in the turn's coordinates (float32: what the file holds).
struct TurnWitness {
  float radius_m = 0, height_m = 0;  ///< distance from the axis; along it from the frame's origin
  float azimuth_rad = 0;             ///< about the axis from x_base
  float direction[3] = {0, 0, 1};    ///< viewing axis in the radial frame (radial, tangential, axis)
};

/// The witness of `T_base_sensor` (taken at q₀ = 0) with viewing axis `viewing_axis_sensor`.
TurnWitness to_turn_witness(const TurnFrame& frame, const Eigen::Isometry3d& T_base_sensor,
                            const Eigen::Vector3d& viewing_axis_sensor);
/// The reduced cell of a witness: height cell, radius cell, relative direction, as one
/// number that orders by height first (shards split by height cell).
std::uint64_t turn_cell(const TurnFrame& frame, const DirectionSet& relative, const TurnWitness& w);
/// The height cell (signed) packed in turn_cell's number.
std::int64_t turn_height_cell(std::uint64_t cell);

/// Paints each witness's turns from the lower to the upper limit into `grid`'s bits, steps of
/// at most half a voxel at its radius and half the directions' mean spacing. Throws Error
/// when that would take more than `max_steps` steps (a corrupt file's lying radius).
void expand_turn_witnesses(const TurnFrame& frame, const std::vector<TurnWitness>& witnesses, CapabilityMap& grid,
                           double max_steps);

/// The number of painting steps of one witness (what expand_turn_witnesses would take).
double turn_steps(const TurnFrame& frame, const TurnWitness& w, double voxel_m, double direction_spacing_rad);

}  // namespace fvx::capmap
