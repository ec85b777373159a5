#include "fvx/io/cloud_file.hpp"

#include <pcl/PCLPointCloud2.h>

#include <stdexcept>
#include <pcl/common/io.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>

#include <algorithm>

#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"
#include "fvx/io/cloud_header.hpp"
#include "save_pcd.hpp"

namespace fvx::io {
namespace {

/// PCL reports problems on stderr itself; fvx reports them once, through its own errors.
void silence_pcl() { pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS); }

bool has_field(const pcl::PCLPointCloud2& cloud, const std::string& name) {
  return std::any_of(cloud.fields.begin(), cloud.fields.end(),
                     [&](const pcl::PCLPointField& f) { return f.name == name; });
}

}  // namespace

CloudFile read_cloud(const std::string& path) {
  require_readable_file(path);
  silence_pcl();
  const std::string ext = lowercase_extension(path);
  pcl::PCLPointCloud2 blob;
  Eigen::Vector4f origin = Eigen::Vector4f::Zero();
  Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity();
  int result = -1;
  bool viewpoint_stated = false;
  try {
    if (ext == ".pcd") {
      viewpoint_stated = check_pcd_header(path);  // before PCL allocates what the header claims
      int version = 0, data_type = 0;
      unsigned data_index = 0;
      pcl::PCDReader reader;
      // PCL 1.13's read() crashes on a file without a header; check the header first.
      if (reader.readHeader(path, blob, origin, orientation, version, data_type, data_index) < 0 ||
          blob.fields.empty())
        throw FileError(path, "corrupt PCD header (no FIELDS, or a malformed line)");
      result = reader.read(path, blob, origin, orientation, version);
    } else if (ext == ".ply") {
      viewpoint_stated = check_ply_header(path);
      int version = 0;
      pcl::PLYReader reader;
      result = reader.read(path, blob, origin, orientation, version);
    } else {
      throw FileError(path, "unknown cloud format '" + ext + "'; expected .pcd or .ply");
    }
  } catch (const pcl::PCLException& e) {
    throw FileError(path, std::string("corrupt point cloud: ") + e.what());
  } catch (const std::logic_error& e) {  // PCL's header parser indexes with at() (fuzzing found it)
    throw FileError(path, std::string("corrupt point cloud header: ") + e.what());
  }
  if (result < 0) throw FileError(path, "corrupt or unreadable point cloud (header or data)");
  if (!has_field(blob, "x") || !has_field(blob, "y") || !has_field(blob, "z"))
    throw FileError(path, "the cloud has no x, y, z fields");
  const std::size_t expected = std::size_t(blob.width) * blob.height;
  if (blob.data.size() < expected * blob.point_step)
    throw FileError(path, "truncated point data: header promises " + std::to_string(expected) +
                              " points");

  CloudFile file;
  pcl::PointCloud<pcl::PointXYZ> xyz;
  if (expected > 0) pcl::fromPCLPointCloud2(blob, xyz);  // with no points PCL binds a reference to null data
  file.width = static_cast<int>(xyz.width);
  file.height = static_cast<int>(xyz.height);
  file.points.reserve(xyz.size());
  for (const auto& p : xyz.points) file.points.emplace_back(p.x, p.y, p.z);

  const Eigen::Quaterniond q = orientation.cast<double>();
  if (!origin.head<3>().allFinite() || !q.coeffs().allFinite() || q.norm() < 1e-9)
    throw FileError(path, "VIEWPOINT is not a finite pose");
  file.viewpoint = Eigen::Isometry3d(q.normalized());
  file.viewpoint.pretranslate(origin.head<3>().cast<double>());
  file.viewpoint_stated = viewpoint_stated;
  return file;
}

void write_pcd(const std::string& path, const std::vector<Eigen::Vector3f>& points,
               const Eigen::Isometry3d& T_world_sensor, int width, int height) {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.reserve(points.size());
  for (const auto& p : points) cloud.push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
  const bool organised = width > 0 && height > 0 && std::size_t(width) * std::size_t(height) == points.size();
  cloud.width = organised ? std::uint32_t(width) : std::uint32_t(points.size());
  cloud.height = organised ? std::uint32_t(height) : 1u;
  cloud.is_dense = std::all_of(points.begin(), points.end(), [](const Eigen::Vector3f& p) { return p.allFinite(); });
  const Eigen::Vector3d t = T_world_sensor.translation();
  cloud.sensor_origin_ = Eigen::Vector4f(float(t.x()), float(t.y()), float(t.z()), 0.0f);
  cloud.sensor_orientation_ = Eigen::Quaterniond(T_world_sensor.rotation()).cast<float>();
  write_path_atomically(path, [&](const std::string& temp) {
    save_pcd_binary(temp, cloud, path);
  });
}

}  // namespace fvx::io
