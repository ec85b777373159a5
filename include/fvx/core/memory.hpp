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

/// Once, at the start of a process (fvx's main), before the work allocates: glibc's heap is
/// made to grow once by 512 MiB (less under a smaller address-space limit) of address space
/// backed by transparent huge pages, to serve every block up to 32 MiB from it (glibc would
/// map each block above 128 KiB on its own, and unmap it when freed). Other threads keep
/// their own arenas: one arena for all made `fvx capmap build` 2.7x slower (its threads waited
/// on the arena's lock). Why: each first touch of a 4 KiB page is a page fault, and on the virtual
/// machines fvx was measured on a fault costs about 11 µs, 3 ms per MiB touched: the
/// analysis's key lists and clusters, grown a block at a time, made 35 000 faults (a third of
/// a second) of `fvx nbv` on geb079, 5 900 with this (README, "Page faults"). Freed blocks stay
/// in the heap for the next one instead of being faulted in again. Nothing is done under
/// strict overcommit (vm.overcommit_memory = 2, where the reserve would be charged), under the
/// sanitizers (they bring their own allocator), or when FVX_DEFAULT_HEAP is set.
void use_huge_page_heap();
/// Whether use_huge_page_heap() does anything in this process: not under the sanitizers'
/// allocator, strict overcommit or FVX_DEFAULT_HEAP.
bool huge_page_heap_applies();

/// Ends the process with `status` once a command's outputs are written and closed, without
/// freeing what it built: the kernel takes the address space back at once, where freeing an
/// octree node by node took 0.6 s of a 5 s `fvx integrate` (README, "Ending a command").
/// Flushes every stream first. Under the sanitizers it returns `status` instead, so that
/// their leak checks still see every block freed. For a command's last line only:
/// `return core::end_process(0);`.
int end_process(int status);

}  // namespace fvx::core
