#pragma once
/// \file
/// Stage `utility` (paper §IV-C, Algorithm 1): utility vectors from each frontier-void's
/// ellipsoid corners through its frontier cells, traced into free space, their utility
/// accumulated per cell. For every frontier-void fv_i = (v_i, F_i), every corner c of v_i
/// (μ_i and μ_i ± a_ij·e_ij, ARCHITECTURE.md §3) and every frontier cell f of F_i, a ray
/// starts at pos(f), goes along normalize(pos(f) − c) for at most s_r, and stops at the first
/// cell that is not free; each cell it passes, f included, gains u_i. Cells with much
/// utility see many voids through their frontiers: candidate viewpoints.
///
/// Two ways to accumulate (Config::accumulation):
/// - Exact: every vector, as Algorithm 1 writes it. Its cost is Σ_i 7·|F_i| rays; on real
///   maps one frontier cluster touching a thousand voids makes hundreds of millions.
/// - Sampled (default): when the exact count exceeds Config::max_vectors, each
///   frontier-void traces all 7 corners from a stratified sample of S_i of its |F_i|
///   frontier cells (strata along a Morton order, so the sample spreads over the frontier
///   surface), each vector weighted u_i·|F_i|/S_i. Every frontier cell is drawn with
///   probability S_i/|F_i|, so the expected field is the exact field, cell by cell. The
///   budget goes to frontier-voids in proportion to u_i·|F_i| (their share of the exact
///   field's total), so every traced vector carries about the same utility. Under the
///   budget the sampled field is the exact field.
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "fvx/frontier_voids/frontier_voids.hpp"
#include "fvx/core/large_vector.hpp"
#include "fvx/map/dense_grid.hpp"

namespace fvx::utility {

enum class Accumulation { Exact, Sampled };
const char* to_string(Accumulation a);
/// "exact" or "sampled"; UsageError naming `what` otherwise.
Accumulation parse_accumulation(const std::string& name, const std::string& what = "--accumulation");

struct Config {
  double sensor_range_m = 4.0;  ///< s_r: the longest a utility ray goes, metres (Kinect v1: 4)
  /// A ray adds utility only to cells at least this far from its frontier cell, metres (it
  /// is still traced, and stopped, from the frontier on). 0: the paper's Algorithm 1, every
  /// cell from the frontier on. The sensor's minimum depth: a viewpoint nearer to the
  /// frontier than that measures nothing behind it.
  double min_range_m = 0.0;
  unsigned threads = 0;         ///< 0: all cores; the field is the same on any count
  Accumulation accumulation = Accumulation::Sampled;
  /// Sampled: the number of utility vectors to trace at most (about; every frontier-void
  /// keeps at least kMinSamples frontier cells). Under it, every vector is traced.
  std::size_t max_vectors = std::size_t(1) << 21;
  std::uint64_t seed = 1;       ///< sampled: which frontier cells each stratum draws
  /// The box (metres) holding every cell whose utility is read afterwards (the search's
  /// candidate viewpoints: view bounds, the arm's reach). A ray is walked only as far as it
  /// can still reach a cell of the box, and not at all when it misses the box: the field is
  /// exact inside it and partial outside. None: the whole grid.
  std::optional<Eigen::AlignedBox3d> read_box_m;
  /// Called on the calling thread now and then: frontier-voids traced so far, and in all.
  std::function<void(std::size_t done, std::size_t total)> progress;
  std::vector<std::string> validate() const;
};

/// How many contributing frontier-voids a cell remembers (the largest by utility): the
/// voids a sensor at the cell should be turned towards.
constexpr int kContributors = 4;
/// Sampled: frontier cells every frontier-void keeps at least (all of them when it has fewer).
constexpr std::size_t kMinSamples = 8;

/// Per grid cell, the indices (into Analysis::frontier_voids) of the kContributors
/// frontier-voids with the largest utility whose vectors pass it (ties: lower index), −1 for
/// unused slots, largest first. Kept only for the cells some vector passed, behind a 4-byte
/// slot per cell: a list per cell took 16 bytes on every cell of the grid (176 MB filled on
/// the 11 M-cell grid of the slambook frames at 2.5 cm, a seventh of that search's time).
/// The lists are kept per stripe of cells (stripe()), so that threads may fill cells of
/// different stripes at once.
class Contributors {
 public:
  using List = std::array<std::int32_t, kContributors>;
  static constexpr std::size_t kStripes = 64;
  /// Stripes of 4 096 consecutive cells (a few rows of a grid), dealt round-robin.
  static std::size_t stripe(std::size_t cell) { return (cell >> 12) % kStripes; }
  explicit Contributors(std::size_t cells = 0) : slot_(cells, 0) {}
  std::size_t size() const { return slot_.size(); }
  /// The list of `cell`: −1 in every slot when no vector passed it.
  const List& operator[](std::size_t cell) const {
    return slot_[cell] ? lists_[stripe(cell)][slot_[cell] - 1] : kNone;
  }
  /// The list of `cell` to fill, made (all −1) on first use. Threads may call it at once
  /// for cells of different stripes.
  List& make(std::size_t cell);
  /// Cell by cell.
  bool operator==(const Contributors& other) const;
  bool operator!=(const Contributors& other) const { return !(*this == other); }

 private:
  static constexpr List kNone{-1, -1, -1, -1};
  core::LargeVector<std::uint32_t> slot_;  ///< per cell: 0, or 1 + its index in its stripe's list
  std::array<std::vector<List>, kStripes> lists_;
};

struct Field {
  core::LargeVector<double> util_m3;  ///< per grid cell (DenseGrid index), the sum of u_i through it
  Contributors contributors;
  std::size_t vectors = 0;      ///< utility vectors traced
  std::size_t exact_vectors = 0;  ///< what the exact accumulation traces (7 per frontier cell and frontier-void)
  bool sampled = false;         ///< vectors < exact_vectors: the field is an unbiased estimate
  std::size_t cells = 0;        ///< cells with utility > 0
  double max_m3 = 0.0;
};

/// Accumulates Algorithm 1 over `grid` (the map within the search space). Frontier cells
/// outside the grid cast no ray; rays end at the grid's edge.
Field accumulate(const map::DenseGrid& grid, const frontier_voids::Analysis& analysis, const Config& config);

}  // namespace fvx::utility
