#include "fvx/core/memory.hpp"

#include <cstdio>
#include <fstream>

#include "fvx/core/error.hpp"

namespace fvx::core {

std::optional<std::size_t> available_memory_bytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string name, unit;
  unsigned long long kib = 0;
  while (meminfo >> name >> kib >> unit)
    if (name == "MemAvailable:") return std::size_t(kib) * 1024;
  return std::nullopt;
}

void require_memory_for_box(const Eigen::AlignedBox3d& box_m, double resolution_m, double bytes_per_cell,
                            const std::string& what, const std::string& advice) {
  if (box_m.isEmpty()) return;
  const Eigen::Vector3d size_m = box_m.sizes();
  const double cells = (size_m / resolution_m).prod(), need = cells * bytes_per_cell;
  const std::optional<std::size_t> available = available_memory_bytes();
  const bool too_many = cells >= 4e9, too_large = available && need > double(*available);
  if (!too_many && !too_large) return;
  char figures[200];
  std::snprintf(figures, sizeof figures, " holds %.0f M cells (%.1f x %.1f x %.1f m at %g m)", cells / 1e6,
                size_m.x(), size_m.y(), size_m.z(), resolution_m);
  char limit[160];
  if (too_large)
    std::snprintf(limit, sizeof limit, ": about %.1f GiB, and %.1f GiB of memory is available", need / double(1ull << 30),
                  double(*available) / double(1ull << 30));
  else
    std::snprintf(limit, sizeof limit, ", more than the 4000 M a grid indexes");
  throw Error(what + figures + limit + "; " + advice);
}

}  // namespace fvx::core
