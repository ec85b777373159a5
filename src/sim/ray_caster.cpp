// Three ray casters behind one interface. Normals come from the mesh, not the back end, so
// every back end reports the same outward normal.
#include "fvx/sim/ray_caster.hpp"

#include <embree3/rtcore.h>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include "fvx/core/error.hpp"

namespace fvx::sim {

const char* to_string(Backend backend) {
  switch (backend) {
    case Backend::Embree: return "embree";
    case Backend::CgalAabb: return "cgal";
    case Backend::BruteForce: return "brute";
  }
  return "?";
}

Backend parse_backend(const std::string& text, const std::string& what) {
  if (text == "embree") return Backend::Embree;
  if (text == "cgal") return Backend::CgalAabb;
  if (text == "brute") return Backend::BruteForce;
  throw UsageError(what + ": '" + text + "' is not a ray-casting back end; use embree, cgal or brute");
}

namespace {

Eigen::Vector3f triangle_normal(const Mesh& mesh, std::uint32_t t) {
  const auto& tri = mesh.triangles[t];
  const Eigen::Vector3f& a = mesh.vertices[tri[0]];
  return (mesh.vertices[tri[1]] - a).cross(mesh.vertices[tri[2]] - a).normalized();
}

class EmbreeCaster final : public RayCaster {
 public:
  explicit EmbreeCaster(const Mesh& mesh) : mesh_(mesh) {
    device_ = rtcNewDevice(nullptr);
    if (!device_) throw Error("cannot start Embree (rtcNewDevice failed)");
    scene_ = rtcNewScene(device_);
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.vertices.size()));
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
      for (int k = 0; k < 3; ++k) vertices[3 * i + k] = mesh.vertices[i][k];
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.triangles.size()));
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) indices[3 * i + k] = mesh.triangles[i][k];
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene_, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene_);
  }
  ~EmbreeCaster() override {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  EmbreeCaster(const EmbreeCaster&) = delete;
  EmbreeCaster& operator=(const EmbreeCaster&) = delete;

  Hit cast(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_min,
           float t_max) const override {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh{};
    rh.ray.org_x = origin.x();
    rh.ray.org_y = origin.y();
    rh.ray.org_z = origin.z();
    rh.ray.dir_x = direction.x();
    rh.ray.dir_y = direction.y();
    rh.ray.dir_z = direction.z();
    rh.ray.tnear = t_min;
    rh.ray.tfar = t_max;
    rh.ray.mask = ~0u;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &context, &rh);
    Hit hit;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
    hit.distance = rh.ray.tfar;
    hit.triangle = rh.hit.primID;
    hit.normal = triangle_normal(mesh_, hit.triangle);
    return hit;
  }

 private:
  const Mesh& mesh_;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

class CgalCaster final : public RayCaster {
  using K = CGAL::Simple_cartesian<double>;
  using Iterator = std::vector<K::Triangle_3>::const_iterator;
  using Primitive = CGAL::AABB_triangle_primitive<K, Iterator>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

 public:
  explicit CgalCaster(const Mesh& mesh) : mesh_(mesh) {
    auto point = [&](std::uint32_t i) {
      const Eigen::Vector3f& v = mesh.vertices[i];
      return K::Point_3(v.x(), v.y(), v.z());
    };
    for (const auto& t : mesh.triangles) triangles_.emplace_back(point(t[0]), point(t[1]), point(t[2]));
    tree_.insert(triangles_.begin(), triangles_.end());
    tree_.build();
  }

  Hit cast(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_min,
           float t_max) const override {
    const Eigen::Vector3d o = origin.cast<double>() + double(t_min) * direction.cast<double>();
    const Eigen::Vector3d d = direction.cast<double>();
    const K::Ray_3 ray(K::Point_3(o.x(), o.y(), o.z()), K::Vector_3(d.x(), d.y(), d.z()));
    const auto found = tree_.first_intersection(ray);
    Hit hit;
    if (!found) return hit;
    K::Point_3 p;
    if (const K::Point_3* point = boost::get<K::Point_3>(&found->first)) {
      p = *point;
    } else if (const K::Segment_3* segment = boost::get<K::Segment_3>(&found->first)) {
      p = CGAL::squared_distance(ray.source(), segment->source()) <= CGAL::squared_distance(ray.source(), segment->target())
              ? segment->source()
              : segment->target();
    } else {
      return hit;
    }
    const double t = t_min + (Eigen::Vector3d(p.x(), p.y(), p.z()) - o).norm() / d.norm();
    if (t > t_max) return hit;
    hit.distance = float(t);
    hit.triangle = std::uint32_t(std::distance(triangles_.cbegin(), found->second));
    hit.normal = triangle_normal(mesh_, hit.triangle);
    return hit;
  }

