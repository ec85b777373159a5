#include "fvx/io/trajectory.hpp"

#include <filesystem>
#include <fstream>

#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"
#include "fvx/core/parse.hpp"
#include "fvx/core/pose.hpp"

namespace fvx::io {

const char* to_string(TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::Tum: return "tum";
    case TrajectoryFormat::TumNoStamp: return "tum-no-stamp";
    case TrajectoryFormat::RedwoodLog: return "redwood-log";
  }
  return "?";
}

namespace {

struct Line {
  int number;
  std::vector<std::string> fields;
};

std::vector<Line> read_lines(const std::string& path) {
  require_readable_file(path);
  std::ifstream in(path);
  std::vector<Line> lines;
  std::string text;
  for (int n = 1; std::getline(in, text); ++n) {
    const auto hash = text.find('#');
    if (hash != std::string::npos) text.resize(hash);
    auto fields = split_whitespace(text);
    if (!fields.empty()) lines.push_back({n, std::move(fields)});
  }
  return lines;
}

std::vector<double> numbers(const Line& line, const std::string& path) {
  std::vector<double> values;
  for (const auto& f : line.fields)
    values.push_back(parse_double(f, path + ":" + std::to_string(line.number)));
  return values;
}

Trajectory read_tum(const std::vector<Line>& lines, const std::string& path) {
  Trajectory trajectory;
  const std::size_t fields = lines.front().fields.size();
  if (fields != 7 && fields != 8)
    throw FileError(path, "line " + std::to_string(lines.front().number) + ": expected 8 fields " +
                              "(stamp tx ty tz qx qy qz qw) or 7 (tx ty tz qx qy qz qw), got " +
                              std::to_string(fields));
  trajectory.format = fields == 8 ? TrajectoryFormat::Tum : TrajectoryFormat::TumNoStamp;
  for (const Line& line : lines) {
    const std::string where = path + ":" + std::to_string(line.number);
    if (line.fields.size() != fields)
      throw FileError(path, "line " + std::to_string(line.number) + ": expected " +
                                std::to_string(fields) + " fields like the first pose line, got " +
                                std::to_string(line.fields.size()));
    try {
      const auto v = numbers(line, path);
      const std::size_t o = fields - 7;
      TrajectoryEntry entry;
      if (o == 1) entry.stamp_s = v[0];
      entry.T_world_sensor = pose_from_translation_quaternion({v[o], v[o + 1], v[o + 2]}, v[o + 3],
                                                              v[o + 4], v[o + 5], v[o + 6], where);
      trajectory.entries.push_back(entry);
    } catch (const UsageError& e) {
      throw Error(e.what());  // already names file:line
    }
  }
  return trajectory;
}

Trajectory read_redwood(const std::vector<Line>& lines, const std::string& path) {
  Trajectory trajectory;
  trajectory.format = TrajectoryFormat::RedwoodLog;
  if (lines.size() % 5 != 0)
    throw FileError(path, "a Redwood .log has 5 lines per frame (id id n, then 4 matrix rows); " +
                              std::to_string(lines.size()) + " non-empty lines is not a multiple of 5");
  try {
    for (std::size_t i = 0; i < lines.size(); i += 5) {
      const std::vector<double> header = numbers(lines[i], path);
      if (header.size() != 3)
        throw FileError(path, "line " + std::to_string(lines[i].number) + ": expected 'id id n'");
      Eigen::Matrix4d M;
      for (int r = 0; r < 4; ++r) {
        const auto row = numbers(lines[i + 1 + r], path);
        if (row.size() != 4)
          throw FileError(path, "line " + std::to_string(lines[i + 1 + r].number) +
                                    ": expected 4 numbers of a matrix row");
        M.row(r) = Eigen::Vector4d(row[0], row[1], row[2], row[3]).transpose();
      }
      const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
      if ((R * R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-3 ||
          R.determinant() <= 0 || (M.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-6)
        throw FileError(path, "line " + std::to_string(lines[i + 1].number) +
                                  ": the matrix is not a rigid transform");
      TrajectoryEntry entry;
      entry.frame_id = static_cast<long>(header[0]);
      entry.T_world_sensor = Eigen::Isometry3d(Eigen::Quaterniond(R).normalized());
      entry.T_world_sensor.pretranslate(M.topRightCorner<3, 1>());
      trajectory.entries.push_back(entry);
    }
  } catch (const UsageError& e) {
    throw Error(e.what());  // already names file:line
  }
  return trajectory;
}

}  // namespace

Trajectory read_trajectory(const std::string& path) {
  const std::vector<Line> lines = read_lines(path);
  if (lines.empty()) throw FileError(path, "the trajectory holds no poses");
  if (std::filesystem::path(path).extension() == ".log") return read_redwood(lines, path);
  return read_tum(lines, path);
}

}  // namespace fvx::io
