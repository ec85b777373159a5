#include "fvx/core/json.hpp"

#include <cmath>
#include <nlohmann/json.hpp>

namespace fvx {

Json vec_json(const Eigen::Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); }

Json pose_json(const Eigen::Isometry3d& T) {
  Eigen::Quaterniond q(T.rotation());
  if (q.w() < 0) q.coeffs() *= -1.0;  // one sign for one rotation
  return {{"position_m", vec_json(T.translation())}, {"quaternion_xyzw", {q.x(), q.y(), q.z(), q.w()}}};
}

Json bounds_json(const Eigen::AlignedBox3d& b) {
  if (b.isEmpty()) return nullptr;
  return {{"min", vec_json(b.min())}, {"max", vec_json(b.max())}};
}

Json bounds_json(const std::optional<Eigen::AlignedBox3d>& b) { return b ? bounds_json(*b) : Json(nullptr); }

Json finite_or_null(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

}  // namespace fvx
