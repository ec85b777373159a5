#include "fvx/capmap/capability_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"
#include "fvx/core/pose.hpp"

namespace fvx::capmap {

ArmConfig arm_config_of(const CapabilityHeader& h) {
  ArmConfig config{h.base_link, h.tip_link};
  const auto& m = h.mount_xyz_rpy;  // metres and radians
  config.T_tip_sensor = pose_from_xyz_rpy(m[0], m[1], m[2], m[3], m[4], m[5]);
  config.viewing_axis_sensor = h.viewing_axis;
  return config;
}

DirectionSet::DirectionSet(int count) {
  FVX_ASSERT(count >= 1, "a direction set needs directions");
  const double golden_angle = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / count;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = i * golden_angle;
    directions_.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
  }
}

int DirectionSet::nearest(const Eigen::Vector3d& d) const {
  int best = 0;
  double best_dot = -2.0;
  for (int i = 0; i < size(); ++i) {
    const double dot = directions_[std::size_t(i)].dot(d);
    if (dot > best_dot) best_dot = dot, best = i;
  }
  return best;
}

std::vector<int> DirectionSet::within(const Eigen::Vector3d& d, double angle_rad) const {
  std::vector<int> out;
  const double min_dot = std::cos(angle_rad);
  for (int i = 0; i < size(); ++i)
    if (directions_[std::size_t(i)].dot(d) >= min_dot) out.push_back(i);
  return out;
}

double DirectionSet::mean_spacing_rad() const { return std::sqrt(4.0 * M_PI / size()); }

CapabilityMap::CapabilityMap(CapabilityHeader header) : header_(std::move(header)), directions_(header_.directions) {
  FVX_ASSERT(header_.voxel_m > 0.0, "voxel size");
  FVX_ASSERT(header_.shard_count >= 1 && header_.shard_index < header_.shard_count, "shard");
}

std::int64_t CapabilityMap::voxel_of(const Eigen::Vector3d& p) const {
  std::int64_t index = 0, stride = 1;
  for (int a = 0; a < 3; ++a) {
    const double c = std::floor((p[a] - header_.origin_m[a]) / header_.voxel_m);
    if (!(c >= 0.0) || c >= double(header_.dims[std::size_t(a)])) return -1;
    index += std::int64_t(c) * stride;
    stride *= std::int64_t(header_.dims[std::size_t(a)]);
  }
  return index;
}

Eigen::Vector3d CapabilityMap::center_of(std::int64_t voxel) const {
  const std::int64_t nx = header_.dims[0], ny = header_.dims[1];
  const Eigen::Vector3d cell(double(voxel % nx), double(voxel / nx % ny), double(voxel / (nx * ny)));
  return header_.origin_m + (cell.array() + 0.5).matrix() * header_.voxel_m;
}

void CapabilityMap::set(std::int64_t voxel, int direction) {
  FVX_ASSERT(voxel >= 0 && direction >= 0 && direction < directions_.size(), "bit out of range");
  auto& words = voxels_[voxel];
  if (words.empty()) words.assign(std::size_t((directions_.size() + 63) / 64), 0);
  words[std::size_t(direction / 64)] |= std::uint64_t(1) << (direction % 64);
}

bool CapabilityMap::reachable(std::int64_t voxel, int direction) const {
  const auto it = voxels_.find(voxel);
  return it != voxels_.end() && (it->second[std::size_t(direction / 64)] >> (direction % 64) & 1u);
}

bool CapabilityMap::reachable(const Eigen::Vector3d& p, const Eigen::Vector3d& d) const {
  const std::int64_t v = voxel_of(p);
  return v >= 0 && reachable(v, directions_.nearest(d));
}

std::vector<int> CapabilityMap::reachable_directions(const Eigen::Vector3d& p) const {
  std::vector<int> out;
  const auto it = voxels_.find(voxel_of(p));
  if (it == voxels_.end()) return out;
  for (int i = 0; i < directions_.size(); ++i)
    if (it->second[std::size_t(i / 64)] >> (i % 64) & 1u) out.push_back(i);
  return out;
}

