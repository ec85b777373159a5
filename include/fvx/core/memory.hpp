#pragma once
/// \file
/// What the machine can give: a run that would need more memory than is available stops
/// before it allocates, with a message saying what to make smaller, instead of being killed.
#include <Eigen/Geometry>
#include <cstddef>
#include <optional>
#include <string>

namespace fvx::core {

/// Bytes of memory available to new allocations (Linux: MemAvailable in /proc/meminfo),
/// or none where the system does not say.
std::optional<std::size_t> available_memory_bytes();

/// Throws Error when a dense array over `box_m` at `resolution_m`, `bytes_per_cell` per cell,
/// would need more memory than is available, or more cells than a grid indexes (4·10⁹). The
/// message names `what` holds the cells, the figures, and `advice` (what to make smaller).
void require_memory_for_box(const Eigen::AlignedBox3d& box_m, double resolution_m, double bytes_per_cell,
                            const std::string& what, const std::string& advice);

}  // namespace fvx::core
