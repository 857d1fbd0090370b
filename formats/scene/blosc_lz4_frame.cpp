#include "formats/scene/blosc_lz4_frame.h"

#include <lz4.h>

#include <climits>
#include <cstdint>
#include <cstring>
#include <vector>

namespace vox {

namespace {

// Blosc 1.21's constants (blosc.h, blosc.c).
constexpr int64_t kMinBufferSize = 128;  // smaller inputs are stored
constexpr int64_t kMaxSplits = 16;       // types wider than this are never split
constexpr int64_t kMaxTypeSize = 255;
constexpr int64_t kMaxBufferSize = int64_t(INT_MAX) - int64_t(kBloscFrameOverhead);
constexpr int64_t kMaxBlockSize = (int64_t(INT_MAX) - kMaxTypeSize * int64_t(sizeof(int32_t))) / 3;
constexpr uint8_t kFormatVersion = 2, kLz4FormatVersion = 1, kLz4Format = 1;
constexpr uint8_t kShuffled = 0x1, kStored = 0x2, kNoSplit = 0x10;
constexpr int kLz4Acceleration = 10 - 9;  // Blosc's get_accel for LZ4 at compression level 9

void put32(uint8_t* at, int64_t v) {
  const uint32_t u = uint32_t(int32_t(v));
  at[0] = uint8_t(u), at[1] = uint8_t(u >> 8), at[2] = uint8_t(u >> 16), at[3] = uint8_t(u >> 24);
}

/// Blosc's split_block in its default mode (BLOSC_FORWARD_COMPAT_SPLIT), for LZ4.
bool splits(int64_t typeSize, int64_t blockSize) { return typeSize <= kMaxSplits && blockSize / typeSize >= kMinBufferSize; }

/// Blosc's compute_blocksize with the block size forced to nbytes, at level 9.
int64_t blockSizeFor(int64_t typeSize, int64_t nbytes) {
  if (nbytes < typeSize) return 1;
  int64_t block = nbytes;  // forced (nbytes > 0 here)
  if (block < kMinBufferSize) block = kMinBufferSize;
  if (block > kMaxBlockSize) block = kMaxBlockSize;
  if (splits(typeSize, block)) {
    if (block > (int64_t(1) << 18)) block = int64_t(1) << 18;
    block *= typeSize;
    if (block < (int64_t(1) << 16)) block = int64_t(1) << 16;
    if (block > (int64_t(1) << 20)) block = int64_t(1) << 20;
  }
  if (block > nbytes) block = nbytes;
  if (block > typeSize) block = block / typeSize * typeSize;
  return block;
}

/// Blosc's byte shuffle: byte j of element i goes to j * elements + i; the
/// bytes after the last whole element stay where they are.
void shuffle(int64_t typeSize, int64_t bytes, const uint8_t* src, uint8_t* dst) {
  const int64_t elements = bytes / typeSize, rest = bytes % typeSize;
  for (int64_t j = 0; j < typeSize; ++j)
    for (int64_t i = 0; i < elements; ++i) dst[j * elements + i] = src[i * typeSize + j];
  std::memcpy(dst + (bytes - rest), src + (bytes - rest), size_t(rest));
}

/// Blosc's blosc_c: one block at dest (ntbytes already written, room up to
/// maxBytes), returning its bytes, 0 when it does not fit, < 0 on LZ4's failure.
int64_t compressBlock(const uint8_t* src, int64_t bytes, bool leftover, bool noSplit, int64_t typeSize, int64_t ntbytes,
                      int64_t maxBytes, uint8_t* dest) {
  const uint8_t* streams = src;
  if (typeSize > 1) {
    thread_local std::vector<uint8_t> shuffled;
    if (shuffled.size() < size_t(bytes)) shuffled.resize(size_t(bytes));
    shuffle(typeSize, bytes, src, shuffled.data());
    streams = shuffled.data();
  }
  const int64_t nStreams = (!noSplit && !leftover) ? typeSize : 1;
  const int64_t perStream = bytes / nStreams;
  int64_t written = 0;
  for (int64_t j = 0; j < nStreams; ++j) {
    dest += 4, ntbytes += 4, written += 4;
    int64_t maxOut = perStream;
    if (ntbytes + maxOut > maxBytes) {
      maxOut = maxBytes - ntbytes;
      if (maxOut <= 0) return 0;
    }
    const char* in = reinterpret_cast<const char*>(streams + j * perStream);
    int64_t n = LZ4_compress_fast(in, reinterpret_cast<char*>(dest), int(perStream), int(maxOut), kLz4Acceleration);
    if (n > maxOut || n < 0) return -1;
    if (n == 0 || n == perStream) {  // LZ4 could not make it smaller: the shuffled bytes as they are
      if (ntbytes + perStream > maxBytes) return 0;
      std::memcpy(dest, in, size_t(perStream));
      n = perStream;
    }
    put32(dest - 4, n);
    dest += n, ntbytes += n, written += n;
  }
  return written;
}

}  // namespace

size_t bloscLz4Frame(const void* srcVoid, size_t nbytesIn, size_t typeSizeIn, void* destVoid, size_t destSizeIn) {
  if (nbytesIn > size_t(kMaxBufferSize) || destSizeIn < kBloscFrameOverhead) return 0;
  const auto* src = static_cast<const uint8_t*>(srcVoid);
  auto* dest = static_cast<uint8_t*>(destVoid);
  const int64_t nbytes = int64_t(nbytesIn);
  // Blosc keeps destsize in an int32.
  const int64_t destSize = int64_t(int32_t(destSizeIn > size_t(INT_MAX) ? INT_MAX : destSizeIn));
  const int64_t typeSize = int64_t(typeSizeIn) > kMaxTypeSize || typeSizeIn == 0 ? 1 : int64_t(typeSizeIn);
  const int64_t block = blockSizeFor(typeSize, nbytes);
  const int64_t leftover = nbytes % block;
  const int64_t nBlocks = nbytes / block + (leftover > 0 ? 1 : 0);

  // write_compression_header
  uint8_t flags = kShuffled | uint8_t((splits(typeSize, block) ? 0 : kNoSplit)) | uint8_t(kLz4Format << 5);
  int64_t headerBytes = 16 + 4 * nBlocks;
  if (nbytes < kMinBufferSize) flags |= kStored, headerBytes = 16;
  dest[0] = kFormatVersion;
  dest[1] = kLz4FormatVersion;
  dest[3] = uint8_t(typeSize);
  put32(dest + 4, nbytes);
  put32(dest + 8, block);

  // blosc_compress_context and serial_blosc
  auto store = [&]() -> int64_t {
    if (nbytes + int64_t(kBloscFrameOverhead) > destSize) return 0;
    if (nbytes) std::memcpy(dest + 16, src, size_t(nbytes));
    return 16 + nbytes;
  };
  int64_t total = 0;
  if (flags & kStored) {
    total = store();
    if (total == 0) {
      dest[2] = flags;
      return 0;
    }
  } else {
    total = headerBytes;
    for (int64_t j = 0; j < nBlocks; ++j) {
      put32(dest + 16 + 4 * j, total);
      const bool last = j == nBlocks - 1 && leftover > 0;
      const int64_t n = compressBlock(src + j * block, last ? leftover : block, last, (flags & kNoSplit) != 0, typeSize,
                                      total, destSize, dest + total);
      if (n < 0) return 0;
      if (n == 0) {
        total = 0;
        break;
      }
      total += n;
    }
    if (total == 0) {  // Blosc's last chance: stored, if it fits
      flags |= kStored;
      total = store();
    }
  }
  dest[2] = flags;
  put32(dest + 12, total);
  return size_t(total);
}

}  // namespace vox
