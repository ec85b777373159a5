#pragma once
/// \file
/// The table of functions that fvx-heavy.so (the part of fvx that needs PCL and OpenCV)
/// hands to the fvx binary. PCL's and OpenCV's libraries pull in some 190 shared objects
/// whose loading took 0.2 s of every command's start; loading them on first use lets
/// `fvx nbv`, `frontiers`, `voids` and `capmap` start in milliseconds.
///
/// Errors do not cross the boundary as exceptions: each entry catches inside the module and
/// returns a Failure that the loader rethrows as the same fvx error kind.
#include <string>
#include <vector>

#include "fvx/io/cloud_file.hpp"
#include "fvx/io/depth_image.hpp"
#include "fvx/io/rosbag.hpp"
#include "fvx/io/visual.hpp"
#include "fvx/registration/registration.hpp"

namespace fvx::heavy {

/// What an entry threw, if anything.
struct Failure {
  enum class Kind { None, Usage, File, Error, OutOfMemory, Other };
  Kind kind = Kind::None;
  std::string message;  ///< what(); for File, the problem without the path
  std::string path;     ///< FileError::path()
};

/// Bumped whenever an entry's signature or a type it passes changes.
constexpr int kAbiVersion = 3;

struct Api {
  int abi_version;
  void (*read_cloud)(Failure&, const std::string& path, io::CloudFile& out);
  void (*write_pcd)(Failure&, const std::string& path, const std::vector<Eigen::Vector3f>& points,
                    const Eigen::Isometry3d& T_world_sensor, int width, int height);
  void (*read_depth_image)(Failure&, const std::string& path, io::DepthImage& out);
  void (*write_depth_png)(Failure&, const std::string& path, const io::DepthImage& depth);
  void (*write_colored_cloud)(Failure&, const std::string& path, const std::vector<Eigen::Vector3f>& points,
                              const std::vector<io::Rgb>& colors);
  void (*write_ply_mesh)(Failure&, const std::string& path, const std::vector<Eigen::Vector3f>& vertices,
                         const std::vector<std::array<std::uint32_t, 3>>& triangles,
                         const std::vector<io::Rgb>& colors);
  void (*write_top_view_png)(Failure&, const std::string& path, double cell_m,
                             const std::vector<io::PictureLayer>& layers, int width_px);
  void (*write_png)(Failure&, const std::string& path, const io::RgbImage& image);
  void (*write_line_plot_png)(Failure&, const std::string& path, const std::string& title,
                              const std::string& x_label, const std::string& y_label,
                              const std::vector<io::PlotSeries>& series, int width_px, int height_px);
  void (*align)(Failure&, const std::vector<Eigen::Vector3d>& points_sensor,
                const Eigen::Isometry3d& T_world_sensor_prior, const std::vector<Eigen::Vector3f>& target_world,
                const registration::Config& config, registration::Result& out);
  void (*index_bag)(Failure&, const io::BagQuery& query, std::vector<io::BagMessage>& out);
  void (*read_bag_scan)(Failure&, const io::BagQuery& query, const io::BagMessage& message, io::BagScan& out);
};

/// The module's one exported symbol.
extern "C" using ApiFunction = const Api* ();
constexpr const char* kApiSymbol = "fvx_heavy_api";
constexpr const char* kModuleName = "fvx-heavy.so";

}  // namespace fvx::heavy
