#include "fvx/io/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
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
    case TrajectoryFormat::Kitti: return "kitti";
    case TrajectoryFormat::PoseFiles: return "pose-files";
  }
  return "?";
}

const char* to_string(PoseFormatChoice choice) {
  switch (choice) {
    case PoseFormatChoice::Auto: return "auto";
    case PoseFormatChoice::Tum: return "tum";
    case PoseFormatChoice::Redwood: return "redwood";
    case PoseFormatChoice::Kitti: return "kitti";
  }
  return "?";
}

PoseFormatChoice parse_pose_format(const std::string& text, const std::string& what) {
  if (text == "auto") return PoseFormatChoice::Auto;
  if (text == "tum") return PoseFormatChoice::Tum;
  if (text == "redwood") return PoseFormatChoice::Redwood;
  if (text == "kitti") return PoseFormatChoice::Kitti;
  throw UsageError(what + " '" + text + "': expected auto, tum, redwood or kitti");
}

std::string frame_name(const std::string& path) {
  const std::string name = std::filesystem::path(path).filename().string();
  return name.substr(0, name.find('.'));
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
                              "(stamp tx ty tz qx qy qz qw), 7 (tx ty tz qx qy qz qw) or 12 (KITTI), got " +
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

std::string line_text(const Line& line) { return "line " + std::to_string(line.number); }

/// Matrix rows hold finite numbers; ScanNet marks a frame without a pose with -inf.
void check_finite(const Line& line, const std::string& path) {
  for (const std::string& f : line.fields)
    if (!std::isfinite(std::strtod(f.c_str(), nullptr)))
      throw FileError(path, line_text(line) + ": the matrix is not finite (ScanNet writes -inf for a frame "
                                              "without a pose: leave that frame out)");
}

/// `rows` lines from `first` of 4 numbers each: the top rows of a 4x4 matrix (the rest: 0 0 0 1).
Eigen::Matrix4d matrix_rows(const std::vector<Line>& lines, std::size_t first, int rows, const std::string& path) {
  Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
  for (int r = 0; r < rows; ++r) {
    check_finite(lines[first + r], path);
    const auto row = numbers(lines[first + r], path);
    if (row.size() != 4)
      throw FileError(path, line_text(lines[first + r]) + ": expected 4 numbers of a matrix row, got " +
                                std::to_string(row.size()));
    M.row(r) = Eigen::Vector4d(row[0], row[1], row[2], row[3]).transpose();
  }
  return M;
}

/// A camera-to-world matrix as a pose, re-orthonormalised; FileError unless rigid.
Eigen::Isometry3d rigid_pose(const Eigen::Matrix4d& M, const std::string& path, const Line& line) {
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  if ((R * R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-3 || R.determinant() <= 0 ||
      (M.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-6)
    throw FileError(path, line_text(line) + ": the matrix is not a rigid transform");
  Eigen::Isometry3d T(Eigen::Quaterniond(R).normalized());
  T.pretranslate(M.topRightCorner<3, 1>());
  return T;
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
      if (header.size() != 3) throw FileError(path, line_text(lines[i]) + ": expected 'id id n'");
      TrajectoryEntry entry;
      entry.frame_id = static_cast<long>(header[0]);
      entry.T_world_sensor = rigid_pose(matrix_rows(lines, i + 1, 4, path), path, lines[i + 1]);
      trajectory.entries.push_back(entry);
    }
  } catch (const UsageError& e) {
    throw Error(e.what());  // already names file:line
  }
  return trajectory;
}

/// KITTI: per line the top three rows of the 4x4 matrix, row-major; line i is frame i.
Trajectory read_kitti(const std::vector<Line>& lines, const std::string& path) {
  Trajectory trajectory;
  trajectory.format = TrajectoryFormat::Kitti;
  try {
    for (const Line& line : lines) {
      check_finite(line, path);
      const std::vector<double> v = numbers(line, path);
      if (v.size() != 12)
        throw FileError(path, line_text(line) + ": expected 12 numbers (a 3x4 matrix, row-major), got " +
                                  std::to_string(v.size()));
      Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
      for (int i = 0; i < 12; ++i) M(i / 4, i % 4) = v[std::size_t(i)];
      TrajectoryEntry entry;
      entry.frame_id = long(trajectory.entries.size());
      entry.T_world_sensor = rigid_pose(M, path, line);
      trajectory.entries.push_back(entry);
    }
  } catch (const UsageError& e) {
    throw Error(e.what());
  }
  return trajectory;
}

/// One 4x4 matrix file (7-Scenes frame-XXXXXX.pose.txt, ScanNet pose/N.txt).
Eigen::Isometry3d read_pose_file(const std::string& path) {
  const std::vector<Line> lines = read_lines(path);
  if (lines.size() != 4)
    throw FileError(path, "expected a 4x4 matrix (4 rows of 4 numbers), got " + std::to_string(lines.size()) + " rows");
  try {
    return rigid_pose(matrix_rows(lines, 0, 4, path), path, lines.front());
  } catch (const UsageError& e) {
    throw Error(e.what());
  }
}

/// A folder of per-frame pose files: `*.pose.txt`, or else every `*.txt`, sorted by name
/// (shorter first, so that ScanNet's 2.txt comes before 10.txt).
Trajectory read_pose_folder(const std::string& dir) {
  std::vector<std::string> poses, texts;
  std::error_code error;
  std::filesystem::directory_iterator folder(dir, error);
  if (error) throw FileError(dir, "cannot list the folder: " + error.message());
  for (const auto& e : folder) {
    const std::string name = e.path().filename().string();
    auto ends_with = [&](const std::string& tail) {
      return name.size() > tail.size() && name.compare(name.size() - tail.size(), tail.size(), tail) == 0;
    };
    if (ends_with(".pose.txt")) poses.push_back(e.path().string());
    else if (ends_with(".txt")) texts.push_back(e.path().string());
    if (poses.size() + texts.size() > kMaxPoseFiles)
      throw FileError(dir, "more than " + std::to_string(kMaxPoseFiles) + " pose files");
  }
  std::vector<std::string>& files = poses.empty() ? texts : poses;
  if (files.empty()) throw FileError(dir, "the folder holds no pose file (frame-XXXXXX.pose.txt or N.txt)");
  std::sort(files.begin(), files.end(), [](const std::string& a, const std::string& b) {
    return std::make_pair(a.size(), a) < std::make_pair(b.size(), b);
  });
  Trajectory trajectory;
  trajectory.format = TrajectoryFormat::PoseFiles;
  for (const std::string& file : files) {
    TrajectoryEntry entry;
    entry.frame_name = frame_name(file);
    entry.T_world_sensor = read_pose_file(file);
    trajectory.entries.push_back(entry);
  }
  return trajectory;
}

}  // namespace

Trajectory read_trajectory(const std::string& path, PoseFormatChoice choice) {
  if (std::filesystem::is_directory(path)) {
    if (choice != PoseFormatChoice::Auto)
      throw FileError(path, "a folder holds per-frame 4x4 pose files; --pose-format names a trajectory file's format");
    return read_pose_folder(path);
  }
  const std::vector<Line> lines = read_lines(path);
  if (lines.empty()) throw FileError(path, "the trajectory holds no poses");
  const bool log = std::filesystem::path(path).extension() == ".log";
  if (choice == PoseFormatChoice::Redwood || (choice == PoseFormatChoice::Auto && log)) return read_redwood(lines, path);
  if (choice == PoseFormatChoice::Kitti || (choice == PoseFormatChoice::Auto && lines.front().fields.size() == 12))
    return read_kitti(lines, path);
  return read_tum(lines, path);
}

}  // namespace fvx::io
