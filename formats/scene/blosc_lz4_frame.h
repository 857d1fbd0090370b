// Blosc 1 frames of byte-shuffled LZ4, as OpenVDB's Blosc compression stores a
// leaf's values, written without Blosc's own bookkeeping.
//
// Why not blosc_compress_ctx: Blosc 1 has no reusable context, so every call
// allocates (and frees) its shuffle buffers with posix_memalign. The scene
// writer compresses every leaf of every grid on all its workers, and vox runs
// with one malloc arena (tools/cli/alloc_tuning.h), so with two workers those
// calls queued on the arena's lock: writing the bunny's scene at 256 took 14 ms
// on 2 threads against 8 ms on one (docs/bench-voxelize.md, "The write on
// two threads, and votes inline"). This writes the same bytes with a per-thread buffer and the
// same LZ4 call Blosc makes; the unit test BloscLz4Frame.* compares the two
// byte for byte.
//
// Format (Blosc 1, format version 2), all integers little-endian:
//   byte 0       2: the Blosc format version
//   byte 1       1: the LZ4 format version
//   byte 2       flags: 0x01 byte-shuffled, 0x02 stored (memcpy), 0x10 blocks
//                not split into one stream per byte of the type, 0x20 LZ4 (1 << 5)
//   byte 3       the type size (bytes per element the shuffle transposes)
//   bytes 4-7    nbytes, the uncompressed size
//   bytes 8-11   the block size
//   bytes 12-15  the frame's size, header included
//   then, unless stored: one int32 offset per block (from the frame's start),
//   each block as its streams (one per byte of the type when split, else one),
//   each stream an int32 size and that many bytes: LZ4's block format, or the
//   shuffled bytes themselves when LZ4 cannot make them smaller. Stored frames
//   carry the nbytes bytes after the 16-byte header.
#pragma once

#include <cstddef>

namespace vox {

/// The most a frame adds to its input: the 16-byte header (BLOSC_MAX_OVERHEAD).
inline constexpr size_t kBloscFrameOverhead = 16;

/// Compresses the `nbytes` bytes at `src` into one Blosc 1 frame at `dest`
/// (room for `destSize` bytes) and returns its size, or 0 when it does not fit
/// (or nbytes exceeds Blosc's limit, 2^31 - 17). The bytes are those of
/// blosc_compress_ctx(9, BLOSC_SHUFFLE, typeSize, nbytes, src, dest, destSize,
/// "lz4", nbytes, 1) with Blosc 1.21: compression level 9 (LZ4's acceleration
/// 1), byte shuffle, a block size of nbytes (the whole buffer), the default
/// split mode. Give destSize >= nbytes + kBloscFrameOverhead and the frame
/// always fits (stored when it does not compress).
/// Thread-safe: each thread keeps its own shuffle buffer (grown to its largest
/// block, never freed before the thread ends); nothing else is shared.
size_t bloscLz4Frame(const void* src, size_t nbytes, size_t typeSize, void* dest, size_t destSize);

}  // namespace vox
