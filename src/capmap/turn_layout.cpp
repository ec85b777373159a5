#include "fvx/capmap/turn_layout.hpp"

#include <algorithm>
#include <cmath>
#include <thread>
#include <unordered_map>

#include "fvx/capmap/arm.hpp"
#include "fvx/capmap/capability_map.hpp"
#include "fvx/core/error.hpp"
#include "fvx/core/threads.hpp"

namespace fvx::capmap {

TurnFrame TurnFrame::of(const Arm& arm, double voxel_m, int directions) {
  const std::optional<FirstJointAxis>& axis = arm.first_joint_axis();
  if (!axis) throw Error("the arm's first movable joint is not revolute: its map has no turn layout (use --layout grid)");
  TurnFrame f;
  f.point_base = axis->point_base;
  f.axis_base = axis->direction_base;
  // x: the base's x (else y) made perpendicular to the axis; any fixed choice would do.
  Eigen::Vector3d x = Eigen::Vector3d::UnitX() - f.axis_base * f.axis_base.x();
  if (x.norm() < 0.5) x = Eigen::Vector3d::UnitY() - f.axis_base * f.axis_base.y();
  f.x_base = x.normalized();
  f.lower_rad = arm.lower_rad()[0];
  f.upper_rad = arm.upper_rad()[0];
  f.cell_m = voxel_m / kCellsPerVoxel;
  f.relative_directions = directions * kDirectionsPerDirection;
  return f;
}

namespace {

/// Columns x, y, z of the turn's frame in the base frame.
Eigen::Matrix3d R_base_turn(const TurnFrame& f) {
  Eigen::Matrix3d R;
  R << f.x_base, f.axis_base.cross(f.x_base), f.axis_base;
  return R;
}

constexpr std::int64_t kHeightOffset = std::int64_t(1) << 23;  ///< height cells are signed

}  // namespace

TurnWitness to_turn_witness(const TurnFrame& frame, const Eigen::Isometry3d& T_base_sensor,
                            const Eigen::Vector3d& viewing_axis_sensor) {
  const Eigen::Matrix3d R = R_base_turn(frame);
  const Eigen::Vector3d p = R.transpose() * (T_base_sensor.translation() - frame.point_base);
  const Eigen::Vector3d d = R.transpose() * (T_base_sensor.linear() * viewing_axis_sensor);
  const double azimuth = std::atan2(p.y(), p.x()), c = std::cos(azimuth), s = std::sin(azimuth);
  TurnWitness w;
  w.radius_m = float(std::hypot(p.x(), p.y()));
  w.height_m = float(p.z());
  w.azimuth_rad = float(azimuth);
  // The direction in the radial frame at the witness's azimuth: turning the pose turns both.
  const Eigen::Vector3d relative(c * d.x() + s * d.y(), -s * d.x() + c * d.y(), d.z());
  for (int a = 0; a < 3; ++a) w.direction[a] = float(relative[a]);
  return w;
}

std::uint64_t turn_cell(const TurnFrame& frame, const DirectionSet& relative, const TurnWitness& w) {
  const auto radius = std::uint64_t(std::clamp(std::floor(double(w.radius_m) / frame.cell_m), 0.0, double(kHeightOffset - 1)));
  const auto height = std::uint64_t(std::clamp(std::floor(double(w.height_m) / frame.cell_m) + double(kHeightOffset), 0.0,
                                               double(2 * kHeightOffset - 1)));
  const Eigen::Vector3d d(w.direction[0], w.direction[1], w.direction[2]);
  return height << 40 | radius << 16 | std::uint64_t(relative.nearest_banded(d.normalized()));
}

std::int64_t turn_height_cell(std::uint64_t cell) { return std::int64_t(cell >> 40) - kHeightOffset; }

double turn_steps(const TurnFrame& frame, const TurnWitness& w, double voxel_m, double direction_spacing_rad) {
  // A step moves the sensor by radius·step and turns its axis by at most step.
  const double step = std::min(0.5 * voxel_m / std::max(double(w.radius_m), 1e-9), 0.5 * direction_spacing_rad);
  return std::ceil((frame.upper_rad - frame.lower_rad) / step);
}

namespace {

/// Paints the turns of witnesses [begin, end) through `paint(voxel, direction)`.
template <typename Paint>
void paint_turns(const TurnFrame& frame, const std::vector<TurnWitness>& witnesses, std::size_t begin, std::size_t end,
                 const CapabilityMap& grid, Paint&& paint) {
  const double voxel_m = grid.header().voxel_m, spacing = grid.directions().mean_spacing_rad();
  const Eigen::Matrix3d R = R_base_turn(frame);
  for (std::size_t i = begin; i < end; ++i) {
    const TurnWitness& w = witnesses[i];
    const int steps = int(turn_steps(frame, w, voxel_m, spacing));
    const Eigen::Vector3d relative(w.direction[0], w.direction[1], w.direction[2]);
    int direction = -1;  // the last step's: the next one is near it
    for (int k = 0; k <= steps; ++k) {
      // q₀ from the lower to the upper limit: the witness turned to azimuth a + q₀.
      const double q0 = steps ? frame.lower_rad + (frame.upper_rad - frame.lower_rad) * k / steps : frame.lower_rad;
      const double azimuth = double(w.azimuth_rad) + q0, c = std::cos(azimuth), s = std::sin(azimuth);
      const Eigen::Vector3d p = frame.point_base + R * Eigen::Vector3d(w.radius_m * c, w.radius_m * s, w.height_m);
      const std::int64_t voxel = grid.voxel_of(p);
      if (voxel < 0) continue;
      const Eigen::Vector3d d =
          R * Eigen::Vector3d(c * relative.x() - s * relative.y(), s * relative.x() + c * relative.y(), relative.z());
      direction = grid.directions().nearest_banded(d.normalized(), direction);
      paint(voxel, direction);
    }
  }
}

/// A grid's bits, dense (voxel-major words), when every thread's copy fits in this many bytes.
constexpr double kDenseBytes = 256.0 * 1024 * 1024;

}  // namespace

void expand_turn_witnesses(const TurnFrame& frame, const std::vector<TurnWitness>& witnesses, CapabilityMap& grid,
                           double max_steps) {
  const double voxel_m = grid.header().voxel_m, spacing = grid.directions().mean_spacing_rad();
  double total = 0;
  for (const TurnWitness& w : witnesses) total += turn_steps(frame, w, voxel_m, spacing);
  if (total > max_steps) throw Error("expanding the turn layout would take " + std::to_string(total) + " steps");
  const auto& dims = grid.header().dims;
  const std::size_t words = std::size_t((grid.directions().size() + 63) / 64);
  const double voxels = double(dims[0]) * dims[1] * dims[2];
  const unsigned threads = core::worker_count(0, (witnesses.size() + 1023) / 1024);
  if (voxels * double(words) * 8.0 * threads > kDenseBytes) {  // a huge grid: only the voxels painted
    std::unordered_map<std::int64_t, std::vector<std::uint64_t>> bits;
    paint_turns(frame, witnesses, 0, witnesses.size(), grid, [&](std::int64_t voxel, int d) {
      auto& mine = bits[voxel];
      if (mine.empty()) mine.assign(words, 0);
      mine[std::size_t(d / 64)] |= std::uint64_t(1) << (d % 64);
    });
    for (const auto& [voxel, mine] : bits) grid.set_words(voxel, mine.data());
    return;
  }
  // Each thread paints its share of the witnesses into its own copy; the union is the map.
  std::vector<std::vector<std::uint64_t>> bits(threads, std::vector<std::uint64_t>(std::size_t(voxels) * words, 0));
  std::vector<std::thread> pool;
  for (unsigned t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      paint_turns(frame, witnesses, witnesses.size() * t / threads, witnesses.size() * (t + 1) / threads, grid,
                  [&](std::int64_t voxel, int d) { bits[t][std::size_t(voxel) * words + std::size_t(d / 64)] |= std::uint64_t(1) << (d % 64); });
    });
  for (auto& thread : pool) thread.join();
  std::vector<std::uint64_t> mine(words);
  for (std::size_t voxel = 0; voxel < std::size_t(voxels); ++voxel) {
    bool any = false;
    for (std::size_t w = 0; w < words; ++w) {
      mine[w] = 0;
      for (const auto& copy : bits) mine[w] |= copy[voxel * words + w];
      any = any || mine[w];
    }
    if (any) grid.set_words(std::int64_t(voxel), mine.data());
  }
}

}  // namespace fvx::capmap
