#include "fvx/io/image_header.hpp"

#include <cctype>
#include <algorithm>
#include <cstdint>
#include <fstream>
#include <string>

#include "fvx/core/error.hpp"
#include "fvx/io/intrinsics.hpp"

namespace fvx::io {
namespace {

/// `count` bytes of the file from `offset`, or fewer where the file ends.
std::string bytes_at(const std::string& path, std::uint64_t offset, std::size_t count) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path, "cannot open the image");
  in.seekg(std::streamoff(offset));
  std::string bytes(count, '\0');
  if (in) in.read(bytes.data(), std::streamsize(count));
  bytes.resize(in ? count : std::size_t(std::max<std::streamsize>(in.gcount(), 0)));
  return bytes;
}

std::uint32_t big_endian(const std::string& b, std::size_t at, int bytes) {
  std::uint32_t v = 0;
  for (int i = 0; i < bytes; ++i) v = (v << 8) | std::uint8_t(b[at + std::size_t(i)]);
  return v;
}

std::uint32_t in_order(const std::string& b, std::size_t at, int bytes, bool little) {
  if (!little) return big_endian(b, at, bytes);
  std::uint32_t v = 0;
  for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | std::uint8_t(b[at + std::size_t(i)]);
  return v;
}

ImageHeader png_header(const std::string& path, const std::string& b) {
  // Signature (8), then the IHDR chunk: length (4), "IHDR", width (4), height (4).
  if (b.size() < 24 || b.compare(12, 4, "IHDR") != 0) throw FileError(path, "PNG header cut short or without IHDR");
  return {"PNG", big_endian(b, 16, 4), big_endian(b, 20, 4)};
}

/// PGM (P5 binary, P2 ascii): magic, width, height, maxval, separated by whitespace and
/// '#' comments to the end of the line.
ImageHeader pgm_header(const std::string& path, const std::string& b) {
  std::size_t at = 2;
  long long values[2] = {0, 0};
  for (long long& value : values) {
    while (at < b.size() && (std::isspace(static_cast<unsigned char>(b[at])) || b[at] == '#'))
      at = b[at] == '#' ? b.find('\n', at) : at + 1;
    if (at >= b.size() || !std::isdigit(static_cast<unsigned char>(b[at])))
      throw FileError(path, "PGM header without a width and a height");
    for (; at < b.size() && std::isdigit(static_cast<unsigned char>(b[at])) && value <= kMaxImagePixels; ++at)
      value = value * 10 + (b[at] - '0');
  }
  return {"PGM", values[0], values[1]};
}

/// TIFF: byte order, 42, the first directory's offset (writers often put it after the
/// pixels); ImageWidth (256) and ImageLength (257) as SHORT or LONG entries of it.
ImageHeader tiff_header(const std::string& path, const std::string& b) {
  const bool little = b[0] == 'I';
  const std::uint32_t offset = in_order(b, 4, 4, little);
  const std::string count = bytes_at(path, offset, 2);
  if (count.size() < 2) throw FileError(path, "TIFF directory offset " + std::to_string(offset) + " is past the end");
  const std::uint32_t entries = in_order(count, 0, 2, little);
  const std::string ifd = bytes_at(path, std::uint64_t(offset) + 2, 12 * std::size_t(entries));
  ImageHeader h{"TIFF", 0, 0};
  for (std::size_t at = 0; at + 12 <= ifd.size(); at += 12) {
    const std::uint32_t tag = in_order(ifd, at, 2, little), type = in_order(ifd, at + 2, 2, little);
    const std::uint32_t value = type == 3 ? in_order(ifd, at + 8, 2, little) : in_order(ifd, at + 8, 4, little);
    if (tag == 256) h.width = value;
    if (tag == 257) h.height = value;
  }
  return h;
}

}  // namespace

ImageHeader check_image_header(const std::string& path) {
  const std::string b = bytes_at(path, 0, 4096);  // a PGM's comments may be long
  ImageHeader h;
  if (b.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0)
    h = png_header(path, b);
  else if (b.size() >= 3 && b[0] == 'P' && (b[1] == '5' || b[1] == '2'))
    h = pgm_header(path, b);
  else if (b.size() >= 8 && (b.compare(0, 4, "II*\0", 4) == 0 || b.compare(0, 4, "MM\0*", 4) == 0))
    h = tiff_header(path, b);
  else
    throw FileError(path, "not a PNG, PGM or TIFF image (depth images are 16-bit PNG, PGM or TIFF)");
  for (const auto& [side, value] : {std::pair{"width", h.width}, {"height", h.height}})
    if (value < 1 || value > kMaxImageSidePx)
      throw FileError(path, h.format + " " + side + " " + std::to_string(value) + " is not 1 to " +
                                std::to_string(kMaxImageSidePx) + " pixels");
  if (h.width * h.height > kMaxImagePixels)
    throw FileError(path, h.format + " of " + std::to_string(h.width) + "x" + std::to_string(h.height) +
                              " pixels is larger than 2^26 pixels");
  return h;
}

}  // namespace fvx::io
