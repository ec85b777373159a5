#include "fvx/report/analysis.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <numeric>

namespace fvx::report {

Json frontier_clusters_json(const std::vector<frontiers::Cluster>& clusters) {
  Json out = Json::array();
  for (const auto& c : clusters)
    out.push_back({{"id", c.id}, {"cells", c.cells.size()}, {"centroid_m", vec_json(c.centroid_m)},
                   {"bounds_m", bounds_json(c.bounds_m)}});
  return out;
}

Json void_clusters_json(const std::vector<voids::VoidCluster>& clusters) {
  Json out = Json::array();
  for (const auto& c : clusters) {
    Json axes = Json::array();
    for (int j = 0; j < 3; ++j) axes.push_back(vec_json(c.axes.col(j)));
    out.push_back({{"id", c.id},
                   {"cells", c.cells.size()},
                   {"volume_m3", c.volume_m3},
                   {"volume_dm3", frontier_voids::to_dm3(c.volume_m3)},
                   {"fit_score", c.fit_score},
                   {"mean_m", vec_json(c.mean_m)},
                   {"axes", axes},
                   {"variances_m2", vec_json(c.variances_m2)},
                   {"semi_axes_m", vec_json(c.semi_axes_m)}});
  }
  return out;
}

Json frontier_voids_json(const std::vector<frontier_voids::FrontierVoid>& pairs,
                         const std::vector<voids::VoidCluster>& clusters) {
  Json out = Json::array();
  for (const auto& p : pairs)
    out.push_back({{"void_id", p.void_id},
                   {"frontier_ids", p.frontier_ids},
                   {"void_cells", clusters[std::size_t(p.void_id)].cells.size()},
                   {"utility_m3", p.utility_m3},
                   {"utility_dm3", frontier_voids::to_dm3(p.utility_m3)},
                   {"enclosed", p.enclosed()}});
  return out;
}

void write_cells_cloud(const std::string& path, const map::OccupancyMap& map, const frontier_voids::Analysis& a,
                       bool with_voids, bool by_cluster) {
  std::vector<Eigen::Vector3f> points;
  std::vector<io::Rgb> colors;
  for (const auto& c : a.frontier_clusters)
    for (const auto& k : c.cells) {
      points.push_back(map.center_of(k).cast<float>());
      colors.push_back(by_cluster ? io::cluster_color(c.id) : kFrontierRed);
    }
  if (with_voids)
    for (const auto& c : a.void_clusters)
      for (const auto& k : c.cells) {
        points.push_back(map.center_of(k).cast<float>());
        colors.push_back(by_cluster ? io::cluster_color(c.id + 1000) : kVoidViolet);
      }
  io::write_colored_cloud(path, points, colors);
}

void write_ellipsoids(const std::string& path, const std::vector<voids::VoidCluster>& clusters) {
  // A UV sphere per cluster, scaled by the semi-axes and turned onto the eigenvectors.
  constexpr int kRings = 8, kSegments = 16;
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<io::Rgb> colors;
  for (const auto& c : clusters) {
    const auto base = std::uint32_t(vertices.size());
    for (int i = 0; i <= kRings; ++i) {
      const double theta = M_PI * i / kRings;
      for (int j = 0; j < kSegments; ++j) {
        const double phi = 2 * M_PI * j / kSegments;
        const Eigen::Vector3d unit(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
        vertices.push_back((c.mean_m + c.axes * c.semi_axes_m.cwiseProduct(unit)).cast<float>());
        colors.push_back(io::cluster_color(c.id + 1000));
      }
    }
    for (int i = 0; i < kRings; ++i)
      for (int j = 0; j < kSegments; ++j) {
        const std::uint32_t a = base + std::uint32_t(i * kSegments + j),
                            b = base + std::uint32_t(i * kSegments + (j + 1) % kSegments);
        triangles.push_back({a, a + kSegments, b});
        triangles.push_back({b, a + kSegments, b + kSegments});
      }
  }
  io::write_ply_mesh(path, vertices, triangles, colors);
}

io::PictureLayer occupied_layer(const map::OccupancyMap& map, const Eigen::AlignedBox3d& bounds_m) {
  io::PictureLayer occupied{"occupied (lighter is higher)", kOccupiedGrey, {}, false, true};
  for (const auto& c : map.occupied_centers())
    if (bounds_m.contains(c.cast<double>())) occupied.centers_m.push_back(c.cast<double>());
  return occupied;
}

io::PictureLayer void_layer(const map::OccupancyMap& map, const frontier_voids::Analysis& a) {
  io::PictureLayer voids{"void", kVoidViolet, {}, true, false};
  for (const auto& k : a.void_cells) voids.centers_m.push_back(map.center_of(k));
  return voids;
}

void write_picture(const std::string& path, const map::OccupancyMap& map, const frontier_voids::Analysis& a,
                   bool with_voids) {
  // Occupied cells shaded by height (the scene's shape); frontier and void cells translucent
  // over them, since in a view from above they lie at every height.
  std::vector<io::PictureLayer> layers = {occupied_layer(map, a.bounds_m)};
  io::PictureLayer frontier{"frontier", kFrontierRed, {}, true, false};
  for (const auto& k : a.frontier_cells) frontier.centers_m.push_back(map.center_of(k));
  layers.push_back(std::move(frontier));
  if (with_voids) layers.push_back(void_layer(map, a));
  io::write_top_view_png(path, map.resolution_m(), layers);
}

Json frontiers_results_json(const frontier_voids::Analysis& a) {
  return {{"bounds_m", bounds_json(a.bounds_m)},
          {"frontier_cells", a.frontier_cells.size()},
          {"frontier_clusters", frontier_clusters_json(a.frontier_clusters)}};
}

Json voids_results_json(const frontier_voids::Analysis& a, double R) {
  const std::size_t paired_cells = std::accumulate(
      a.frontier_voids.begin(), a.frontier_voids.end(), std::size_t(0), [&](std::size_t n, const auto& fv) {
        return n + (fv.enclosed() ? 0 : a.void_clusters[std::size_t(fv.void_id)].cells.size());
      });
  return {{"bounds_m", bounds_json(a.bounds_m)},
          {"hull_faces", a.hull_faces},
          {"void_cells", a.void_cells.size()},
          {"void_volume_dm3", frontier_voids::to_dm3(double(a.void_cells.size()) * R * R * R)},
          {"void_clusters", void_clusters_json(a.void_clusters)},
          {"frontier_cells", a.frontier_cells.size()},
          {"frontier_clusters", frontier_clusters_json(a.frontier_clusters)},
          {"frontier_voids", frontier_voids_json(a.frontier_voids, a.void_clusters)},
          {"observable_void_cells", paired_cells}};
}

}  // namespace fvx::report
