#include "fvx/sim/depth_sensor.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

#include "fvx/core/error.hpp"
#include "fvx/core/threads.hpp"

namespace fvx::sim {

SensorConfig SensorConfig::of(const io::DepthCamera& camera, std::uint64_t seed, unsigned threads) {
  SensorConfig c;
  c.intrinsics = camera.intrinsics;
  c.depth_min_m = camera.depth_min_m;
  c.depth_max_m = camera.depth_max_m;
  c.seed = seed;
  c.threads = threads;
  return c;
}

std::vector<std::string> SensorConfig::validate() const {
  std::vector<std::string> problems = intrinsics.validate();
  if (!(depth_min_m >= 0.0)) problems.push_back("depth_min_m must be >= 0 m");
  if (!(depth_max_m > depth_min_m) || !std::isfinite(depth_max_m))
    problems.push_back("depth_max_m must be finite and greater than depth_min_m");
  if (!(noise_m_per_m2 >= 0.0) || !std::isfinite(noise_m_per_m2)) problems.push_back("noise_m_per_m2 must be >= 0");
  if (!(baseline_m > 0.0)) problems.push_back("baseline_m must be > 0 m");
  if (!(dropout_incidence_deg > 0.0 && dropout_incidence_deg <= 90.0))
    problems.push_back("dropout_incidence_deg must be in (0, 90]");
  if (!(no_return_depth_m == 0.0 || (no_return_depth_m > depth_max_m && std::isfinite(no_return_depth_m))))
    problems.push_back("no_return_depth_m must be 0 or a finite depth beyond depth_max_m");
  return problems;
}

namespace {

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

/// A standard normal sample that depends only on (seed, frame, pixel): Box–Muller on two
/// counter-based uniforms.
double gaussian(std::uint64_t seed, std::uint64_t frame, std::uint64_t pixel) {
  const std::uint64_t a = splitmix64(seed ^ splitmix64(frame * 0x100000001B3ull + pixel));
  const std::uint64_t b = splitmix64(a);
  const double u1 = (double(a >> 11) + 0.5) * 0x1.0p-53;  // (0, 1)
  const double u2 = double(b >> 11) * 0x1.0p-53;          // [0, 1)
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

}  // namespace

Frame render(const RayCaster& caster, const Eigen::Isometry3d& T_world_sensor,
             const SensorConfig& config, std::uint64_t frame_index) {
  throw_if_problems("sensor", config.validate());
  const io::Intrinsics& K = config.intrinsics;
  Frame frame;
  frame.depth.width = K.width;
  frame.depth.height = K.height;
  frame.depth.raw.assign(std::size_t(K.width) * K.height, 0);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  frame.points_sensor.assign(frame.depth.raw.size(), Eigen::Vector3f(nan, nan, nan));

  const Eigen::Matrix3f R = T_world_sensor.linear().cast<float>();
  const Eigen::Vector3f origin = T_world_sensor.translation().cast<float>();
  const double cos_dropout = std::cos(config.dropout_incidence_deg * M_PI / 180.0);
  const double fb = std::abs(K.fx) * config.baseline_m;

  struct Counts {
    std::size_t valid = 0, no_surface = 0, too_near = 0, grazing = 0;
  };
  auto render_rows = [&](int row_begin, int row_end, Counts& counts) {
    for (int v = row_begin; v < row_end; ++v) {
      for (int u = 0; u < K.width; ++u) {
        // Direction with z = 1 in the optical frame: the hit distance is the depth.
        const Eigen::Vector3f ray_sensor(float((u - K.cx) / K.fx), float((v - K.cy) / K.fy), 1.0f);
        const Eigen::Vector3f ray_world = R * ray_sensor;
        const Hit hit = caster.cast(origin, ray_world, 0.0f, float(config.depth_max_m));
        if (!hit.hit()) {
          ++counts.no_surface;
          if (config.no_return_depth_m > 0.0)
            frame.points_sensor[std::size_t(v) * K.width + u] = float(config.no_return_depth_m) * ray_sensor;
          continue;
        }
        double z = hit.distance;
        if (z < config.depth_min_m) {
          ++counts.too_near;
          continue;
        }
        const double cos_incidence = std::abs(hit.normal.dot(ray_world.normalized()));
        if (cos_incidence < cos_dropout) {
          ++counts.grazing;
          continue;
        }
        const std::size_t pixel = std::size_t(v) * K.width + u;
        if (config.noise_m_per_m2 > 0.0)
          z += config.noise_m_per_m2 * z * z * gaussian(config.seed, frame_index, pixel);
        if (config.quantize_disparity) z = fb / (std::round(8.0 * fb / z) / 8.0);
        const double raw = std::round(z * K.depth_scale);
        if (!(z > 0.0) || raw < 1.0 || raw >= double(io::kDepthSaturated) || z > config.depth_max_m) {
          ++counts.no_surface;
          continue;
        }
        frame.depth.raw[pixel] = std::uint16_t(raw);
        frame.points_sensor[pixel] = float(z) * ray_sensor;
        ++counts.valid;
      }
    }
  };

  const unsigned threads = core::worker_count(config.threads, std::size_t(K.height));
  std::vector<Counts> counts(threads);
  std::vector<std::thread> pool;
  const int rows_per_thread = (K.height + int(threads) - 1) / int(threads);
  for (unsigned t = 1; t < threads; ++t)
    pool.emplace_back(render_rows, int(t) * rows_per_thread, std::min(K.height, int(t + 1) * rows_per_thread),
                      std::ref(counts[t]));
  render_rows(0, std::min(K.height, rows_per_thread), counts[0]);
  for (auto& thread : pool) thread.join();
  for (const Counts& c : counts) {
    frame.valid += c.valid;
    frame.no_surface += c.no_surface;
    frame.too_near += c.too_near;
    frame.grazing += c.grazing;
  }
  return frame;
}

}  // namespace fvx::sim
