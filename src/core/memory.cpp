#include "fvx/core/memory.hpp"

#include <malloc.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>

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

namespace {

#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define FVX_SANITIZED_ALLOCATOR 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define FVX_SANITIZED_ALLOCATOR 1
#endif

[[maybe_unused]] bool strict_overcommit() {  // unused under the sanitizers
  std::ifstream mode("/proc/sys/vm/overcommit_memory");
  int value = 0;
  return mode >> value && value == 2;
}

/// 512 MiB, or an eighth of the address-space limit when one is set (ulimit -v).
std::size_t heap_reserve_bytes() {
  std::size_t reserve = std::size_t(512) << 20;
  rlimit limit{};
  if (getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
    reserve = std::min<std::size_t>(reserve, std::size_t(limit.rlim_cur) / 8);
  return reserve;
}

}  // namespace

int end_process(int status) {
#ifndef FVX_SANITIZED_ALLOCATOR
  std::cout.flush();
  std::cerr.flush();
  std::clog.flush();
  std::fflush(nullptr);  // every C stream
  std::_Exit(status);
#endif
  return status;
}

bool huge_page_heap_applies() {
#ifdef FVX_SANITIZED_ALLOCATOR
  return false;
#else
  return !std::getenv("FVX_DEFAULT_HEAP") && !strict_overcommit();
#endif
}

void use_huge_page_heap() {
  if (!huge_page_heap_applies()) return;
  const std::size_t reserve = heap_reserve_bytes(), huge_page = std::size_t(2) << 20;
  mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's largest: blocks up to 32 MiB come from the heap
  mallopt(M_TRIM_THRESHOLD, 1 << 30);   // and the reserve is not handed back when they are freed
  mallopt(M_TOP_PAD, int(reserve));
  void* block = std::malloc(std::size_t(1) << 20);  // more than a new heap holds: it grows by the reserve
  const auto end = reinterpret_cast<std::uintptr_t>(sbrk(0));
  const auto start = (reinterpret_cast<std::uintptr_t>(block) + huge_page - 1) & ~(huge_page - 1);
  // Only when the block lies in the heap below its end (not mapped elsewhere on a failure).
  if (block && start < end && end - start <= reserve + huge_page)
    madvise(reinterpret_cast<void*>(start), end - start, MADV_HUGEPAGE);  // advice: without THP, no harm
  std::free(block);
  mallopt(M_TOP_PAD, 128 << 10);  // glibc's default: the heap grows as usual beyond the reserve
}

}  // namespace fvx::core
