#include "fvx/io/cloud_header.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

#include "fvx/core/error.hpp"
#include "fvx/core/parse.hpp"

namespace fvx::io {
namespace {

constexpr long long kMaxCount = (1LL << 31) - 1;
constexpr std::size_t kMaxHeaderLines = 4096;

long long count_of(const std::string& path, const std::string& field, const std::string& text) {
  try {
    return parse_int_in(text, field, 0, kMaxCount);
  } catch (const Error&) {
    throw FileError(path, field + " '" + text + "' is not a count in [0, 2^31)");
  }
}

/// A number as PCD ascii data holds it: a finite value, or nan/inf for an invalid point.
bool is_number(const std::string& token) {
  char* end = nullptr;
  std::strtod(token.c_str(), &end);
  return !token.empty() && end == token.c_str() + token.size();
}

void check_viewpoint(const std::string& path, const std::string& line, const std::vector<std::string>& values);

struct PcdHeader {
  std::vector<std::string> fields, sizes, types, counts;
  long long width = -1, height = -1, points = -1;
  std::string data;
  bool viewpoint = false;  ///< a VIEWPOINT line was read
  std::size_t values_per_point = 0, point_bytes = 0;
};

/// The keyword PCL's PCDReader::readHeader takes a line for: it compares the first token's
/// prefix, in this order ("POINTS6" is POINTS to it), so this check must too. "" for none.
std::string pcd_keyword(const std::string& token) {
  static const char* const kKeywords[] = {"VERSION", "FIELDS", "COLUMNS", "SIZE", "TYPE", "COUNT",
                                          "WIDTH", "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};
  for (const char* k : kKeywords)
    if (token.compare(0, std::strlen(k), k) == 0) return std::string(k) == "COLUMNS" ? "FIELDS" : k;
  return "";
}

/// Reads the header lines up to DATA as PCL will; `in` is left at the first data byte. PCL
/// sizes its buffer at every POINTS line, splits values only at spaces, tabs and CRs, and
/// reads on after DATA while lines start with a keyword (binary data that begins with
/// "POINTS 4294967295" was a header line to it). So a repeated keyword, a keyword after DATA,
/// a count line with more than one value and other control characters are refused: what this
/// check reads is then what PCL reads.
PcdHeader read_pcd_header(const std::string& path, std::istream& in) {
  PcdHeader h;
  std::string line;
  std::set<std::string> seen;
  std::streamoff data_at = -1;
  for (std::size_t n = 0; n <= kMaxHeaderLines && std::getline(in, line); ++n) {
    if (line.empty()) continue;
    std::vector<std::string> t = split_whitespace(line);
    if (!t.empty() && t[0][0] == '#') continue;
    const std::string key = t.empty() ? "" : pcd_keyword(t[0]);
    if (key.empty() && data_at >= 0) break;  // the data: PCL's header ends here too
    if (key.empty()) throw FileError(path, "corrupt PCD header: '" + line + "' before DATA");
    if (data_at >= 0) throw FileError(path, "corrupt PCD data: it starts with a header line (" + key + ")");
    if (std::any_of(line.begin(), line.end(), [](char c) { return std::iscntrl(static_cast<unsigned char>(c)) && c != '\t' && c != '\r'; }))
      throw FileError(path, "corrupt PCD header: a control character in line " + std::to_string(n + 1));
    t.erase(t.begin());
    if (key == "VERSION") continue;
    if (!seen.insert(key).second) throw FileError(path, "corrupt PCD header: " + key + " is given twice");
    if (t.size() != 1 && (key == "WIDTH" || key == "HEIGHT" || key == "POINTS" || key == "DATA"))
      throw FileError(path, "corrupt PCD header: '" + line + "'");
    if (key == "FIELDS") h.fields = t;
    else if (key == "SIZE") h.sizes = t;
    else if (key == "TYPE") h.types = t;
    else if (key == "COUNT") h.counts = t;
    else if (key == "WIDTH") h.width = count_of(path, "WIDTH", t[0]);
    else if (key == "HEIGHT") h.height = count_of(path, "HEIGHT", t[0]);
    else if (key == "POINTS") h.points = count_of(path, "POINTS", t[0]);
    else if (key == "VIEWPOINT") check_viewpoint(path, line, t), h.viewpoint = true;
    else h.data = t[0], data_at = in.eof() ? std::streamoff(std::filesystem::file_size(path)) : std::streamoff(in.tellg());
  }
  if (data_at < 0) throw FileError(path, "corrupt PCD header: no DATA line");
  in.clear();
  in.seekg(data_at);
  return h;
}

void check_viewpoint(const std::string& path, const std::string& line, const std::vector<std::string>& values) {
  bool finite = values.size() == 7;
  for (const std::string& v : values) finite = finite && is_number(v) && std::isfinite(std::strtod(v.c_str(), nullptr));
  if (!finite) throw FileError(path, "VIEWPOINT '" + line.substr(line.find("VIEWPOINT") + 9) + "' is not seven finite numbers");
}

/// FIELDS, SIZE, TYPE and COUNT agree, and each size is one its type can have.
void check_pcd_fields(const std::string& path, PcdHeader& h) {
  if (h.fields.empty()) throw FileError(path, "corrupt PCD header: no FIELDS");
  if (h.counts.empty()) h.counts.assign(h.fields.size(), "1");
  if (h.sizes.size() != h.fields.size() || h.types.size() != h.fields.size() || h.counts.size() != h.fields.size())
    throw FileError(path, "corrupt PCD header: FIELDS, SIZE, TYPE and COUNT name different numbers of fields");
  for (std::size_t i = 0; i < h.fields.size(); ++i) {
    const std::string &size = h.sizes[i], &type = h.types[i];
    const bool known = (type == "F" && (size == "4" || size == "8")) ||
                       ((type == "I" || type == "U") && (size == "1" || size == "2" || size == "4" || size == "8"));
    if (!known) throw FileError(path, "field " + h.fields[i] + ": TYPE " + type + " with SIZE " + size + " is not a PCD type");
    const long long count = count_of(path, "COUNT of " + h.fields[i], h.counts[i]);
    if (count < 1 || count > 1 << 20) throw FileError(path, "COUNT of " + h.fields[i] + " is " + h.counts[i]);
    h.values_per_point += std::size_t(count);
    h.point_bytes += std::size_t(count) * std::size_t(std::atoi(size.c_str()));
  }
  if (h.width < 0 || h.height < 0) throw FileError(path, "corrupt PCD header: no WIDTH or HEIGHT");
  if (h.points < 0) h.points = h.width * h.height;
  if (h.width * h.height != h.points)
    throw FileError(path, "WIDTH × HEIGHT (" + std::to_string(h.width) + " × " + std::to_string(h.height) +
                              ") is not POINTS (" + std::to_string(h.points) + ")");
}

/// Every ascii data line holds the values of one point, each a number; as many lines as points.
void check_pcd_ascii(const std::string& path, const PcdHeader& h, std::istream& in, std::uint64_t bytes_left) {
  // Each value takes at least two bytes ("0 "): a count beyond that cannot be in the file.
  if (std::uint64_t(h.points) * h.values_per_point * 2 > bytes_left + h.values_per_point * 2)
    throw FileError(path, "POINTS " + std::to_string(h.points) + " is more than the ascii data can hold (" +
                              std::to_string(bytes_left) + " bytes)");
  std::string line;
  long long points = 0;
  while (points < h.points && std::getline(in, line)) {
    const std::vector<std::string> tokens = split_whitespace(line);
    if (tokens.empty()) continue;
    if (tokens.size() != h.values_per_point)
      throw FileError(path, "data line " + std::to_string(points + 1) + " has " + std::to_string(tokens.size()) +
                                " values, the header declares " + std::to_string(h.values_per_point));
    for (const std::string& token : tokens)
      if (!is_number(token))
        throw FileError(path, "data line " + std::to_string(points + 1) + ": '" + token + "' is not a number");
    ++points;
  }
  if (points < h.points)
    throw FileError(path, "truncated point data: header promises " + std::to_string(h.points) + " points, the file holds " +
                              std::to_string(points));
}

void check_pcd_binary(const std::string& path, const PcdHeader& h, std::istream& in, std::uint64_t bytes_left) {
  const std::uint64_t need = std::uint64_t(h.points) * h.point_bytes;
  if (h.data == "binary") {
    if (need > bytes_left)
      throw FileError(path, "truncated point data: header promises " + std::to_string(h.points) + " points (" +
                                std::to_string(need) + " bytes), the file holds " + std::to_string(bytes_left));
    return;
  }
  std::uint32_t sizes[2] = {0, 0};  // compressed, uncompressed (little-endian, as PCL writes them)
  if (bytes_left < 8 || !in.read(reinterpret_cast<char*>(sizes), 8))
    throw FileError(path, "truncated binary_compressed data: no block sizes");
  if (sizes[0] > bytes_left - 8)
    throw FileError(path, "binary_compressed block of " + std::to_string(sizes[0]) + " bytes, the file holds " +
                              std::to_string(bytes_left - 8));
  if (sizes[1] != need)
    throw FileError(path, "binary_compressed block unpacks to " + std::to_string(sizes[1]) + " bytes, " +
                              std::to_string(h.points) + " points need " + std::to_string(need));
  if (std::uint64_t(sizes[1]) > 256 * std::uint64_t(sizes[0]) + 1024)
    throw FileError(path, "binary_compressed block claims " + std::to_string(sizes[1]) + " bytes from " +
                              std::to_string(sizes[0]) + " (more than LZF can pack)");
}

std::uint64_t bytes_after(std::istream& in, const std::string& path) {
  const auto here = in.tellg();
  const auto size = std::filesystem::file_size(path);
  return here < 0 || std::uint64_t(here) > size ? 0 : size - std::uint64_t(here);
}

/// Bytes of a PLY scalar type; 0 for a name PLY does not have.
std::size_t ply_type_bytes(const std::string& type) {
  static const std::pair<const char*, std::size_t> kTypes[] = {
      {"char", 1},  {"uchar", 1}, {"int8", 1},    {"uint8", 1},  {"short", 2},  {"ushort", 2},
      {"int16", 2}, {"uint16", 2}, {"int", 4},    {"uint", 4},   {"int32", 4},  {"uint32", 4},
      {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
  for (const auto& [name, bytes] : kTypes)
    if (type == name) return bytes;
  return 0;
}

struct PlyElement {
  std::string name;
  long long count = 0;
  std::uint64_t min_bytes = 0;  ///< per element in binary: its scalars, and each list's count
};

/// What PCL's PLYReader builds from a header that it cannot be trusted with (CI's fuzzer
/// found one; reading PCL 1.13's reader, the rest): it sizes the cloud by obj_info num_cols x num_rows when both are set (120 GB from
/// a 200-byte file; fewer cells than vertices write past its buffer and assert; more cells
/// are zeros, points at the origin, unless a range_grid element places the vertices in them),
/// asserts on an obj_info line that does not start at its first column, and keeps uchar
/// red [green] blue as one rgb field whose bytes it writes at blue (a blue without red before
/// it asserts; other orders write into the wrong field).
struct PlyLayout {
  std::uint32_t width = 0, height = 0;  ///< as PCL holds them while it reads the header
  long long vertices = -1;              ///< the vertex element's count; -1 without one
  long long range_grid = -1;            ///< the range_grid element's count; -1 without one
  std::string colour;                   ///< the open red..blue run's last name, or ""
  bool rgb = false;                     ///< a whole red..blue run was read (alpha amends it)
};

/// obj_info's number as PCL reads it: atoi (glibc: int(strtol)), stored as uint32.
std::uint32_t pcl_atoi(const std::string& text) {
  return std::uint32_t(int(std::strtol(text.c_str(), nullptr, 10)));
}

void read_ply_obj_info(const std::string& path, const std::string& line, const std::vector<std::string>& t,
                       PlyLayout& layout) {
  if (line.compare(0, 8, "obj_info") != 0)
    throw FileError(path, "PLY header line '" + line + "' does not start with obj_info (PCL cannot read it)");
  if (t.size() < 3) return;
  if (t[1] == "num_cols") layout.width = pcl_atoi(t[2]);
  if (t[1] == "num_rows") layout.height = pcl_atoi(t[2]);
}

void read_ply_element(const std::string& path, const std::vector<std::string>& t, std::vector<PlyElement>& elements,
                      PlyLayout& layout) {
  elements.push_back({t[1], count_of(path, "element " + t[1], t[2]), 0});
  if (t[1] == "range_grid") layout.range_grid = elements.back().count;
  if (t[1] != "vertex") return;
  if (layout.vertices >= 0) throw FileError(path, "PLY header declares two vertex elements");
  layout.vertices = elements.back().count;
  if (layout.width == 0 || layout.height == 0) layout.width = std::uint32_t(layout.vertices), layout.height = 1;
}

/// PCL's colour properties of a vertex: uchar red [green] blue in a row, alpha after them.
void read_ply_colour(const std::string& path, const std::string& type, const std::string& name, PlyLayout& layout) {
  auto is = [&](const char* c) { return name == c || name == std::string("diffuse_") + c; };
  const bool uchar = type == "uchar" || type == "uint8";
  const bool colour = uchar && (is("red") || is("green") || is("blue"));
  const bool follows = (is("green") && layout.colour == "red") || (is("blue") && !layout.colour.empty());
  if (colour && (is("red") ? !layout.colour.empty() : !follows))
    throw FileError(path, "PLY vertex colour '" + name + "' is not in a uchar red [green] blue run; PCL misreads it");
  if (!colour && !layout.colour.empty())
    throw FileError(path, "PLY vertex property '" + name + "' splits a red [green] blue run; PCL misreads it");
  if (uchar && name == "alpha" && !layout.rgb)
    throw FileError(path, "PLY vertex property 'alpha' without red, green and blue before it; PCL cannot read it");
  layout.colour = !colour || is("blue") ? "" : (is("red") ? "red" : "green");
  layout.rgb = layout.rgb || (colour && is("blue"));
}

/// The end of the header: PCL's cloud is width x height cells, the vertices or the range grid
/// that places them (PCL's writer drops NaN points of an organised cloud and writes one).
void check_ply_layout(const std::string& path, const PlyLayout& layout) {
  if (!layout.colour.empty()) throw FileError(path, "PLY vertex colour red has no blue after it; PCL misreads it");
  const std::uint64_t cells = std::uint64_t(layout.width) * layout.height;
  const bool gridded = layout.range_grid >= layout.vertices && cells == std::uint64_t(layout.range_grid);
  if (layout.vertices >= 0 && cells != std::uint64_t(layout.vertices) && !gridded)
    throw FileError(path, "PLY obj_info num_cols x num_rows (" + std::to_string(layout.width) + " x " +
                              std::to_string(layout.height) + ") is neither the vertex count " +
                              std::to_string(layout.vertices) + " nor a range_grid's");
}

}  // namespace

bool check_ply_header(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line, format;
  std::vector<PlyElement> elements;
  PlyLayout layout;
  for (std::size_t n = 0;; ++n) {
    if (n > kMaxHeaderLines || !std::getline(in, line)) throw FileError(path, "corrupt PLY header: no end_header");
    const std::vector<std::string> t = split_whitespace(line);
    if (t.empty()) continue;
    if (t[0] == "end_header") break;
    // PCL skips a line it does not know and reads on with the wrong layout: refuse it here.
    static const std::set<std::string> kKeywords = {"ply", "format", "comment", "obj_info", "element", "property"};
    if (!kKeywords.count(t[0]) || (t[0] == "ply") != (n == 0))
      throw FileError(path, "corrupt PLY header: '" + line + "'");
    if (t[0] == "format" && t.size() >= 2) format = t[1];
    if (t[0] == "obj_info") read_ply_obj_info(path, line, t, layout);
    if (t[0] == "element" && t.size() == 3) read_ply_element(path, t, elements, layout);
    if (t[0] != "property") continue;
    const bool list = t.size() == 5 && t[1] == "list";
    const std::string type = list ? t[2] : (t.size() == 3 ? t[1] : "");
    if (elements.empty() || !ply_type_bytes(type) || (list && !ply_type_bytes(t[3])))
      throw FileError(path, "corrupt PLY header: '" + line + "'");
    // PCL aborts on some list properties of vertices (an assert in its reader).
    if (list && elements.back().name == "vertex")
      throw FileError(path, "PLY vertex property '" + t.back() + "' is a list; fvx reads vertices of single values");
    if (elements.back().name == "vertex") read_ply_colour(path, type, t.back(), layout);
    elements.back().min_bytes += ply_type_bytes(type);
  }
  check_ply_layout(path, layout);
  if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
    throw FileError(path, "PLY format '" + format + "': expected ascii, binary_little_endian or binary_big_endian");
  const std::uint64_t left = bytes_after(in, path);
  std::uint64_t need = 0;  // ascii: at least "0\n" per element
  for (const PlyElement& e : elements) need += std::uint64_t(e.count) * (format == "ascii" ? 2 : e.min_bytes);
  if (need > left + 2)
    throw FileError(path, "truncated PLY data: the header declares " + std::to_string(need) + " bytes at least (" +
                              (elements.empty() ? std::string("no element") : "element " + elements.front().name + " " +
                                                  std::to_string(elements.front().count)) +
                              "), the file holds " + std::to_string(left));
  // PCL's PLY writer stores the sensor pose as one "camera" element (view_p*, *_axis*).
  return std::any_of(elements.begin(), elements.end(), [](const PlyElement& e) { return e.name == "camera" && e.count == 1; });
}

bool check_pcd_header(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  PcdHeader h = read_pcd_header(path, in);
  check_pcd_fields(path, h);
  const std::uint64_t left = bytes_after(in, path);
  if (h.data == "ascii") check_pcd_ascii(path, h, in, left);
  else if (h.data == "binary" || h.data == "binary_compressed") check_pcd_binary(path, h, in, left);
  else throw FileError(path, "DATA " + h.data + ": expected ascii, binary or binary_compressed");
  return h.viewpoint;
}

}  // namespace fvx::io
