#pragma once
/// \file
/// How many threads a stage runs: the `--threads` convention of every command, in one place.
#include <algorithm>
#include <cstddef>
#include <limits>
#include <thread>

namespace fvx::core {

/// `requested` threads, 0 meaning all cores (at least one when the count is unknown), and no
/// more than `work_items` (at least one): a thread without work only costs its start.
inline unsigned worker_count(unsigned requested,
                             std::size_t work_items = std::numeric_limits<std::size_t>::max()) {
  const unsigned wanted = requested ? requested : std::max(1u, std::thread::hardware_concurrency());
  return unsigned(std::max<std::size_t>(1, std::min<std::size_t>(wanted, work_items)));
}

}  // namespace fvx::core
