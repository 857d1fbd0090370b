// glibc's allocator tuned for a short process that touches tens to hundreds
// of MB of fresh heap: a mesh bake (tools/bake/voxelize_mesh.cpp) or a pack of
// a scene's leaves (tools/cmds/pack_chunks_light.cpp).
//
// With glibc's defaults that memory arrives 4 KB page by page (big arrays
// through separate mmaps, a thread arena per thread), and the page faults
// were a third of a 256^3 surface bake on the benchmark VM (~5000 faults) and
// a fifth of packing a 1024^3 surface scene (~17000). So, for this process
// only: one arena, big arrays from the heap, the heap grown in 256 MB steps of
// address space, and that range marked for transparent huge pages. Resident
// memory still counts only what is touched (in 2 MB pages: a few MB more at most).
#pragma once

namespace voxcli {

/// Call once it is certain this process does the work (not before a command
/// defers to another module). VOX_DEFAULT_MALLOC set: does nothing (to measure).
void tuneAllocatorForShortRun();

}  // namespace voxcli
