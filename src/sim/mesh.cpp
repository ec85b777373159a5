#include "fvx/sim/mesh.hpp"

#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Simple_cartesian.h>

#include <ostream>

#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"

namespace fvx::sim {

Eigen::AlignedBox3f Mesh::bounds() const {
  Eigen::AlignedBox3f box;
  for (const auto& v : vertices) box.extend(v);
  return box;
}

void Mesh::add_box(const Eigen::AlignedBox3f& box) {
  const auto base = std::uint32_t(vertices.size());
  for (int i = 0; i < 8; ++i)  // corner i: bit 0 → x max, bit 1 → y max, bit 2 → z max
    vertices.emplace_back(i & 1 ? box.max().x() : box.min().x(), i & 2 ? box.max().y() : box.min().y(),
                          i & 4 ? box.max().z() : box.min().z());
  // Two triangles per face, counter-clockwise seen from outside.
  static const std::uint32_t faces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6},   // z−, z+
                                             {0, 1, 4}, {1, 5, 4}, {2, 6, 3}, {3, 6, 7},   // y−, y+
                                             {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};  // x−, x+
  for (const auto& f : faces) triangles.push_back({base + f[0], base + f[1], base + f[2]});
}

void Mesh::append(const Mesh& other) {
  const auto base = std::uint32_t(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  for (const auto& t : other.triangles) triangles.push_back({base + t[0], base + t[1], base + t[2]});
}

Mesh read_mesh(const std::string& path) {
  require_readable_file(path);
  const std::string ext = lowercase_extension(path);
  if (ext != ".ply" && ext != ".obj" && ext != ".stl" && ext != ".off")
    throw FileError(path, "unknown mesh format '" + ext + "'; expected .ply, .obj, .stl or .off");
  using Point = CGAL::Simple_cartesian<double>::Point_3;
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> polygons;
  bool ok = false;
  try {
    ok = CGAL::IO::read_polygon_soup(path, points, polygons, CGAL::parameters::verbose(false));
  } catch (const std::exception& e) {
    throw FileError(path, std::string("cannot parse the mesh: ") + e.what());
  }
  if (!ok) throw FileError(path, "cannot parse the mesh (corrupt, empty, or not a " + ext + " file)");
  Mesh mesh;
  for (const Point& p : points) {
    const Eigen::Vector3f v(float(p.x()), float(p.y()), float(p.z()));
    if (!v.allFinite()) throw FileError(path, "the mesh has a vertex that is not finite");
    mesh.vertices.push_back(v);
  }
  for (const auto& polygon : polygons) {
    for (std::size_t corner : polygon)
      if (corner >= points.size()) throw FileError(path, "a face refers to a vertex that does not exist");
    for (std::size_t i = 1; i + 1 < polygon.size(); ++i)
      mesh.triangles.push_back({std::uint32_t(polygon[0]), std::uint32_t(polygon[i]), std::uint32_t(polygon[i + 1])});
  }
  if (mesh.triangles.empty()) throw FileError(path, "the mesh has no triangles");
  return mesh;
}

void write_mesh_ply(const std::string& path, const Mesh& mesh) {
  write_file_atomically(path, [&](std::ostream& out) {
    out << "ply\nformat binary_little_endian 1.0\ncomment fvx scene\nelement vertex "
        << mesh.vertices.size() << "\nproperty float x\nproperty float y\nproperty float z\n"
        << "element face " << mesh.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const auto& v : mesh.vertices) out.write(reinterpret_cast<const char*>(v.data()), 3 * sizeof(float));
    for (const auto& t : mesh.triangles) {
      const unsigned char three = 3;
      const std::int32_t index[3] = {std::int32_t(t[0]), std::int32_t(t[1]), std::int32_t(t[2])};
      out.write(reinterpret_cast<const char*>(&three), 1);
      out.write(reinterpret_cast<const char*>(index), sizeof index);
    }
  });
}

}  // namespace fvx::sim
