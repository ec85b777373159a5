// The capability map's file (.fcm), format in man/fvx-capmap.5.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "fvx/capmap/build.hpp"  // kWitnessRound
#include "fvx/capmap/capability_map.hpp"
#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"

namespace fvx::capmap {

namespace {

constexpr char kMagic[8] = {'F', 'V', 'X', 'C', 'M', 'A', 'P', '\n'};
/// Version 2 names the bit definition in the header's `method` (fk-witness maps are new in
/// it: an older fvx must not read them as centre bits) and checksums with FNV-1a's own
/// offset basis; version 1 files (IK at the voxel centre) are still read. Version 3 is the
/// turn layout (witnesses instead of bits): an fvx that reads only 1 and 2 refuses it by its
/// version ("format version 3; this fvx reads versions 1 to 2"). Grid maps stay version 2.
/// Version 4 is a samples shard (rounds of witnesses instead of bits): an older fvx must not
/// merge it as a z-slab.
constexpr std::uint32_t kGridVersion = 2, kTurnVersion = 3, kSamplesVersion = 4;
/// Painting steps a file may ask for: one witness (65 536: 5 000 voxels from the axis), and all
/// of them: 2^24, or 4 096 per witness on average (the youBot at 1.25 cm takes about 300), so
/// that a small corrupt file cannot ask for minutes.
constexpr double kMaxStepsPerWitness = 65536, kMinStepBudget = double(1 << 24), kStepsPerWitness = 4096;
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

nlohmann::ordered_json turn_json(const TurnFrame& f) {
  const auto xyz = [](const Eigen::Vector3d& v) { return std::vector<double>{v.x(), v.y(), v.z()}; };
  return {{"point_m", xyz(f.point_base)}, {"axis", xyz(f.axis_base)},       {"x_axis", xyz(f.x_base)},
          {"limits_rad", {f.lower_rad, f.upper_rad}}, {"cell_m", f.cell_m}, {"relative_directions", f.relative_directions}};
}

Eigen::Vector3d vector3(const nlohmann::json& j) {
  const auto v = j.get<std::vector<double>>();
  return Eigen::Vector3d(v.at(0), v.at(1), v.at(2));
}

TurnFrame turn_from_json(const nlohmann::json& j) {
  TurnFrame f;
  f.point_base = vector3(j.at("point_m"));
  f.axis_base = vector3(j.at("axis"));
  f.x_base = vector3(j.at("x_axis"));
  const auto limits = j.at("limits_rad").get<std::vector<double>>();
  f.lower_rad = limits.at(0);
  f.upper_rad = limits.at(1);
  f.cell_m = j.at("cell_m");
  f.relative_directions = j.at("relative_directions");
  return f;
}

/// LEB128: 7 bits a byte, low first, the high bit set on every byte but the last.
void put_varint(std::string& out, std::uint64_t value) {
  for (; value >= 0x80; value >>= 7) out.push_back(char((value & 0x7f) | 0x80));
  out.push_back(char(value));
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
  /// A varint (put_varint) that ends before `end` and fits 63 bits.
  std::uint64_t varint(std::size_t end) {
    std::uint64_t value = 0;
    for (int shift = 0; shift < 63; shift += 7) {
      if (at >= end) throw FileError(path, "a round's bits run past its bytes");
      const auto byte = std::uint8_t(bytes[at++]);
      value |= std::uint64_t(byte & 0x7f) << shift;
      if (!(byte & 0x80)) return value;
    }
    throw FileError(path, "a round's bits hold a number of more than 63 bits");
  }
};

}  // namespace

void CapabilityMap::save(const std::string& path) const {
  if (lowercase_extension(path) != ".fcm") throw FileError(path, "capability maps are written as .fcm");
  std::string out(kMagic, sizeof kMagic);
  const bool turn = header_.layout == "turn", samples = header_.shard_split == "samples";
  put<std::uint32_t>(out, turn ? kTurnVersion : samples ? kSamplesVersion : kGridVersion);
  nlohmann::ordered_json header = header_json(header_);
  if (turn) header["layout"] = "turn", header["turn"] = turn_json(header_.turn);
  if (samples)
    header["shard_split"] = "samples", header["target_recall"] = header_.target_recall,
    header["fk_samples"] = header_.fk_samples;
  const std::string header_text = header.dump();
  put<std::uint32_t>(out, std::uint32_t(header_text.size()));
  out += header_text;
  if (samples) {
    put<std::uint64_t>(out, sample_rounds_.size());
    for (const SampleRound& r : sample_rounds_) {
      put<std::uint64_t>(out, r.samples), put<std::uint64_t>(out, r.known), put<std::uint64_t>(out, r.fresh.size());
      std::string entries;  // the gap to the bit before minus one, and the count minus one, as varints
      std::int64_t previous = -1;
      for (const auto& [bit, count] : r.fresh) {
        put_varint(entries, std::uint64_t(bit - previous - 1)), put_varint(entries, count - 1u);
        previous = bit;
      }
      put<std::uint64_t>(out, entries.size());
      out += entries;
    }
    put<std::uint64_t>(out, fnv1a(out, kFnvBasis));
    write_file_atomically(path, [&](std::ostream& s) { s.write(out.data(), std::streamsize(out.size())); });
    return;
  }
  if (turn) {
    put<std::uint64_t>(out, turn_witnesses_.size());
    for (const TurnWitness& w : turn_witnesses_)
      for (const float value : {w.radius_m, w.height_m, w.azimuth_rad, w.direction[0], w.direction[1], w.direction[2]})
        put<float>(out, value);
    put<std::uint64_t>(out, fnv1a(out, kFnvBasis));
    write_file_atomically(path, [&](std::ostream& s) { s.write(out.data(), std::streamsize(out.size())); });
    return;
  }
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
  if (h.layout != "turn") return;
  const TurnFrame& f = h.turn;
  if (!f.point_base.allFinite() || f.point_base.norm() > 1e4) bad("turn point_m is not a finite point within 10 km");
  if (!(std::abs(f.axis_base.norm() - 1) < 1e-6) || !(std::abs(f.x_base.norm() - 1) < 1e-6) ||
      !(std::abs(f.axis_base.dot(f.x_base)) < 1e-6))
    bad("turn axis and x_axis are not perpendicular unit vectors");
  if (!(f.lower_rad <= f.upper_rad) || !(f.upper_rad - f.lower_rad <= 2 * M_PI + 1e-9) || !std::isfinite(f.lower_rad))
    bad("turn limits_rad are not an interval of at most a full turn");
  if (!(f.cell_m > 0) || !std::isfinite(f.cell_m)) bad("turn cell_m is not a finite size");
  if (f.relative_directions < 1 || f.relative_directions > 16384) bad("turn relative_directions, expected 1 to 16384");
}

/// The turn layout's witnesses: finite, unit directions, one per reduced cell, each in this
/// shard's height cells, within the painting budget.
std::vector<TurnWitness> read_turn_witnesses(Reader& r, const CapabilityHeader& h, const std::string& path) {
  const auto count = r.get<std::uint64_t>();
  if (count > (r.bytes.size() - r.at) / 24) throw FileError(path, "truncated capability map");
  const DirectionSet relative(h.turn.relative_directions), directions(h.directions);
  std::vector<TurnWitness> witnesses(count);
  std::vector<std::uint64_t> cells;
  for (TurnWitness& w : witnesses) {
    w.radius_m = r.get<float>(), w.height_m = r.get<float>(), w.azimuth_rad = r.get<float>();
    for (float& c : w.direction) c = r.get<float>();
    const Eigen::Vector3d d(w.direction[0], w.direction[1], w.direction[2]);
    if (!(w.radius_m >= 0) || !std::isfinite(w.radius_m) || !std::isfinite(w.height_m) || !std::isfinite(w.azimuth_rad) ||
        !(std::abs(d.norm() - 1) < 1e-4))
      throw FileError(path, "a turn witness is not a finite pose with a unit direction");
    if (turn_steps(h.turn, w, h.voxel_m, directions.mean_spacing_rad()) > kMaxStepsPerWitness)
      throw FileError(path, "a turn witness lies too far from the axis for the voxel size");
    cells.push_back(turn_cell(h.turn, relative, w));
    if (std::uint64_t(turn_height_cell(cells.back()) % h.shard_count + h.shard_count) % h.shard_count != h.shard_index)
      throw FileError(path, "a turn witness lies outside the shard's height cells");
  }
  std::sort(cells.begin(), cells.end());
  if (std::adjacent_find(cells.begin(), cells.end()) != cells.end())
    throw FileError(path, "two turn witnesses share a reduced cell");
  return witnesses;
}

/// A samples shard's rounds: each within a round's size, its fresh bits in the grid, ascending
/// (by construction: gaps), no more configurations than the round's and the budget's.
std::vector<SampleRound> read_sample_rounds(Reader& r, const CapabilityHeader& h, const std::string& path) {
  const std::int64_t bits = std::int64_t(h.dims[0]) * h.dims[1] * h.dims[2] * h.directions;
  const auto count = r.get<std::uint64_t>();
  if (count > (r.bytes.size() - r.at) / 32) throw FileError(path, "truncated capability map");
  std::vector<SampleRound> rounds(count);
  std::uint64_t drawn = 0;
  for (SampleRound& round : rounds) {
    round.samples = r.get<std::uint64_t>(), round.known = r.get<std::uint64_t>();
    const auto fresh = r.get<std::uint64_t>(), length = r.get<std::uint64_t>();
    if (length > r.bytes.size() - r.at) throw FileError(path, "truncated capability map");
    if (fresh > length / 2) throw FileError(path, "a round names more bits than its bytes hold");
    const std::size_t end = r.at + std::size_t(length);
    std::uint64_t counted = round.known;
    std::int64_t previous = -1;
    for (std::uint64_t i = 0; i < fresh; ++i) {
      const std::uint64_t gap = r.varint(end), n = r.varint(end) + 1;
      if (gap >= std::uint64_t(bits - previous - 1) || n > kWitnessRound)
        throw FileError(path, "a round's bits are not bits of the grid, each counted at most 2^18 times");
      previous += std::int64_t(gap) + 1;
      round.fresh.emplace_back(previous, std::uint32_t(n));
      counted += n;
    }
    if (r.at != end) throw FileError(path, "a round's bytes do not end with its bits");
    if (round.samples > kWitnessRound || counted > round.samples)
      throw FileError(path, "a round counts more configurations than it holds (at most 2^18)");
    drawn += round.samples;
  }
  if (drawn > h.fk_samples) throw FileError(path, "the rounds hold more configurations than the budget (fk_samples)");
  return rounds;
}

/// The header's JSON, checked: every field, values in range, a method and layout this fvx
/// reads in a file of the version that holds them.
CapabilityHeader read_header(const std::string& text, std::uint32_t version, const std::string& path) {
  CapabilityHeader h;
  try {
    const auto j = nlohmann::json::parse(text);
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
    h.layout = j.value("layout", "grid");
    if (h.layout == "turn") h.turn = turn_from_json(j.at("turn"));
    h.shard_split = j.value("shard_split", "slab");
    if (h.shard_split == "samples") h.target_recall = j.at("target_recall"), h.fk_samples = j.at("fk_samples");
  } catch (const nlohmann::json::exception& e) {
    throw FileError(path, std::string("bad capability-map header: ") + e.what());
  }
  check_header_values(h, path);
  if (h.method != "fk-witness" && h.method != "fk-seeded-ik" && h.method != "exhaustive-ik")
    throw FileError(path, "unknown bit definition '" + h.method + "' (method); this fvx reads fk-witness, "
                          "fk-seeded-ik and exhaustive-ik maps");
  if (version == 1 && h.method == "fk-witness") throw FileError(path, "an fk-witness map must be format version 2");
  if (h.layout != "grid" && h.layout != "turn") throw FileError(path, "unknown layout '" + h.layout + "'");
  if ((version == kTurnVersion) != (h.layout == "turn"))
    throw FileError(path, "layout '" + h.layout + "' in a version " + std::to_string(version) + " file; the turn layout "
                          "is version 3 and only it");
  if (h.layout == "turn" && h.method != "fk-witness") throw FileError(path, "a turn layout holds fk-witness maps only");
  if (h.shard_split != "slab" && h.shard_split != "samples") throw FileError(path, "unknown shard_split '" + h.shard_split + "'");
  if ((version == kSamplesVersion) != (h.shard_split == "samples"))
    throw FileError(path, "a samples shard is format version 4 and only it");
  if (h.shard_split == "samples" && (h.method != "fk-witness" || h.layout != "grid" || !(h.target_recall > 0) ||
                                     !(h.target_recall <= 1) || h.fk_samples < 1 || h.fk_samples > (std::uint64_t(1) << 40)))
    throw FileError(path, "bad capability-map header: a samples shard needs fk-witness, the grid layout, target_recall "
                          "in (0, 1] and fk_samples from 1 to 2^40");
  return h;
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
  if (version < 1 || version > kSamplesVersion)
    throw FileError(path, "capability map format version " + std::to_string(version) + "; this fvx reads versions 1 to " +
                              std::to_string(kSamplesVersion));
  if (fnv1a(body, version == 1 ? kFnvBasisVersion1 : kFnvBasis) != stored)
    throw FileError(path, "checksum mismatch: the capability map is corrupt or truncated");
  const auto header_size = r.get<std::uint32_t>();
  if (r.at + header_size > body.size()) throw FileError(path, "truncated capability map");
  const CapabilityHeader h = read_header(body.substr(r.at, header_size), version, path);
  r.at += header_size;
  CapabilityMap map(h);
  if (h.layout == "turn") {
    std::vector<TurnWitness> witnesses = read_turn_witnesses(r, h, path);
    if (r.at != body.size()) throw FileError(path, "trailing bytes after the witness list");
    try {
      const double budget = std::max(kMinStepBudget, kStepsPerWitness * double(witnesses.size()));
      map.set_turn_witnesses(std::move(witnesses), budget);
    } catch (const Error& e) {
      throw FileError(path, e.what());
    }
    return map;
  }
  if (h.shard_split == "samples") {
    map.set_sample_rounds(read_sample_rounds(r, h, path));
    if (r.at != body.size()) throw FileError(path, "trailing bytes after the rounds");
    return map;  // its bits are the merge's to decide
  }
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
