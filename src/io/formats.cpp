// The io helpers that need neither PCL nor OpenCV, so that the fvx binary has them without
// loading fvx-heavy.so (src/heavy/api.hpp).
#include <algorithm>
#include <cmath>

#include "fvx/core/atomic_file.hpp"
#include "fvx/io/cloud_file.hpp"
#include "fvx/io/depth_image.hpp"
#include "fvx/io/visual.hpp"

namespace fvx::io {

bool is_legacy_openni_viewpoint(const Eigen::Isometry3d& T) {
  const Eigen::Matrix3d flip_x = Eigen::Vector3d(1, -1, -1).asDiagonal();
  return T.translation().norm() < 1e-9 && (T.linear() - flip_x).cwiseAbs().maxCoeff() < 1e-6;
}

bool is_depth_image_path(const std::string& path) {
  const std::string ext = lowercase_extension(path);
  return ext == ".png" || ext == ".pgm" || ext == ".tif" || ext == ".tiff";
}

Rgb cluster_color(int id) {
  // Golden-angle hues: neighbouring ids differ, and the same id always gets the same colour.
  // HSV (s = 200, v = 230 of 255) to RGB as OpenCV's 8-bit conversion does it (hue/2 in a
  // byte, rounded half to even), so colours stay those of earlier fvx versions.
  const double hue = std::fmod(id * 137.508, 360.0);
  const int hue_byte = hue < 0 ? 0 : std::min(255, int(std::nearbyint(hue / 2.0)));
  const double h = (hue_byte % 180) * 2.0 / 60.0;
  const double s = 200.0 / 255.0, v = 230.0 / 255.0;
  const int sector = int(std::floor(h));
  const double f = h - sector;
  const double p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  const double table[6][3] = {{v, t, p}, {q, v, p}, {p, v, t}, {p, q, v}, {t, p, v}, {v, p, q}};
  const double* rgb = table[sector % 6];
  const auto byte = [](double x) { return std::uint8_t(std::lround(x * 255.0)); };
  return {byte(rgb[0]), byte(rgb[1]), byte(rgb[2])};
}

}  // namespace fvx::io
