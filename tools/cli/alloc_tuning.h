// glibc's allocator tuned for a process that touches tens of MB to GBs of
// fresh heap: a mesh bake (tools/bake/voxelize_mesh.cpp), a pack of a scene's
// leaves (tools/cmds/pack_chunks_light.cpp), a fusion of views
// (tools/cmds/cmd_fuse.cpp, with growAdvisedHeap for its estimated peak).
//
// With glibc's defaults that memory arrives 4 KB page by page (big arrays
// through separate mmaps, a thread arena per thread), and the page faults
// were a third of a 256^3 surface bake on the benchmark VM (~5000 faults) and
// a fifth of packing a 1024^3 surface scene (~17000). So, for this process
// only: one arena, big arrays from the heap, the heap grown in 256 MB steps of
// address space, and that range marked for transparent huge pages. Resident
// memory still counts only what is touched (in 2 MB pages: a few MB more at most).
#pragma once

#include <cstdint>

namespace voxcli {

/// Call once it is certain this process does the work (not before a command
/// defers to another module). VOX_DEFAULT_MALLOC set: does nothing (to measure).
void tuneAllocatorForShortRun();

/// After tuneAllocatorForShortRun, for a run whose peak is known to pass the
/// 256 MB it advises (a fusion of many views: its memory estimate): grows the
/// heap once by `expectedPeakBytes` (at most 1.5 GiB) of address space, marked
/// for transparent huge pages, and keeps it grown. Resident memory still
/// counts only the pages touched. VOX_DEFAULT_MALLOC set: does nothing.
void growAdvisedHeap(uint64_t expectedPeakBytes);

}  // namespace voxcli