Eigen::AlignedBox3d CapabilityMap::reachable_box_base() const {
  Eigen::AlignedBox3d box;
  const Eigen::Vector3d half = Eigen::Vector3d::Constant(0.5 * header_.voxel_m);
  for (const auto& [voxel, words] : voxels_)
    if (std::any_of(words.begin(), words.end(), [](std::uint64_t w) { return w != 0; })) {
      box.extend(center_of(voxel) - half);
      box.extend(center_of(voxel) + half);
    }
  return box;
}

std::vector<Eigen::Vector3d> CapabilityMap::reachable_directions(const Eigen::Isometry3d& T_world_base,
                                                                const Eigen::Vector3d& p_world) const {
  std::vector<Eigen::Vector3d> out;
  for (int i : reachable_directions(T_world_base.inverse() * p_world)) out.push_back(T_world_base.linear() * directions_[i]);
  return out;
}

double CapabilityMap::reachability_index(const Eigen::Vector3d& p) const {
  const auto it = voxels_.find(voxel_of(p));
  if (it == voxels_.end()) return 0.0;
  int reachable = 0;  // pruning asks this of every cell with utility: count bits, build nothing
  for (const std::uint64_t word : it->second) reachable += __builtin_popcountll(word);
  return 100.0 * double(reachable) / directions_.size();
}

CapabilityMap CapabilityMap::merge(const std::vector<CapabilityMap>& shards) {
  if (shards.empty()) throw Error("no shards to merge");
  const CapabilityHeader& first = shards.front().header_;
  std::vector<bool> seen(first.shard_count, false);
  CapabilityHeader joined = first;
  joined.shard_index = 0;
  joined.shard_count = 1;
  CapabilityMap out(joined);
  for (const CapabilityMap& shard : shards) {
    const CapabilityHeader& b = shard.header_;
    if (first.urdf_hash != b.urdf_hash || first.base_link != b.base_link || first.tip_link != b.tip_link ||
        first.mount_xyz_rpy != b.mount_xyz_rpy || first.voxel_m != b.voxel_m || first.origin_m != b.origin_m ||
        first.dims != b.dims || first.directions != b.directions || first.seed != b.seed ||
        first.method != b.method || first.shard_count != b.shard_count ||
        first.position_tolerance_m != b.position_tolerance_m || first.angle_tolerance_rad != b.angle_tolerance_rad)
      throw Error("the shards were not made from the same arm and settings; they cannot be merged");
    if (seen[b.shard_index]) throw Error("shard " + std::to_string(b.shard_index + 1) + " is given twice");
    seen[b.shard_index] = true;
    for (const auto& [voxel, words] : shard.voxels_) {
      auto& mine = out.voxels_[voxel];
      if (mine.empty()) mine.assign(words.size(), 0);
      for (std::size_t w = 0; w < words.size(); ++w) mine[w] |= words[w];
    }
  }
  for (std::uint32_t i = 0; i < first.shard_count; ++i)
    if (!seen[i]) throw Error("shard " + std::to_string(i + 1) + " of " + std::to_string(first.shard_count) + " is missing");
  return out;
}

namespace {

constexpr char kMagic[8] = {'F', 'V', 'X', 'C', 'M', 'A', 'P', '\n'};
/// Version 2 names the bit definition in the header's `method` (fk-witness maps are new in
/// it: an older fvx must not read them as centre bits) and checksums with FNV-1a's own
/// offset basis; version 1 files (IK at the voxel centre) are still read.
constexpr std::uint32_t kVersion = 2;
constexpr std::uint64_t kFnvBasis = 14695981039346656037ull;
constexpr std::uint64_t kFnvBasisVersion1 = 1469598103934665603ull;  ///< a digit short: version 1's

std::uint64_t fnv1a(const std::string& bytes, std::uint64_t basis) {
  std::uint64_t h = basis;
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  return h;
}

template <typename T>
void put(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));  // little-endian hosts only (x86-64, arm64)
  out.append(bytes, sizeof(T));
}

