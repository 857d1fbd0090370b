#include "formats/pagefile/bricks_layout.h"

#include <bit>
#include <cstring>
#include <string>

#include "formats/pagefile/layout_io.h"
#include "formats/pagefile/pagefile.h"
#include "libvox/core/bits.h"

namespace vox::pagefile {

uint64_t bricksPayloadBytes(uint32_t chunkVoxels, uint32_t occupied, bool full, uint32_t flags) {
  uint64_t n = full ? 0 : chunkVoxels / 8;
  n += 4ull * occupied;
  if (flags & kFlagColor) n += 4ull * occupied;
  if (flags & kFlagSurface) n += (uint64_t(occupied) + 7) / 8;
  return n;
}

uint64_t bricksSizeFromIndex(const Header& h, const IndexEntry& e) {
  return bricksPayloadBytes(h.chunkVoxels(), e.occupied, e.flags & kChunkFull, h.flags);
}

std::vector<uint8_t> encodeBricks(const ChunkVoxels& chunk, uint32_t flags, const ChunkPlace&) {
  const uint32_t N = chunk.side * chunk.side * chunk.side;
  const bool full = chunk.count == N;
  const bool color = flags & kFlagColor, surfaceCh = flags & kFlagSurface;
  std::vector<uint8_t> bytes(bricksPayloadBytes(N, chunk.count, full, flags), 0);
  uint8_t* p = bytes.data();
  if (!full) {
    for (uint32_t w = 0; w < N / 64; ++w) storeLE<uint64_t>(p + 8 * w, chunk.bits[w]);
    p += N / 8;
  }
  uint8_t* sum = p;
  uint8_t* colp = sum + 4ull * chunk.count;
  uint8_t* surf = colp + (color ? 4ull * chunk.count : 0);
  uint32_t rank = 0;
  for (uint32_t w = 0; w < N / 64; ++w)
    for (uint64_t word = chunk.bits[w]; word; word &= word - 1) {
      const uint32_t k = w * 64 + uint32_t(std::countr_zero(word));
      std::memcpy(sum + 4 * rank, chunk.summary[k].data(), 4);
      if (color) std::memcpy(colp + 4 * rank, chunk.color[k].data(), 4);
      if (surfaceCh && chunk.surface[k]) setBit(surf, rank);
      ++rank;
    }
  return bytes;
}

namespace {

// The occupied voxels (index only), from the bitmap or, for a full chunk, all
// of them; checks the popcount and the domain. Returns the bytes after the bitmap.
const uint8_t* readOccupancy(const ChunkPayload& in, std::vector<DecodedVoxel>& out) {
  const Header& h = in.header;
  const IndexEntry& e = in.entry;
  const uint32_t C = h.chunkSide(), N = h.chunkVoxels();
  const uint8_t* p = in.bytes.data();
  const auto lim = chunkLimits(h, e);
  if (e.flags & kChunkFull) {
    if (lim[0] != C || lim[1] != C || lim[2] != C) in.fail("field 'flags': a full chunk that crosses the edge of the domain");
    for (uint32_t k = 0; k < N; ++k) out.push_back({k, {}, true, {}});
    return p;
  }
  uint64_t count = 0;
  for (uint32_t w = 0; w < N / 64; ++w) {
    uint64_t word = loadLE<uint64_t>(p + 8 * w);
    count += uint64_t(bitCount(word));
    while (word) {
      const uint32_t k = w * 64 + uint32_t(std::countr_zero(word));
      word &= word - 1;
      const uint32_t x = k & (C - 1), y = (k >> h.chunkLog2) & (C - 1), z = k >> (2 * h.chunkLog2);
      if (x >= lim[0] || y >= lim[1] || z >= lim[2])
        in.fail("field 'bitmap': voxel (" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z) +
                ") of the chunk lies outside the level's dims");
      out.push_back({k, {}, true, {}});
    }
  }
  if (count != e.occupied)
    in.fail("field 'bitmap': " + std::to_string(count) + " bits set, the index says " + std::to_string(e.occupied) +
            " occupied voxels");
  return p + N / 8;
}

const uint8_t* readSummaries(const ChunkPayload& in, const uint8_t* p, std::vector<DecodedVoxel>& out) {
  for (DecodedVoxel& v : out) {
    std::memcpy(v.summary.data(), p, 4);
    p += 4;
    if (v.summary[0] == 0) in.fail("field 'summary': voxel " + std::to_string(v.index) + " is occupied but has class 0");
  }
  return p;
}

const uint8_t* readColors(const ChunkPayload& in, const uint8_t* p, std::vector<DecodedVoxel>& out) {
  for (DecodedVoxel& v : out) {
    std::memcpy(v.color.data(), p, 4);
    p += 4;
    if (const char* why = colorProblem(v.color)) in.fail(std::string("field 'color': ") + why);
  }
  return p;
}

void readSurfaceBits(const ChunkPayload& in, const uint8_t* p, std::vector<DecodedVoxel>& out) {
  for (size_t k = 0; k < out.size(); ++k) out[k].surface = bitOf(p, k);
  const size_t rest = out.size() % 8;
  if (rest && (p[out.size() / 8] >> rest)) in.fail("field 'surface': padding bits must be 0");
}

}  // namespace

std::vector<DecodedVoxel> decodeBricks(const ChunkPayload& in) {
  const uint32_t flags = in.header.flags;
  std::vector<DecodedVoxel> out;
  out.reserve(in.entry.occupied);
  const uint8_t* p = readOccupancy(in, out);
  p = readSummaries(in, p, out);
  if (flags & kFlagColor) p = readColors(in, p, out);
  if (flags & kFlagSurface) readSurfaceBits(in, p, out);
  return out;
}

}  // namespace vox::pagefile
