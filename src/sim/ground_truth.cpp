#include "fvx/sim/ground_truth.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "fvx/core/error.hpp"

namespace fvx::sim {
namespace {

std::string metres_text(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

}  // namespace

GroundTruth::GroundTruth(const Mesh& mesh, const RayCaster& caster, double resolution_m,
                         const Eigen::AlignedBox3d& region)
    : resolution_m_(resolution_m) {
  FVX_ASSERT(resolution_m > 0.0 && !region.isEmpty(), "ground truth needs a resolution and a region");
  const double R = resolution_m;
  // The region comes from a scene file: it must fit the map's key space (OctoMap's 16-bit keys,
  // ±32767 cells) and a grid this class can allocate, or fvx says so instead of aborting.
  const double reach_m = 32767.0 * R;
  if (!(region.min().array().abs() <= reach_m).all() || !(region.max().array().abs() <= reach_m).all())
    throw Error("the search space reaches beyond ±" + std::to_string(int(reach_m)) + " m, the most a map of " +
                metres_text(R) + " m cells holds");
  const Eigen::Array3d cells = (region.max() - region.min()).array() / R + 1.0;
  if (cells.prod() >= 2e9)
    throw Error("the search space holds " + metres_text(cells.prod()) + " cells of " + metres_text(R) +
                " m; the ground truth holds at most 2e9");
  // Cells whose centres lie in the region: centre (k + 0.5)·R ∈ [min, max].
  first_ = ((region.min().array() / R) - 0.5).ceil().cast<int>();
  const Eigen::Vector3i last = ((region.max().array() / R) - 0.5).floor().cast<int>();
  size_ = (last - first_).array().max(-1) + 1;
  FVX_ASSERT((size_.array() > 0).all(), "the region holds no cell centre");
  FVX_ASSERT(double(size_.x()) * size_.y() * size_.z() < 2e9, "ground-truth region too large");
  solid_.assign(std::size_t(size_.x()) * size_.y() * size_.z(), 0);

  // Interior: crossings along +x rows through the cell centres, from outside the mesh.
  const Eigen::AlignedBox3f bounds = mesh.bounds();
  const float start_x = std::min(bounds.min().x(), float(region.min().x())) - 1.0f;
  for (int z = 0; z < size_.z(); ++z) {
    for (int y = 0; y < size_.y(); ++y) {
      const Eigen::Vector3d c = center_of(first_ + Eigen::Vector3i(0, y, z));
      const Eigen::Vector3f origin(start_x, float(c.y()), float(c.z()));
      std::vector<float> crossings;
      for (float t = 0.0f;;) {
        const Hit hit = caster.cast(origin, Eigen::Vector3f::UnitX(), t, std::numeric_limits<float>::max());
        if (!hit.hit()) break;
        crossings.push_back(start_x + hit.distance);
        t = hit.distance + 1e-5f;
      }
      std::size_t passed = 0;
      for (int x = 0; x < size_.x(); ++x) {
        const double cx = center_of(first_ + Eigen::Vector3i(x, y, z)).x();
        while (passed < crossings.size() && crossings[passed] < cx) ++passed;
        if (passed % 2 == 1) solid_[index(first_ + Eigen::Vector3i(x, y, z))] = 1;
      }
    }
  }

  // Surface: sample every triangle at R/4 and mark the cells the samples fall in. Samples
  // sit 1 µm inside the material (against the outward normal) and inside the triangle
  // (towards its centroid): a face or an edge lying exactly on a cell border then marks the
  // cell holding the material, not the empty one beside it.
  const double step = R / 4.0;
  for (const auto& tri : mesh.triangles) {
    const Eigen::Vector3d v[3] = {mesh.vertices[tri[0]].cast<double>(), mesh.vertices[tri[1]].cast<double>(),
                                  mesh.vertices[tri[2]].cast<double>()};
    const Eigen::Vector3d inward = -1e-6 * (v[1] - v[0]).cross(v[2] - v[0]).normalized();
    const Eigen::Vector3d centroid = (v[0] + v[1] + v[2]) / 3.0;
    auto inset = [&](const Eigen::Vector3d& p) -> Eigen::Vector3d { return p + inward + 1e-6 * (centroid - p).normalized(); };
    const Eigen::Vector3d a = inset(v[0]), b = inset(v[1]), c = inset(v[2]);
    const int n = std::max(1, int(std::ceil(std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()}) / step)));
    for (int i = 0; i <= n; ++i) {
      for (int j = 0; i + j <= n; ++j) {
        const Eigen::Vector3d p = a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n);
        const Eigen::Vector3i cell = cell_of(p);
        if (contains(cell)) solid_[index(cell)] = 1;
      }
    }
  }
  solid_count_ = std::size_t(std::count(solid_.begin(), solid_.end(), 1));
}

