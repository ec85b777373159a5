// The fvx binary's side of fvx-heavy.so: finds and loads the module on the first call that
// needs PCL or OpenCV, and defines the io/ and registration/ functions that live there as
// calls through its table (api.hpp says why).
#include <dlfcn.h>
#include <unistd.h>

#include <climits>
#include <cstdlib>
#include <mutex>
#include <string>
#include <vector>

#include "api.hpp"
#include "fvx/core/error.hpp"

namespace fvx::heavy {
namespace {

std::string executable_folder() {
  char buffer[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", buffer, sizeof buffer - 1);
  if (n <= 0) return {};
  const std::string exe(buffer, std::size_t(n));
  return exe.substr(0, exe.find_last_of('/'));
}

/// Where the module may be, in order: $FVX_HEAVY (a path to the file), beside the binary
/// (the build tree), ../lib/fvx/ from the binary (an installed tree), and where this build
/// put it (test programs in other folders of the build tree).
std::vector<std::string> candidates() {
  std::vector<std::string> paths;
  if (const char* env = std::getenv("FVX_HEAVY"); env && *env) return {env};
  const std::string folder = executable_folder();
  if (!folder.empty()) {
    paths.push_back(folder + "/" + kModuleName);
    paths.push_back(folder + "/../lib/fvx/" + kModuleName);
  }
  paths.push_back(FVX_HEAVY_BUILD_PATH);
  return paths;
}

const Api* load() {
  std::string tried;
  for (const std::string& path : candidates()) {
    if (::access(path.c_str(), R_OK) != 0) {
      tried += (tried.empty() ? "" : ", ") + path;
      continue;
    }
    void* module = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!module) throw Error("cannot load " + path + " (fvx's PCL and OpenCV part): " + ::dlerror());
    auto* entry = reinterpret_cast<ApiFunction*>(::dlsym(module, kApiSymbol));
    const Api* api = entry ? entry() : nullptr;
    if (!api || api->abi_version != kAbiVersion)
      throw Error(path + " is from another fvx build; reinstall fvx (module and binary together)");
    return api;
  }
  throw Error("cannot find " + std::string(kModuleName) +
              " (fvx's PCL and OpenCV part, needed for point clouds, depth images, pictures "
              "and registration); looked at " + tried + "; set FVX_HEAVY to its path");
}

const Api& api() {
  static std::once_flag once;
  static const Api* loaded = nullptr;
  std::call_once(once, [] { loaded = load(); });
  return *loaded;
}

void rethrow(const Failure& f) {
  switch (f.kind) {
    case Failure::Kind::None: return;
    case Failure::Kind::File: throw FileError(f.path, f.message);
    case Failure::Kind::Usage: throw UsageError(f.message);
    case Failure::Kind::OutOfMemory: throw std::bad_alloc();
    case Failure::Kind::Error: throw Error(f.message);
    case Failure::Kind::Other: throw Error("unexpected error: " + f.message);
  }
}

/// Calls entry `member` of the table and rethrows what it reported.
template <auto member, typename... Args>
void call(Args&&... args) {
  Failure failure;
  (api().*member)(failure, std::forward<Args>(args)...);
  rethrow(failure);
}

}  // namespace
}  // namespace fvx::heavy

namespace fvx::io {
using heavy::Api;
using heavy::call;

CloudFile read_cloud(const std::string& path) {
  CloudFile out;
  call<&Api::read_cloud>(path, out);
  return out;
}

void write_pcd(const std::string& path, const std::vector<Eigen::Vector3f>& points,
               const Eigen::Isometry3d& T_world_sensor, int width, int height) {
  call<&Api::write_pcd>(path, points, T_world_sensor, width, height);
}

DepthImage read_depth_image(const std::string& path) {
  DepthImage out;
  call<&Api::read_depth_image>(path, out);
  return out;
}

void write_depth_png(const std::string& path, const DepthImage& depth) {
  call<&Api::write_depth_png>(path, depth);
}

void write_colored_cloud(const std::string& path, const std::vector<Eigen::Vector3f>& points,
                         const std::vector<Rgb>& colors) {
  call<&Api::write_colored_cloud>(path, points, colors);
}

void write_ply_mesh(const std::string& path, const std::vector<Eigen::Vector3f>& vertices,
                    const std::vector<std::array<std::uint32_t, 3>>& triangles, const std::vector<Rgb>& colors) {
  call<&Api::write_ply_mesh>(path, vertices, triangles, colors);
}

void write_top_view_png(const std::string& path, double cell_m, const std::vector<PictureLayer>& layers,
                        int width_px) {
  call<&Api::write_top_view_png>(path, cell_m, layers, width_px);
}

void write_png(const std::string& path, const RgbImage& image) { call<&Api::write_png>(path, image); }

void write_line_plot_png(const std::string& path, const std::string& title, const std::string& x_label,
                         const std::string& y_label, const std::vector<PlotSeries>& series, int width_px,
                         int height_px) {
  call<&Api::write_line_plot_png>(path, title, x_label, y_label, series, width_px, height_px);
}

std::vector<BagMessage> index_bag(const BagQuery& query) {
  std::vector<BagMessage> out;
  call<&Api::index_bag>(query, out);
  return out;
}

BagScan read_bag_scan(const BagQuery& query, const BagMessage& message) {
  BagScan out;
  call<&Api::read_bag_scan>(query, message, out);
  return out;
}

}  // namespace fvx::io

namespace fvx::registration {

Result align(const std::vector<Eigen::Vector3d>& points_sensor, const Eigen::Isometry3d& T_world_sensor_prior,
             const std::vector<Eigen::Vector3f>& target_world, const Config& config) {
  Result out;
  heavy::call<&heavy::Api::align>(points_sensor, T_world_sensor_prior, target_world, config, out);
  return out;
}

}  // namespace fvx::registration
