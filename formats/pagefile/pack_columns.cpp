#include "formats/pagefile/pack_columns.h"

#include <bit>
#include <cstring>
#include <string>

#include "formats/pagefile/pagefile.h"
#include "libvox/core/error.h"

namespace vox::packdetail {

namespace {

void putU32(uint8_t* p, uint32_t v) {
  for (int b = 0; b < 4; ++b) p[b] = uint8_t(v >> (8 * b));
}

void setBit(uint8_t* words, uint32_t bit) { words[bit >> 3] |= uint8_t(1u << (bit & 7)); }

}  // namespace

std::vector<uint8_t> encodeColumns(const ChunkVoxels& chunk, uint32_t flags, const ChunkPlace& place) {
  const uint32_t C = chunk.side, N = C * C * C, log2C = uint32_t(std::countr_zero(C));
  const bool full = chunk.count == N;
  const bool color = flags & pagefile::kFlagColor, surfaceCh = flags & pagefile::kFlagSurface;
  uint32_t surfaceCount = 0;
  for (uint32_t w = 0; w < N / 64; ++w)
    for (uint64_t word = chunk.bits[w]; word; word &= word - 1) {
      const uint32_t k = w * 64 + uint32_t(std::countr_zero(word));
      if (!surfaceCh || chunk.surface[k]) {
        ++surfaceCount;
      } else if (color && chunk.color[k][3] != 0) {
        const uint32_t x = k & (C - 1), y = (k >> log2C) & (C - 1), z = k >> (2 * log2C);
        throwUsage("--layout columns stores colour for surface voxels only, but voxel (" +
                   std::to_string(place.chunk[0] * C + x) + ", " + std::to_string(place.chunk[1] * C + y) + ", " +
                   std::to_string(place.chunk[2] * C + z) + ") of level " + std::to_string(place.level) + " (chunk (" +
                   std::to_string(place.chunk[0]) + ", " + std::to_string(place.chunk[1]) + ", " +
                   std::to_string(place.chunk[2]) + "), field 'colors') is interior and has a colour; use --layout bricks or svo");
      }
    }
  std::vector<uint8_t> out(pagefile::columnsPayloadBytes(C, chunk.count, surfaceCount, full, flags), 0);
  putU32(out.data(), surfaceCount);
  uint8_t* p = out.data() + 8;
  const uint32_t maskBytes = N / 8;
  uint8_t* solid = full ? nullptr : p;
  if (!full) p += maskBytes;
  uint8_t* surface = surfaceCh ? p : nullptr;
  if (surfaceCh) p += maskBytes;
  // Masks: voxel (x, y, z) is bit z + C * (x + C * y), 32 per u32 word, LSB first
  // (bytes of little-endian words, so bit b is bit b % 8 of byte b / 8).
  for (uint32_t w = 0; w < N / 64; ++w)
    for (uint64_t word = chunk.bits[w]; word; word &= word - 1) {
      const uint32_t k = w * 64 + uint32_t(std::countr_zero(word));
      const uint32_t x = k & (C - 1), y = (k >> log2C) & (C - 1), z = k >> (2 * log2C);
      const uint32_t bit = z + C * (x + C * y);
      if (solid) setBit(solid, bit);
      if (surface && chunk.surface[k]) setBit(surface, bit);
    }
  if (!full) {
    // The mip ladder: level m (1 .. log2 C - 1) has side s = C >> m; voxel (x, y, z)
    // is set when a level-0 voxel of its 2^m block is occupied.
    for (uint32_t m = 1; m < log2C; ++m) {
      const uint32_t s = C >> m;
      for (uint32_t w = 0; w < N / 64; ++w)
        for (uint64_t word = chunk.bits[w]; word; word &= word - 1) {
          const uint32_t k = w * 64 + uint32_t(std::countr_zero(word));
          const uint32_t x = (k & (C - 1)) >> m, y = ((k >> log2C) & (C - 1)) >> m, z = (k >> (2 * log2C)) >> m;
          setBit(p, z + s * (x + s * y));
        }
      p += pagefile::columnsLadderWordCount(s) * 4;
    }
  }
  // Summary of every occupied voxel, then colours of the surface voxels, both in
  // column order (bit order of the masks: column x + C * y, then ascending z).
  uint8_t* sum = p;
  uint8_t* offsets = sum + 4ull * chunk.count;
  uint8_t* colors = offsets + 4ull * (C * C + 1);
  uint32_t rank = 0, colorRank = 0;
  for (uint32_t y = 0; y < C; ++y)
    for (uint32_t x = 0; x < C; ++x) {
      if (color) putU32(offsets + 4ull * (x + C * y), colorRank);
      for (uint32_t z = 0; z < C; ++z) {
        const uint32_t k = x + C * (y + C * z);
        if (!chunk.occupied(k)) continue;
        std::memcpy(sum + 4ull * rank++, chunk.summary[k].data(), 4);
        if (color && (!surfaceCh || chunk.surface[k])) std::memcpy(colors + 4ull * colorRank++, chunk.color[k].data(), 4);
      }
    }
  if (color) putU32(offsets + 4ull * C * C, colorRank);
  return out;
}

}  // namespace vox::packdetail
