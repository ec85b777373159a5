#pragma once
/// \file
/// The JSON type of reports and config echoes (nlohmann's, keys in insertion order), and the
/// forms geometry takes in them. Only the forward declaration here: the full header is heavy.
#include <Eigen/Geometry>
#include <nlohmann/json_fwd.hpp>
#include <optional>

namespace fvx {

using Json = nlohmann::ordered_json;

/// [x, y, z]
Json vec_json(const Eigen::Vector3d& v);
/// {"position_m": [x, y, z], "quaternion_xyzw": [qx, qy, qz, qw]} with qw >= 0.
Json pose_json(const Eigen::Isometry3d& T);
/// {"min": [x, y, z], "max": [x, y, z]}; null for an empty box.
Json bounds_json(const Eigen::AlignedBox3d& b);
/// bounds_json of the box, or null when there is none.
Json bounds_json(const std::optional<Eigen::AlignedBox3d>& b);
/// The number, or null for ±infinity and NaN (JSON has neither).
Json finite_or_null(double v);

}  // namespace fvx
