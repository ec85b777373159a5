// core::use_huge_page_heap: the heap grows once by the reserve, marked for transparent huge
// pages, and allocation goes on as before.
#include <gtest/gtest.h>
#include <malloc.h>
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "fvx/core/memory.hpp"

namespace fvx::test {
namespace {

/// The VmFlags line of /proc/self/smaps for the mapping that holds `p`, or "".
std::string heap_flags_at(const void* p) {
  std::ifstream smaps("/proc/self/smaps");
  std::string line;
  bool inside = false;
  const auto at = reinterpret_cast<std::uintptr_t>(p);
  while (std::getline(smaps, line)) {
    unsigned long lo = 0, hi = 0;
    char dash = 0;
    // A mapping's first line: "lo-hi perms …"; its VmFlags line comes last.
    if (std::sscanf(line.c_str(), "%lx%c%lx", &lo, &dash, &hi) == 3 && dash == '-')
      inside = lo <= at && at < hi;
    else if (inside && line.rfind("VmFlags:", 0) == 0)
      return line;
  }
  return "";
}

TEST(HugePageHeap, TheHeapGrowsByTheReserveMarkedForHugePages) {
  // Deliberately skipped where the heap is left as it comes (the sanitizers' allocator,
  // strict overcommit, FVX_DEFAULT_HEAP): there is nothing to check.
  if (!core::huge_page_heap_applies())
    GTEST_SKIP() << "the heap is left as it comes here (sanitizers, strict overcommit or FVX_DEFAULT_HEAP)";
  core::use_huge_page_heap();
  rlimit limit{};
  std::size_t reserve = std::size_t(512) << 20;
  if (getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
    reserve = std::min<std::size_t>(reserve, limit.rlim_cur / 8);
  EXPECT_GE(mallinfo2().arena, reserve);  // bytes the main arena took from the system
  // A block of 4 MiB (glibc would have mapped it on its own) now comes from that heap, which
  // carries the huge-page advice (VmFlags "hg") from the first 2 MiB boundary of the reserve
  // on (the block may begin in the heap below it).
  std::vector<char> block(std::size_t(4) << 20, 1);
  const char* last = &block.back();
  EXPECT_NE(heap_flags_at(last).find(" hg"), std::string::npos) << heap_flags_at(last);
  // And memory is memory: written and read back across the reserve.
  std::vector<std::vector<int>> blocks;
  for (int i = 0; i < 64; ++i) blocks.emplace_back(std::size_t(1) << 18, i);
  for (int i = 0; i < 64; ++i) EXPECT_EQ(blocks[std::size_t(i)][12345], i);
}

}  // namespace
}  // namespace fvx::test
