#include "fvx/core/memory.hpp"

#include <fstream>
#include <string>

namespace fvx::core {

std::optional<std::size_t> available_memory_bytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string name, unit;
  unsigned long long kib = 0;
  while (meminfo >> name >> kib >> unit)
    if (name == "MemAvailable:") return std::size_t(kib) * 1024;
  return std::nullopt;
}

}  // namespace fvx::core
