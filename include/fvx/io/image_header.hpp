#pragma once
/// \file
/// What a depth image's header declares, read before OpenCV decodes it: OpenCV allocates
/// the width × height the header claims (up to 2^30 pixels) before it reads a pixel, so a
/// 40-byte PNG can ask for gigabytes. Only the three encodings fvx reads are accepted.
#include <string>

namespace fvx::io {

/// The most pixels a depth image may have (2^26: 128 MB of 16-bit depth; a 4K sensor has 2^23).
inline constexpr long long kMaxImagePixels = 1LL << 26;

struct ImageHeader {
  std::string format;   ///< "PNG", "PGM" or "TIFF"
  long long width = 0;  ///< pixels, as the header says
  long long height = 0;
};

/// Reads the size from a PNG's IHDR, a binary or ascii PGM's header or a TIFF's first
/// directory, without decoding. Throws FileError for a file of another kind, a header cut
/// short or malformed, a side of 0 or over kMaxImageSidePx, or more than kMaxImagePixels.
ImageHeader check_image_header(const std::string& path);

}  // namespace fvx::io
