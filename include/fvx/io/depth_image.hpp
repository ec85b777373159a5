#pragma once
/// \file
/// 16-bit depth images (PNG, PGM, TIFF) through OpenCV. Raw values are kept; the scale that
/// turns them into metres belongs to the intrinsics (1000 for Kinect/TUM-mm, 5000 for TUM).
#include <cstdint>
#include <string>
#include <vector>

namespace fvx::io {

/// The raw value a saturated or failed pixel holds in some encodings; read as no measurement.
inline constexpr std::uint16_t kDepthSaturated = 65535;

struct DepthImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint16_t> raw;  ///< row-major, 0 and kDepthSaturated = no measurement

  std::uint16_t at(int row, int column) const { return raw[std::size_t(row) * width + column]; }
};

/// Reads a single-channel 16-bit image. Throws FileError for a missing or unreadable file, an
/// 8-bit or colour image, or an empty image.
DepthImage read_depth_image(const std::string& path);

/// Writes a 16-bit single-channel PNG, atomically.
void write_depth_png(const std::string& path, const DepthImage& depth);

/// True when the file extension is one read_depth_image accepts (.png .pgm .tif .tiff).
bool is_depth_image_path(const std::string& path);

}  // namespace fvx::io
