// Renders a few noise-free depth scans of a box room with a closed crate in it, as PCD files
// with the sensor pose in VIEWPOINT, for the bundled sample (scripts/make-sample-data.sh).
// Analytic ray casting against axis-aligned boxes; the full virtual Kinect is `fvx simulate`.
//
//   make_box_room OUT_DIR [WIDTH HEIGHT]     (default 160 120: a Kinect v1 decimated by 4)
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "fvx/core/error.hpp"
#include "fvx/io/cloud_file.hpp"

namespace {

struct Box {
  Eigen::Vector3d min, max;
};

// The room: 4 m x 3 m x 2.5 m, floor at z = 0. The crate: 0.6 m cube on the floor, closed.
const Box kRoom{{-2.0, -1.5, 0.0}, {2.0, 1.5, 2.5}};
const Box kCrate{{0.2, -0.3, 0.0}, {0.8, 0.3, 0.6}};

/// Distance along a unit ray to where it leaves `box` from inside (slab method).
double exit_distance(const Box& box, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double t = INFINITY;
  for (int i = 0; i < 3; ++i) {
    if (d[i] > 0) t = std::min(t, (box.max[i] - o[i]) / d[i]);
    if (d[i] < 0) t = std::min(t, (box.min[i] - o[i]) / d[i]);
  }
  return t;
}

/// Distance along a unit ray to where it enters `box` from outside, or infinity.
double entry_distance(const Box& box, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double t_near = -INFINITY, t_far = INFINITY;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0) {
      if (o[i] < box.min[i] || o[i] > box.max[i]) return INFINITY;
      continue;
    }
    double t0 = (box.min[i] - o[i]) / d[i], t1 = (box.max[i] - o[i]) / d[i];
    if (t0 > t1) std::swap(t0, t1);
    t_near = std::max(t_near, t0);
    t_far = std::min(t_far, t1);
  }
  return (t_near <= t_far && t_near > 0) ? t_near : INFINITY;
}

/// T_world_sensor for an optical frame at `eye` looking at `target`, world z up.
Eigen::Isometry3d look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();  // right
  const Eigen::Vector3d y = z.cross(x);                                      // down
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() << x, y, z;
  T.translation() = eye;
  return T;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2 && argc != 4) {
    std::fprintf(stderr, "usage: make_box_room OUT_DIR [WIDTH HEIGHT]\n");
    return 2;
  }
  const std::filesystem::path out = argv[1];
  const int width = argc == 4 ? std::atoi(argv[2]) : 160;
  const int height = argc == 4 ? std::atoi(argv[3]) : 120;
  if (width < 8 || height < 6 || width > 4096 || height > 4096) {
    std::fprintf(stderr, "make_box_room: WIDTH and HEIGHT must be 8..4096 and 6..4096\n");
    return 2;
  }
  std::filesystem::create_directories(out);
  // Kinect v1 intrinsics scaled to the image size.
  const double f = 525.0 * width / 640.0, cx = (width - 1) / 2.0, cy = (height - 1) / 2.0;
  const Eigen::Vector3d crate_center(0.5, 0.0, 0.3);
  const Eigen::Vector3d eyes[] = {{-1.6, -1.1, 1.6}, {-1.6, 1.1, 1.5}, {1.7, 1.2, 1.7}, {1.7, -1.2, 1.4}};
  try {
    for (int view = 0; view < 4; ++view) {
      const Eigen::Isometry3d T_world_sensor = look_at(eyes[view], crate_center);
      std::vector<Eigen::Vector3f> points_sensor;
      for (int v = 0; v < height; ++v) {
        for (int u = 0; u < width; ++u) {
          const Eigen::Vector3d ray_sensor = Eigen::Vector3d((u - cx) / f, (v - cy) / f, 1.0).normalized();
          const Eigen::Vector3d d = T_world_sensor.linear() * ray_sensor;
          const Eigen::Vector3d& o = T_world_sensor.translation();
          const double t = std::min(exit_distance(kRoom, o, d), entry_distance(kCrate, o, d));
          points_sensor.push_back((t * ray_sensor).cast<float>());
        }
      }
      const std::string name = "view" + std::to_string(view) + ".pcd";
      fvx::io::write_pcd((out / name).string(), points_sensor, T_world_sensor);
      std::printf("%s\n", (out / name).c_str());
    }
  } catch (const fvx::Error& e) {
    std::fprintf(stderr, "make_box_room: %s\n", e.what());
    return 1;
  }
  return 0;
}
