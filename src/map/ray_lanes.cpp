#include "ray_lanes.hpp"

#include <immintrin.h>

#include <algorithm>
#include <cstdlib>

namespace fvx::map {

bool ray_lanes_available() {
  static const bool available = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq");
  return available;
}

bool four_ray_lanes_available() {
  static const bool available = __builtin_cpu_supports("avx2");
  return available;
}

int ray_lanes() {
  static const int lanes = [] {
    const int widest = ray_lanes_available() ? 8 : four_ray_lanes_available() ? 4 : 1;
    const char* asked = std::getenv("FVX_RAY_LANES");
    const int wanted = asked ? std::atoi(asked) : widest;
    return wanted >= 8 ? widest : wanted >= 4 ? std::min(widest, 4) : 1;
  }();
  return lanes;
}

void MarkedRays::push(const MarkedRay& ray) {
  t0_.push_back(ray.t_max[0]);
  t1_.push_back(ray.t_max[1]);
  t2_.push_back(ray.t_max[2]);
  d0_.push_back(ray.t_delta[0]);
  d1_.push_back(ray.t_delta[1]);
  d2_.push_back(ray.t_delta[2]);
  length_.push_back(ray.length);
  index_.push_back(ray.index);
  index_end_.push_back(ray.index_end);
  step0_.push_back(ray.index_step[0]);
  step1_.push_back(ray.index_step[1]);
  step2_.push_back(ray.index_step[2]);
}

void MarkedRays::clear() {
  for (auto* column : {&t0_, &t1_, &t2_, &d0_, &d1_, &d2_, &length_}) column->clear();
  for (auto* column : {&index_, &index_end_, &step0_, &step1_, &step2_}) column->clear();
}

namespace {

/// The lowest `n` set bits of `mask`.
__mmask8 lowest_bits(__mmask8 mask, unsigned n) {
  unsigned out = 0, m = mask;
  for (unsigned k = 0; k < n; ++k, m &= m - 1) out |= m & (~m + 1);
  return __mmask8(out);
}

}  // namespace

// Each lane holds one ray; a lane whose ray ended takes the next ray of the list (an expanding
// load fills exactly the free lanes), so the eight stay busy until the list runs out.
__attribute__((target("avx512f,avx512dq"))) void mark_rays_in_lanes(const MarkedRays& r, std::uint64_t* words) {
  const std::size_t n = r.size();
  std::size_t next = 0;
  __m512d t0 = _mm512_setzero_pd(), t1 = t0, t2 = t0, d0 = t0, d1 = t0, d2 = t0, length = t0;
  __m512i index = _mm512_setzero_si512(), index_end = index, step0 = index, step1 = index, step2 = index;
  __mmask8 active = 0;
  alignas(64) std::uint64_t word_of_lane[8], bit_of_lane[8];
  const __m512i one = _mm512_set1_epi64(1), low6 = _mm512_set1_epi64(63);
  while (true) {
    const auto free = __mmask8(~active);
    if (free && next < n) {
      const unsigned take = unsigned(std::min<std::size_t>(unsigned(__builtin_popcount(free)), n - next));
      const __mmask8 load = lowest_bits(free, take);
      t0 = _mm512_mask_expandloadu_pd(t0, load, &r.t0_[next]);
      t1 = _mm512_mask_expandloadu_pd(t1, load, &r.t1_[next]);
      t2 = _mm512_mask_expandloadu_pd(t2, load, &r.t2_[next]);
      d0 = _mm512_mask_expandloadu_pd(d0, load, &r.d0_[next]);
      d1 = _mm512_mask_expandloadu_pd(d1, load, &r.d1_[next]);
      d2 = _mm512_mask_expandloadu_pd(d2, load, &r.d2_[next]);
      length = _mm512_mask_expandloadu_pd(length, load, &r.length_[next]);
      index = _mm512_mask_expandloadu_epi64(index, load, &r.index_[next]);
      index_end = _mm512_mask_expandloadu_epi64(index_end, load, &r.index_end_[next]);
      step0 = _mm512_mask_expandloadu_epi64(step0, load, &r.step0_[next]);
      step1 = _mm512_mask_expandloadu_epi64(step1, load, &r.step1_[next]);
      step2 = _mm512_mask_expandloadu_epi64(step2, load, &r.step2_[next]);
      next += take;
      active = __mmask8(active | load);
    }
    if (!active) return;
    // walk_marked_ray's step: dim = t0 < t1 ? (t0 < t2 ? 0 : 2) : (t1 < t2 ? 1 : 2).
    const __mmask8 first = _mm512_cmp_pd_mask(t0, t1, _CMP_LT_OQ);
    const __m512d smaller = _mm512_mask_blend_pd(first, t1, t0);
    const __mmask8 below_t2 = _mm512_cmp_pd_mask(smaller, t2, _CMP_LT_OQ);
    const auto on0 = __mmask8(first & below_t2), on1 = __mmask8(~first & below_t2), on2 = __mmask8(~below_t2);
    index = _mm512_add_epi64(index, _mm512_mask_blend_epi64(on0, _mm512_mask_blend_epi64(on1, step2, step1), step0));
    t0 = _mm512_mask_add_pd(t0, on0, t0, d0);
    t1 = _mm512_mask_add_pd(t1, on1, t1, d1);
    t2 = _mm512_mask_add_pd(t2, on2, t2, d2);
    const __mmask8 at_end = _mm512_cmpeq_epi64_mask(index, index_end);
    // min(t0, t1, t2) > length; the t's are never NaN, so min is the scalar one. (The masked
    // form with every lane set: GCC 12's plain _mm512_min_pd warns on its undefined source.)
    const __m512d low01 = _mm512_mask_min_pd(t0, __mmask8(0xFF), t0, t1);
    const __m512d low = _mm512_mask_min_pd(low01, __mmask8(0xFF), low01, t2);
    const __mmask8 past = _mm512_cmp_pd_mask(low, length, _CMP_GT_OQ);
    const auto visit = __mmask8(active & ~at_end & ~past);
    // Eight ORs every step, a zero bit into word 0 for the lanes that mark nothing: a loop
    // over the marking lanes mispredicts its count, and a compressing store to memory is
    // slow on some CPUs (AMD Zen 4). Lanes of one step may share a word: the ORs run in turn.
    _mm512_store_si512(word_of_lane, _mm512_maskz_srli_epi64(visit, index, 6));
    _mm512_store_si512(bit_of_lane, _mm512_maskz_sllv_epi64(visit, one, _mm512_and_si512(index, low6)));
    for (int k = 0; k < 8; ++k) words[word_of_lane[k]] |= bit_of_lane[k];
    active = visit;
  }
}

// Four lanes of AVX2. A lane's state lives in the vectors; refilling a lane stores them,
// writes the next ray into the lane's place and loads them again (a ray walks ~100 cells,
// so that happens every few dozen steps). The axis: walk_marked_ray's rule by compares and
// blends; the chosen axis's t gets its step and the others +0.0, which leaves a positive t
// as it is, bit for bit.
__attribute__((target("avx2"))) void mark_rays_in_four_lanes(const MarkedRays& r, std::uint64_t* words) {
  const std::size_t n = r.size();
  std::size_t next = 0;
  alignas(32) double t[3][4] = {}, d[3][4] = {}, length[4] = {};
  alignas(32) std::int64_t index[4] = {}, index_end[4] = {}, step[3][4] = {};
  __m256d t0 = _mm256_setzero_pd(), t1 = t0, t2 = t0, d0 = t0, d1 = t0, d2 = t0, len = t0;
  __m256i idx = _mm256_setzero_si256(), end = idx, s0 = idx, s1 = idx, s2 = idx;
  unsigned active = 0;
  while (true) {
    if (active != 0xF && next < n) {
      _mm256_store_pd(t[0], t0), _mm256_store_pd(t[1], t1), _mm256_store_pd(t[2], t2);
      _mm256_store_si256(reinterpret_cast<__m256i*>(index), idx);
      for (unsigned k = 0; k < 4 && next < n; ++k) {
        if (active >> k & 1) continue;
        t[0][k] = r.t0_[next], t[1][k] = r.t1_[next], t[2][k] = r.t2_[next];
        d[0][k] = r.d0_[next], d[1][k] = r.d1_[next], d[2][k] = r.d2_[next];
        length[k] = r.length_[next], index[k] = r.index_[next], index_end[k] = r.index_end_[next];
        step[0][k] = r.step0_[next], step[1][k] = r.step1_[next], step[2][k] = r.step2_[next];
        active |= 1u << k;
        ++next;
      }
      t0 = _mm256_load_pd(t[0]), t1 = _mm256_load_pd(t[1]), t2 = _mm256_load_pd(t[2]);
      d0 = _mm256_load_pd(d[0]), d1 = _mm256_load_pd(d[1]), d2 = _mm256_load_pd(d[2]);
      len = _mm256_load_pd(length);
      idx = _mm256_load_si256(reinterpret_cast<const __m256i*>(index));
      end = _mm256_load_si256(reinterpret_cast<const __m256i*>(index_end));
      s0 = _mm256_load_si256(reinterpret_cast<const __m256i*>(step[0]));
      s1 = _mm256_load_si256(reinterpret_cast<const __m256i*>(step[1]));
      s2 = _mm256_load_si256(reinterpret_cast<const __m256i*>(step[2]));
    }
    if (!active) return;
    const __m256d first = _mm256_cmp_pd(t0, t1, _CMP_LT_OQ);
    const __m256d below = _mm256_cmp_pd(_mm256_blendv_pd(t1, t0, first), t2, _CMP_LT_OQ);
    const __m256d on0 = _mm256_and_pd(first, below), on1 = _mm256_andnot_pd(first, below);
    const __m256d on2 = _mm256_andnot_pd(below, _mm256_castsi256_pd(_mm256_set1_epi64x(-1)));
    const __m256d chosen_step = _mm256_blendv_pd(
        _mm256_blendv_pd(_mm256_castsi256_pd(s2), _mm256_castsi256_pd(s1), on1), _mm256_castsi256_pd(s0), on0);
    idx = _mm256_add_epi64(idx, _mm256_castpd_si256(chosen_step));
    t0 = _mm256_add_pd(t0, _mm256_and_pd(d0, on0));
    t1 = _mm256_add_pd(t1, _mm256_and_pd(d1, on1));
    t2 = _mm256_add_pd(t2, _mm256_and_pd(d2, on2));
    const unsigned at_end = unsigned(_mm256_movemask_pd(_mm256_castsi256_pd(_mm256_cmpeq_epi64(idx, end))));
    const unsigned past =
        unsigned(_mm256_movemask_pd(_mm256_cmp_pd(_mm256_min_pd(_mm256_min_pd(t0, t1), t2), len, _CMP_GT_OQ)));
    const unsigned visit = active & ~at_end & ~past;
    // Four ORs, a zero bit into word 0 for the lanes that mark nothing (as eight lanes do).
    _mm256_store_si256(reinterpret_cast<__m256i*>(index), idx);
    for (unsigned k = 0; k < 4; ++k) {
      const std::uint64_t on = visit >> k & 1, i = std::uint64_t(index[k]);
      words[(i >> 6) & (0 - on)] |= on << (i & 63);
    }
    active = visit;
  }
}

}  // namespace fvx::map
