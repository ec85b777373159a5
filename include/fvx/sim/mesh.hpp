#pragma once
/// \file
/// Triangle meshes of simulated scenes (stage `sim`). CGAL reads PLY, OBJ, STL and OFF;
/// polygons with more than three corners are split into fans.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace fvx::sim {

struct Mesh {
  std::vector<Eigen::Vector3f> vertices;                ///< metres, world frame
  std::vector<std::array<std::uint32_t, 3>> triangles;  ///< vertex indices, counter-clockwise
                                                        ///< seen from outside

  Eigen::AlignedBox3f bounds() const;
  /// Appends an axis-aligned solid cuboid (12 triangles, outward normals).
  void add_box(const Eigen::AlignedBox3f& box);
  /// Appends another mesh.
  void append(const Mesh& other);
};

/// Reads a mesh. Throws FileError for a missing file, an unknown extension, a file that does
/// not parse, or one without triangles.
Mesh read_mesh(const std::string& path);

/// Writes binary little-endian PLY, atomically.
void write_mesh_ply(const std::string& path, const Mesh& mesh);

}  // namespace fvx::sim
