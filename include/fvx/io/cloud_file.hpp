#pragma once
/// \file
/// Point cloud files (PCD ascii / binary / binary_compressed, PLY) through PCL. PCL stays in
/// the .cpp; callers see Eigen points.
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "fvx/io/depth_image.hpp"

namespace fvx::io {

/// A cloud as stored in its file.
struct CloudFile {
  /// Points in the file's frame (metres), in file order. Organised clouds keep their NaN
  /// points so that index = row * width + column.
  std::vector<Eigen::Vector3d> points;
  int width = 0;   ///< columns (organised) or number of points
  int height = 1;  ///< rows; 1 for an unorganised cloud
  /// The PCD `VIEWPOINT` (or PLY `obj_info` origin/orientation) as `T_world_sensor`.
  /// Identity when the header has none.
  Eigen::Isometry3d viewpoint = Eigen::Isometry3d::Identity();
  /// Whether the file states its pose: a PCD's VIEWPOINT line, a PLY's "camera" element.
  bool viewpoint_stated = false;

  bool organised() const { return height > 1; }
};

/// Reads a .pcd or .ply file. Throws FileError for a missing file, a header that lies about
/// its data (check_pcd_header, check_ply_header: before anything is allocated), corrupt data,
/// a file without x/y/z fields, or an unknown extension.
CloudFile read_cloud(const std::string& path);

/// True if `T` is the 180° rotation about x (VIEWPOINT `0 0 0 0 1 0 0`) that legacy OpenNI
/// grabbers wrote while storing points already in the optical frame.
bool is_legacy_openni_viewpoint(const Eigen::Isometry3d& T);

/// Writes a binary PCD (x y z float) with `T_world_sensor` in VIEWPOINT, atomically.
/// With `width`·`height` equal to the number of points the cloud is organised (row-major,
/// NaN where a pixel has no measurement); otherwise unorganised.
void write_pcd(const std::string& path, const std::vector<Eigen::Vector3f>& points,
               const Eigen::Isometry3d& T_world_sensor, int width = 0, int height = 0);

}  // namespace fvx::io