 private:
  const Mesh& mesh_;
  std::vector<K::Triangle_3> triangles_;
  Tree tree_;
};

class BruteForceCaster final : public RayCaster {
 public:
  explicit BruteForceCaster(const Mesh& mesh) : mesh_(mesh) {}

  /// Möller–Trumbore against every triangle.
  Hit cast(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_min,
           float t_max) const override {
    Hit hit;
    float best = t_max;
    for (std::uint32_t i = 0; i < mesh_.triangles.size(); ++i) {
      const auto& tri = mesh_.triangles[i];
      const Eigen::Vector3f& a = mesh_.vertices[tri[0]];
      const Eigen::Vector3f e1 = mesh_.vertices[tri[1]] - a, e2 = mesh_.vertices[tri[2]] - a;
      const Eigen::Vector3f p = direction.cross(e2);
      const float det = e1.dot(p);
      if (std::abs(det) < 1e-12f) continue;
      const float inv = 1.0f / det;
      const Eigen::Vector3f s = origin - a;
      const float u = s.dot(p) * inv;
      if (u < 0.0f || u > 1.0f) continue;
      const Eigen::Vector3f q = s.cross(e1);
      const float v = direction.dot(q) * inv;
      if (v < 0.0f || u + v > 1.0f) continue;
      const float t = e2.dot(q) * inv;
      if (t >= t_min && t <= best) {
        best = t;
        hit.distance = t;
        hit.triangle = i;
      }
    }
    if (hit.hit()) hit.normal = triangle_normal(mesh_, hit.triangle);
    return hit;
  }

 private:
  const Mesh& mesh_;
};

}  // namespace

namespace {

/// Surfaces crossed from `p` along `direction`, each counted once.
int crossings(const RayCaster& caster, const Eigen::Vector3f& p, const Eigen::Vector3f& direction) {
  int n = 0;
  for (float t = 0.0f;; ++n) {
    const Hit hit = caster.cast(p, direction, t, std::numeric_limits<float>::max());
    if (!hit.hit()) break;
    t = hit.distance + 1e-5f;
  }
  return n;
}

}  // namespace

bool inside_solid(const RayCaster& caster, const Eigen::Vector3f& p) {
  // Parity along three directions off the axes, by majority: where two solids touch, their
  // coincident faces are one hit for the caster, and one ray's parity flips. An axis-aligned
  // ray meets such faces in scenes built from boxes (a floor against a wall: a point inside
  // the floor read as outside along +x); a skew ray seldom does, and two of three agree.
  static const Eigen::Vector3f directions[3] = {Eigen::Vector3f(1.0f, 0.2113f, 0.3719f).normalized(),
                                                Eigen::Vector3f(-0.3163f, 1.0f, 0.1427f).normalized(),
                                                Eigen::Vector3f(0.1981f, -0.4413f, 1.0f).normalized()};
  int odd = 0;
  for (const Eigen::Vector3f& d : directions) odd += crossings(caster, p, d) % 2;
  return odd >= 2;
}

std::unique_ptr<RayCaster> make_ray_caster(const Mesh& mesh, Backend backend) {
  FVX_ASSERT(!mesh.triangles.empty(), "a ray caster needs triangles");
  switch (backend) {
    case Backend::Embree: return std::make_unique<EmbreeCaster>(mesh);
    case Backend::CgalAabb: return std::make_unique<CgalCaster>(mesh);
    case Backend::BruteForce: return std::make_unique<BruteForceCaster>(mesh);
  }
  FVX_ASSERT(false, "unknown back end");
  return nullptr;
}

}  // namespace fvx::sim
