#pragma once
/// \file
/// std::vector for arrays with one entry per grid cell (dense grids, distance transforms,
/// the utility field): tens to hundreds of megabytes on a real map. Above 4 MiB they are
/// mapped on their own and backed by transparent huge pages (madvise; Debian's default THP
/// mode), so that filling them costs one page fault per 2 MiB instead of one per 4 KiB.
/// Measured on the whole `fvx nbv` over the real slambook and geb079 maps, page faults were
/// a sixth of the run time before (scripts/bench-nbv-scale.sh). Smaller arrays, and systems
/// without THP, take the usual path.
#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <vector>

namespace fvx::core {

template <typename T>
struct HugePageAllocator {
  using value_type = T;
  static constexpr std::size_t kMinBytes = std::size_t(4) << 20;
  static constexpr std::size_t kHugePage = std::size_t(2) << 20;

  HugePageAllocator() = default;
  template <typename U>
  HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

  T* allocate(std::size_t n) {
    if (n > std::size_t(-1) / sizeof(T)) throw std::bad_alloc();
    const std::size_t bytes = n * sizeof(T);
    if (bytes < kMinBytes) return std::allocator<T>().allocate(n);
    // Map a huge page more than needed and unmap the ends, so that the array starts on a
    // huge page boundary and every full 2 MiB of it can be one huge page.
    const std::size_t length = mapped_length(bytes);
    void* raw = mmap(nullptr, length + kHugePage, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (raw == MAP_FAILED) throw std::bad_alloc();
    const auto start = reinterpret_cast<std::uintptr_t>(raw);
    const std::uintptr_t aligned = (start + kHugePage - 1) & ~(kHugePage - 1);
    if (aligned > start) munmap(raw, aligned - start);
    const std::uintptr_t end = start + length + kHugePage;
    if (end > aligned + length) munmap(reinterpret_cast<void*>(aligned + length), end - (aligned + length));
    madvise(reinterpret_cast<void*>(aligned), length, MADV_HUGEPAGE);  // advice only: no THP, no harm
    return reinterpret_cast<T*>(aligned);
  }

  void deallocate(T* p, std::size_t n) noexcept {
    const std::size_t bytes = n * sizeof(T);
    if (bytes < kMinBytes) return std::allocator<T>().deallocate(p, n);
    munmap(p, mapped_length(bytes));
  }

  friend bool operator==(const HugePageAllocator&, const HugePageAllocator&) { return true; }
  friend bool operator!=(const HugePageAllocator&, const HugePageAllocator&) { return false; }

 private:
  static std::size_t mapped_length(std::size_t bytes) { return (bytes + kHugePage - 1) & ~(kHugePage - 1); }
};

/// A vector with one entry per grid cell.
template <typename T>
using LargeVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace fvx::core
