#include "fvx/io/intrinsics.hpp"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"
#include "fvx/core/parse.hpp"

namespace fvx::io {

std::vector<std::string> Intrinsics::validate() const {
  std::vector<std::string> problems;
  // The command line's limits hold for files too: a sensor file of width 1e9 must not size
  // an image.
  auto focal = [&](double f, const char* name) {
    if (!std::isfinite(f) || std::abs(f) < 1e-6 || std::abs(f) > kMaxPixels)
      problems.push_back(std::string(name) + " must be a non-zero focal length within ±1e6 pixels");
  };
  focal(fx, "fx");
  focal(fy, "fy");
  if (!(std::abs(cx) <= kMaxPixels) || !(std::abs(cy) <= kMaxPixels)) problems.push_back("cx and cy must be within ±1e6 pixels");
  if (!(depth_scale > 0.0 && depth_scale <= kMaxPixels))
    problems.push_back("depth_scale must be in (0, 1e6] (raw units per metre, e.g. 1000 or 5000)");
  if (width < 1 || height < 1 || width > kMaxImageSidePx || height > kMaxImageSidePx)
    problems.push_back("width and height must be 1 to 16384 pixels");
  return problems;
}

namespace {

constexpr std::size_t kMaxMatrixTextBytes = 4096;  ///< a 4x4 matrix in text is a few hundred bytes

double number(const nlohmann::json& j, const char* key, const std::string& path) {
  if (!j.contains(key)) throw FileError(path, std::string("missing key '") + key + "'");
  if (!j.at(key).is_number()) throw FileError(path, std::string("'") + key + "' must be a number");
  return j.at(key).get<double>();
}

nlohmann::json read_json_object(const std::string& path) {
  require_readable_file(path);
  std::ifstream in(path);
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw FileError(path, std::string("not valid JSON: ") + e.what());
  }
  if (!j.is_object()) throw FileError(path, "expected a JSON object");
  return j;
}

Intrinsics intrinsics_from_json(const nlohmann::json& j, const std::string& path) {
  Intrinsics k;
  if (j.contains("intrinsic_matrix")) {  // Open3D layout, column-major
    const std::set<std::string> known = {"width", "height", "intrinsic_matrix"};
    for (const auto& item : j.items())
      if (!known.count(item.key())) throw FileError(path, "unknown key '" + item.key() + "'");
    const auto& m = j.at("intrinsic_matrix");
    if (!m.is_array() || m.size() != 9 || !std::all_of(m.begin(), m.end(), [](const auto& v) { return v.is_number(); }))
      throw FileError(path, "'intrinsic_matrix' must be 9 numbers (column-major 3x3)");
    k.fx = m[0].get<double>();
    k.fy = m[4].get<double>();
    k.cx = m[6].get<double>();
    k.cy = m[7].get<double>();
  } else {
    const std::set<std::string> known = {"fx", "fy", "cx", "cy", "depth_scale", "width", "height"};
    for (const auto& item : j.items())
      if (!known.count(item.key())) throw FileError(path, "unknown key '" + item.key() + "'");
    k.fx = number(j, "fx", path);
    k.fy = number(j, "fy", path);
    k.cx = number(j, "cx", path);
    k.cy = number(j, "cy", path);
    if (j.contains("depth_scale")) k.depth_scale = number(j, "depth_scale", path);
  }
  for (const auto& [key, field] : {std::pair{"width", &k.width}, {"height", &k.height}}) {
    if (!j.contains(key)) continue;
    const double v = number(j, key, path);  // checked before the conversion: 1e30 is no int
    if (!(v == std::floor(v) && v >= 1 && v <= kMaxImageSidePx)) throw FileError(path, std::string("'") + key + "' must be 1 to 16384 pixels");
    *field = int(v);
  }
  k.size_stated = j.contains("width") && j.contains("height");
  const auto problems = k.validate();
  if (!problems.empty()) throw FileError(path, join_problems(problems));
  return k;
}

/// A text file of 9 numbers (a 3x3 K: 3DMatch's camera-intrinsics.txt) or 16 (a 4x4 with K
/// top left: ScanNet's intrinsic_depth.txt), row-major, without skew.
Intrinsics intrinsics_from_matrix_text(const std::string& text, const std::string& path) {
  std::vector<double> v;
  for (const std::string& token : split_whitespace(text)) {
    if (v.size() == 16) throw FileError(path, "expected a 3x3 or 4x4 intrinsic matrix: more than 16 numbers");
    try {
      v.push_back(parse_double(token, path));
    } catch (const UsageError& e) {
      throw Error(e.what());  // names the file
    }
  }
  if (v.size() != 9 && v.size() != 16)
    throw FileError(path, "expected a 3x3 or 4x4 intrinsic matrix (9 or 16 numbers), got " + std::to_string(v.size()));
  const std::size_t n = v.size() == 9 ? 3 : 4;
  auto at = [&](std::size_t r, std::size_t c) { return v[r * n + c]; };
  bool pinhole = at(0, 1) == 0 && at(1, 0) == 0 && at(2, 0) == 0 && at(2, 1) == 0 && at(2, 2) == 1;
  if (n == 4) pinhole = pinhole && at(0, 3) == 0 && at(1, 3) == 0 && at(2, 3) == 0 && at(3, 0) == 0 && at(3, 1) == 0 &&
                        at(3, 2) == 0 && at(3, 3) == 1;
  if (!pinhole)
    throw FileError(path, "not a pinhole matrix: expected fx 0 cx / 0 fy cy / 0 0 1 (no skew; a 4x4 with 0 0 0 1 around it)");
  Intrinsics k;
  k.fx = at(0, 0);
  k.fy = at(1, 1);
  k.cx = at(0, 2);
  k.cy = at(1, 2);
  const auto problems = k.validate();
  if (!problems.empty()) throw FileError(path, join_problems(problems));
  return k;
}

}  // namespace