nlohmann::ordered_json header_json(const CapabilityHeader& h) {
  return {{"base_link", h.base_link},
          {"tip_link", h.tip_link},
          {"mount_xyz_rpy", h.mount_xyz_rpy},
          {"viewing_axis", {h.viewing_axis.x(), h.viewing_axis.y(), h.viewing_axis.z()}},
          {"urdf_hash", h.urdf_hash},
          {"voxel_m", h.voxel_m},
          {"origin_m", {h.origin_m.x(), h.origin_m.y(), h.origin_m.z()}},
          {"dims", h.dims},
          {"directions", h.directions},
          {"direction_set", "golden-angle spiral"},
          {"position_tolerance_m", h.position_tolerance_m},
          {"angle_tolerance_rad", h.angle_tolerance_rad},
          {"method", h.method},
          {"seed", h.seed},
          {"shard_index", h.shard_index},
          {"shard_count", h.shard_count},
          {"fvx_version", h.fvx_version}};
}

/// Reads little-endian values from the bytes of a file, refusing to run past its end.
struct Reader {
  const std::string& bytes;
  std::size_t at = 0;
  const std::string& path;
  template <typename T>
  T get() {
    if (at + sizeof(T) > bytes.size()) throw FileError(path, "truncated capability map");
    T value;
    std::memcpy(&value, bytes.data() + at, sizeof(T));
    at += sizeof(T);
    return value;
  }
};

}  // namespace

void CapabilityMap::save(const std::string& path) const {
  if (lowercase_extension(path) != ".fcm") throw FileError(path, "capability maps are written as .fcm");
  std::string out(kMagic, sizeof kMagic);
  put<std::uint32_t>(out, kVersion);
  const std::string header = header_json(header_).dump();
  put<std::uint32_t>(out, std::uint32_t(header.size()));
  out += header;
  put<std::uint64_t>(out, voxels_.size());
  for (const auto& [voxel, words] : voxels_) {
    put<std::int64_t>(out, voxel);
    std::uint16_t count = 0;
    for (std::uint64_t w : words) count = std::uint16_t(count + __builtin_popcountll(w));
    put<std::uint16_t>(out, count);
    for (std::uint64_t w : words) put<std::uint64_t>(out, w);
  }
  put<std::uint64_t>(out, fnv1a(out, kFnvBasis));
  write_file_atomically(path, [&](std::ostream& s) { s.write(out.data(), std::streamsize(out.size())); });
}

namespace {

/// The header's numbers within what fvx builds, before anything is sized by them: a lying
/// header (2e9 directions, dims whose product overflows) must not allocate or overflow.
void check_header_values(const CapabilityHeader& h, const std::string& path) {
  const auto bad = [&](const std::string& what) { throw FileError(path, "bad capability-map header: " + what); };
  if (!(h.voxel_m > 0) || !std::isfinite(h.voxel_m) || !h.origin_m.allFinite()) bad("voxel_m or origin_m is not a finite size");
  if (h.directions < 1 || h.directions > 4096) bad("directions " + std::to_string(h.directions) + ", expected 1 to 4096");
  for (const std::uint32_t d : h.dims)
    if (d < 1 || d > (1u << 20)) bad("dims " + std::to_string(d) + ", expected 1 to 2^20 voxels per axis");
  if (double(h.dims[0]) * h.dims[1] * h.dims[2] > double(std::int64_t(1) << 40)) bad("dims hold more than 2^40 voxels");
  if (!(h.position_tolerance_m > 0) || !(h.angle_tolerance_rad >= 0 && h.angle_tolerance_rad < M_PI))
    bad("a tolerance out of range");
  if (h.shard_count < 1 || h.shard_index >= h.shard_count) bad("shard_index is not below shard_count");
}

}  // namespace

