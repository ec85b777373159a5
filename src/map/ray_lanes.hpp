#pragma once
// Private to the map stage: the bitmap walk of ray_keys.hpp for eight rays in step (AVX-512)
// or four (AVX2), where the CPU has them. One ray's walk spends most of its time on the branch
// that picks the axis to step (it goes either way from step to step); the lanes pick by masks
// instead. The arithmetic is walk_marked_ray's (the same IEEE double additions and
// comparisons, no fused operations), so the cells are the same; a test holds both widths to
// the one-ray walk.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ray_keys.hpp"

namespace fvx::map {

/// Whether this CPU runs mark_rays_in_lanes (AVX-512 F and DQ).
bool ray_lanes_available();
/// Whether it runs mark_rays_in_four_lanes (AVX2).
bool four_ray_lanes_available();
/// The walk integrate() uses: 8 (mark_rays_in_lanes), 4 (mark_rays_in_four_lanes) or 1 (one
/// ray at a time), the widest this CPU runs; the environment variable FVX_RAY_LANES may ask
/// for a narrower one (8 or more: the widest, 4–7: at most four, anything else: one), to
/// compare them in a benchmark or test each. Read once.
int ray_lanes();

/// Started rays (start_marked_ray), a column per field, as the lanes load them.
class MarkedRays {
 public:
  void push(const MarkedRay& ray);
  void clear();
  std::size_t size() const { return index_.size(); }

 private:
  friend void mark_rays_in_lanes(const MarkedRays& rays, std::uint64_t* words);
  friend void mark_rays_in_four_lanes(const MarkedRays& rays, std::uint64_t* words);
  std::vector<double> t0_, t1_, t2_, d0_, d1_, d2_, length_;
  std::vector<std::int64_t> index_, index_end_, step0_, step1_, step2_;
};

/// Sets in `words` (a flat bitmap's 64-bit words) the bit of every cell walk_marked_ray
/// marks for each of `rays` (not their first cells, which the caller marks). Only where
/// ray_lanes_available().
void mark_rays_in_lanes(const MarkedRays& rays, std::uint64_t* words);

/// The same, four rays in step (AVX2, for CPUs without AVX-512: no masked loads, so a lane
/// whose ray ended is refilled through memory). Only where four_ray_lanes_available().
void mark_rays_in_four_lanes(const MarkedRays& rays, std::uint64_t* words);

}  // namespace fvx::map