Intrinsics read_intrinsics(const std::string& path) {
  require_readable_file(path);
  std::ifstream in(path, std::ios::binary);
  std::string text(kMaxMatrixTextBytes + 1, '\0');
  in.read(text.data(), std::streamsize(text.size()));
  text.resize(std::size_t(in.gcount()));
  const auto first = text.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && text[first] == '{') return intrinsics_from_json(read_json_object(path), path);
  if (text.size() > kMaxMatrixTextBytes) throw FileError(path, "neither JSON nor a 3x3 or 4x4 intrinsic matrix (too long)");
  return intrinsics_from_matrix_text(text, path);
}

std::vector<std::string> DepthCamera::validate() const {
  std::vector<std::string> problems = intrinsics.validate();
  if (!std::isfinite(depth_min_m) || depth_min_m < 0.0) problems.push_back("depth_min_m must be >= 0 m");
  if (!(depth_max_m > depth_min_m && depth_max_m <= kMaxDepthM))
    problems.push_back("depth_max_m must be greater than depth_min_m and at most 1000 m");
  return problems;
}

DepthCamera read_depth_camera(const std::string& path) {
  nlohmann::json j = read_json_object(path);
  DepthCamera camera;
  for (const char* key : {"depth_min_m", "depth_max_m"}) {
    if (!j.contains(key)) continue;
    if (!j.at(key).is_number()) throw FileError(path, std::string("'") + key + "' must be a number");
    (std::string(key) == "depth_min_m" ? camera.depth_min_m : camera.depth_max_m) = j.at(key).get<double>();
    j.erase(key);
  }
  camera.intrinsics = intrinsics_from_json(j, path);
  const auto problems = camera.validate();
  if (!problems.empty()) throw FileError(path, join_problems(problems));
  return camera;
}

}  // namespace fvx::io

namespace fvx::io {

Json intrinsics_json(const Intrinsics& K) {
  return {{"fx", K.fx}, {"fy", K.fy}, {"cx", K.cx}, {"cy", K.cy},
          {"depth_scale", K.depth_scale}, {"width", K.width}, {"height", K.height}};
}

Json camera_json(const DepthCamera& camera) {
  return {{"intrinsics", intrinsics_json(camera.intrinsics)},
          {"depth_min_m", camera.depth_min_m},
          {"depth_max_m", camera.depth_max_m}};
}

}  // namespace fvx::io
