#pragma once
/// \file
/// What the machine can give: a run that would need more memory than is available stops
/// before it allocates, with a message saying what to make smaller, instead of being killed.
#include <cstddef>
#include <optional>

namespace fvx::core {

/// Bytes of memory available to new allocations (Linux: MemAvailable in /proc/meminfo),
/// or none where the system does not say.
std::optional<std::size_t> available_memory_bytes();

}  // namespace fvx::core