Eigen::Vector3i GroundTruth::cell_of(const Eigen::Vector3d& p) const {
  // Same arithmetic as OctoMap's coordToKey: floor(coordinate · (1/R)).
  const double factor = 1.0 / resolution_m_;
  return {int(std::floor(factor * p.x())), int(std::floor(factor * p.y())), int(std::floor(factor * p.z()))};
}

Eigen::Vector3d GroundTruth::center_of(const Eigen::Vector3i& cell) const {
  return (cell.cast<double>().array() + 0.5) * resolution_m_;
}

bool GroundTruth::contains(const Eigen::Vector3i& cell) const {
  const Eigen::Vector3i local = cell - first_;
  return (local.array() >= 0).all() && (local.array() < size_.array()).all();
}

std::size_t GroundTruth::index(const Eigen::Vector3i& cell) const {
  const Eigen::Vector3i l = cell - first_;
  return (std::size_t(l.z()) * size_.y() + l.y()) * size_.x() + l.x();
}

bool GroundTruth::solid(const Eigen::Vector3i& cell) const {
  FVX_ASSERT(contains(cell), "cell outside the ground truth");
  return solid_[index(cell)] != 0;
}

double GroundTruth::free_volume_m3(const Eigen::AlignedBox3d& box) const {
  std::size_t count = 0;
  for (int z = 0; z < size_.z(); ++z)
    for (int y = 0; y < size_.y(); ++y)
      for (int x = 0; x < size_.x(); ++x) {
        const Eigen::Vector3i cell = first_ + Eigen::Vector3i(x, y, z);
        count += !solid_[index(cell)] && box.contains(center_of(cell));
      }
  return double(count) * resolution_m_ * resolution_m_ * resolution_m_;
}

std::size_t GroundTruth::solid_among(const std::vector<map::VoxelKey>& keys) const {
  std::size_t count = 0;
  for (const map::VoxelKey& k : keys) {
    const Eigen::Vector3i cell(int(k.x) - 32768, int(k.y) - 32768, int(k.z) - 32768);  // OctoMap's key offset
    count += contains(cell) && solid(cell);
  }
  return count;
}

std::size_t GroundTruth::free_in_solid(const map::OccupancyMap& map, const Eigen::AlignedBox3d& box) const {
  std::size_t count = 0;
  for (int z = 0; z < size_.z(); ++z)
    for (int y = 0; y < size_.y(); ++y)
      for (int x = 0; x < size_.x(); ++x) {
        const Eigen::Vector3i cell = first_ + Eigen::Vector3i(x, y, z);
        if (!solid_[index(cell)] || !box.contains(center_of(cell))) continue;
        const auto key = map.key_of(center_of(cell));
        count += key && map.state(*key) == map::VoxelState::Free;
      }
  return count;
}

map::OccupancyMap GroundTruth::to_map() const {
  map::OccupancyMap map(resolution_m_);
  for (int z = 0; z < size_.z(); ++z)
    for (int y = 0; y < size_.y(); ++y)
      for (int x = 0; x < size_.x(); ++x) {
        const Eigen::Vector3i cell = first_ + Eigen::Vector3i(x, y, z);
        const auto key = map.key_of(center_of(cell));
        FVX_ASSERT(key.has_value(), "ground-truth cell outside the map's key space");
        map.set_state(*key, solid_[index(cell)] ? map::VoxelState::Occupied : map::VoxelState::Free);
      }
  return map;
}

Eigen::AlignedBox3d exploration_region(const Eigen::AlignedBox3d& S,
                                       const std::vector<Eigen::Vector3d>& sensor_positions_m) {
  Eigen::AlignedBox3d region(S.min() - Eigen::Vector3d::Constant(0.25), S.max() + Eigen::Vector3d::Constant(0.25));
  for (const Eigen::Vector3d& p : sensor_positions_m) region.extend(p);
  return region.intersection(
      Eigen::AlignedBox3d(S.min() - Eigen::Vector3d::Constant(2.0), S.max() + Eigen::Vector3d::Constant(2.0)));
}

}  // namespace fvx::sim
