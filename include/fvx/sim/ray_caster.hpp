#pragma once
/// \file
/// First-hit ray casting against a mesh. Three interchangeable back ends: Embree (default,
/// fastest), CGAL's AABB tree, and a brute-force loop over triangles (the reference for
/// tests and benchmarks).
#include <Eigen/Geometry>
#include <limits>
#include <memory>
#include <string>

#include "fvx/sim/mesh.hpp"

namespace fvx::sim {

struct Hit {
  /// Distance to the hit in units of the ray direction's length; infinity when nothing is hit.
  float distance = std::numeric_limits<float>::infinity();
  std::uint32_t triangle = 0;                     ///< index into Mesh::triangles
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();  ///< unit geometric normal (outward for
                                                  ///< counter-clockwise triangles)
  bool hit() const { return distance < std::numeric_limits<float>::infinity(); }
};

enum class Backend { Embree, CgalAabb, BruteForce };
const char* to_string(Backend backend);
/// "embree", "cgal" or "brute"; throws UsageError naming `what` otherwise.
Backend parse_backend(const std::string& text, const std::string& what);

class RayCaster {
 public:
  virtual ~RayCaster() = default;
  /// The first triangle along origin + t·direction with t_min < t <= t_max (direction need
  /// not be unit length). Thread-safe.
  virtual Hit cast(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_min,
                   float t_max) const = 0;
};

/// True when `p` lies inside a closed part of the mesh: an odd number of surfaces crossed,
/// along at least two of three fixed skew directions (faces where two solids touch count
/// once for the caster; the vote keeps one such ray from deciding).
bool inside_solid(const RayCaster& caster, const Eigen::Vector3f& p);

/// Builds the acceleration structure for `mesh` (which must outlive the caster).
std::unique_ptr<RayCaster> make_ray_caster(const Mesh& mesh, Backend backend = Backend::Embree);

}  // namespace fvx::sim