CapabilityMap CapabilityMap::load(const std::string& path) {
  require_readable_file(path);
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw FileError(path, "not an fvx capability map (.fcm)");
  if (bytes.size() < sizeof kMagic + 8 + 8) throw FileError(path, "truncated capability map");
  std::uint64_t stored;
  std::memcpy(&stored, bytes.data() + bytes.size() - 8, 8);
  const std::string body = bytes.substr(0, bytes.size() - 8);
  Reader r{body, sizeof kMagic, path};
  const auto version = r.get<std::uint32_t>();
  if (version != 1 && version != kVersion)
    throw FileError(path, "capability map format version " + std::to_string(version) + "; this fvx reads versions 1 to " +
                              std::to_string(kVersion));
  if (fnv1a(body, version == 1 ? kFnvBasisVersion1 : kFnvBasis) != stored)
    throw FileError(path, "checksum mismatch: the capability map is corrupt or truncated");
  const auto header_size = r.get<std::uint32_t>();
  if (r.at + header_size > body.size()) throw FileError(path, "truncated capability map");
  CapabilityHeader h;
  try {
    const auto j = nlohmann::json::parse(body.substr(r.at, header_size));
    h.base_link = j.at("base_link");
    h.tip_link = j.at("tip_link");
    h.mount_xyz_rpy = j.at("mount_xyz_rpy");
    const auto axis = j.at("viewing_axis").get<std::vector<double>>();
    h.viewing_axis = Eigen::Vector3d(axis.at(0), axis.at(1), axis.at(2));
    h.urdf_hash = j.at("urdf_hash");
    h.voxel_m = j.at("voxel_m");
    const auto origin = j.at("origin_m").get<std::vector<double>>();
    h.origin_m = Eigen::Vector3d(origin.at(0), origin.at(1), origin.at(2));
    h.dims = j.at("dims");
    h.directions = j.at("directions");
    h.position_tolerance_m = j.at("position_tolerance_m");
    h.angle_tolerance_rad = j.at("angle_tolerance_rad");
    h.method = j.at("method");
    h.seed = j.at("seed");
    h.shard_index = j.at("shard_index");
    h.shard_count = j.at("shard_count");
    h.fvx_version = j.at("fvx_version");
  } catch (const nlohmann::json::exception& e) {
    throw FileError(path, std::string("bad capability-map header: ") + e.what());
  }
  check_header_values(h, path);
  if (h.method != "fk-witness" && h.method != "fk-seeded-ik" && h.method != "exhaustive-ik")
    throw FileError(path, "unknown bit definition '" + h.method + "' (method); this fvx reads fk-witness, "
                          "fk-seeded-ik and exhaustive-ik maps");
  if (version == 1 && h.method == "fk-witness") throw FileError(path, "an fk-witness map must be format version 2");
  r.at += header_size;
  CapabilityMap map(h);
  const auto count = r.get<std::uint64_t>();
  const std::size_t words = std::size_t((h.directions + 63) / 64);
  const std::int64_t voxels = std::int64_t(h.dims[0]) * h.dims[1] * h.dims[2];
  for (std::uint64_t i = 0; i < count; ++i) {
    const auto voxel = r.get<std::int64_t>();
    if (voxel < 0 || voxel >= voxels) throw FileError(path, "a voxel index lies outside the grid");
    r.get<std::uint16_t>();  // the reachability count, derived from the bits
    auto& bits = map.voxels_[voxel];
    bits.resize(words);
    for (auto& w : bits) w = r.get<std::uint64_t>();
    if (h.directions % 64 && bits.back() >> (h.directions % 64))
      throw FileError(path, "a voxel has bits beyond its " + std::to_string(h.directions) + " directions");
  }
  if (r.at != body.size()) throw FileError(path, "trailing bytes after the voxel list");
  return map;
}

}  // namespace fvx::capmap
