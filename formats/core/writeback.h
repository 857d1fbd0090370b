// Writeback hints for outputs written front to back.
//
// Every output is flushed to disk (fsync) before it is renamed into place
// (file_util.h, AtomicOutput), and that wait is on the critical path of every
// run. A writer that streams its bytes can hand each finished range to the
// kernel's writeback as it goes, so the disk works while the rest is still
// being produced and the final fsync waits for the tail only (measured in
// docs/bench-voxelize.md, "Writeback while writing").
#pragma once

#include <cstdint>
#include <cstdio>

namespace vox {

/// How many bytes a streaming writer lets accumulate before it hands them on.
inline constexpr uint64_t kWritebackStride = uint64_t(1) << 20;

/// Asks the kernel to start writing bytes [from, to) of the open file `fd` to
/// disk, without waiting (Linux sync_file_range, SYNC_FILE_RANGE_WRITE; a no-op
/// elsewhere). The caller has flushed its own buffers up to `to`. A hint only:
/// it never fails, and write errors still surface at the fsync.
void startWriteback(int fd, uint64_t from, uint64_t to);

/// The step both streaming writers take after each write: once `written`
/// (bytes written to `file` so far) is a stride past `queued` (bytes already
/// handed on), flushes `file`'s buffer and hands [queued, written) on.
/// Returns false when that flush fails (errno set): the caller reports it as
/// a failed write.
bool handOnWritten(std::FILE* file, uint64_t written, uint64_t& queued);

}  // namespace vox
