// fvx-heavy.so: the entries of heavy::Api over the PCL and OpenCV implementations in io/ and
// registration/. Only fvx_heavy_api is exported (the module is built with hidden visibility).
#include <new>

#include "api.hpp"
#include "fvx/core/error.hpp"

namespace fvx::heavy {
namespace {

/// Runs `work`, turning what it throws into `failure`.
template <typename Work>
void guarded(Failure& failure, Work&& work) {
  failure = Failure{};
  try {
    work();
  } catch (const FileError& e) {
    failure.kind = Failure::Kind::File;
    failure.path = e.path();
    const std::string what = e.what();
    const std::string prefix = e.path() + ": ";
    failure.message = what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what;
  } catch (const UsageError& e) {
    failure = {Failure::Kind::Usage, e.what(), {}};
  } catch (const Error& e) {
    failure = {Failure::Kind::Error, e.what(), {}};
  } catch (const std::bad_alloc&) {
    failure = {Failure::Kind::OutOfMemory, "out of memory", {}};
  } catch (const std::exception& e) {
    failure = {Failure::Kind::Other, e.what(), {}};
  }
}

const Api kApi = {
    kAbiVersion,
    [](Failure& f, const std::string& path, io::CloudFile& out) {
      guarded(f, [&] { out = io::read_cloud(path); });
    },
    [](Failure& f, const std::string& path, const std::vector<Eigen::Vector3f>& points,
       const Eigen::Isometry3d& T_world_sensor, int width, int height) {
      guarded(f, [&] { io::write_pcd(path, points, T_world_sensor, width, height); });
    },
    [](Failure& f, const std::string& path, io::DepthImage& out) {
      guarded(f, [&] { out = io::read_depth_image(path); });
    },
    [](Failure& f, const std::string& path, const io::DepthImage& depth) {
      guarded(f, [&] { io::write_depth_png(path, depth); });
    },
    [](Failure& f, const std::string& path, const std::vector<Eigen::Vector3f>& points,
       const std::vector<io::Rgb>& colors) { guarded(f, [&] { io::write_colored_cloud(path, points, colors); }); },
    [](Failure& f, const std::string& path, const std::vector<Eigen::Vector3f>& vertices,
       const std::vector<std::array<std::uint32_t, 3>>& triangles, const std::vector<io::Rgb>& colors) {
      guarded(f, [&] { io::write_ply_mesh(path, vertices, triangles, colors); });
    },
    [](Failure& f, const std::string& path, double cell_m, const std::vector<io::PictureLayer>& layers,
       int width_px) { guarded(f, [&] { io::write_top_view_png(path, cell_m, layers, width_px); }); },
    [](Failure& f, const std::string& path, const io::RgbImage& image) {
      guarded(f, [&] { io::write_png(path, image); });
    },
    [](Failure& f, const std::string& path, const std::string& title, const std::string& x_label,
       const std::string& y_label, const std::vector<io::PlotSeries>& series, int width_px, int height_px) {
      guarded(f, [&] { io::write_line_plot_png(path, title, x_label, y_label, series, width_px, height_px); });
    },
    [](Failure& f, const std::vector<Eigen::Vector3d>& points_sensor, const Eigen::Isometry3d& T_world_sensor_prior,
       const std::vector<Eigen::Vector3f>& target_world, const registration::Config& config,
       registration::Result& out) {
      guarded(f, [&] { out = registration::align(points_sensor, T_world_sensor_prior, target_world, config); });
    },
    [](Failure& f, const io::BagQuery& query, std::vector<io::BagMessage>& out) {
      guarded(f, [&] { out = io::index_bag(query); });
    },
    [](Failure& f, const io::BagQuery& query, const io::BagMessage& message, io::BagScan& out) {
      guarded(f, [&] { out = io::read_bag_scan(query, message); });
    },
};

}  // namespace
}  // namespace fvx::heavy

extern "C" __attribute__((visibility("default"))) const fvx::heavy::Api* fvx_heavy_api() {
  return &fvx::heavy::kApi;
}
