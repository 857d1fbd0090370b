#include "formats/pagefile/columns_layout.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <string>

#include "formats/pagefile/layout_io.h"
#include "formats/pagefile/pagefile.h"
#include "libvox/core/bits.h"
#include "libvox/core/error.h"

namespace vox::pagefile {

// Mask bit of chunk voxel (x, y, z) of a chunk of side s: column x + s * y, then z.
// Masks are u32 words, LSB first (bytes of little-endian words, so bit b is
// bit b % 8 of byte b / 8).

uint32_t columnsLadderWordCount(uint32_t side) { return uint32_t((uint64_t(side) * side * side + 31) / 32); }

uint64_t columnsLadderBytes(uint32_t chunkSide) {
  uint64_t n = 0;
  for (uint32_t s = chunkSide / 2; s >= 2; s /= 2) n += 4ull * columnsLadderWordCount(s);
  return n;
}

uint64_t columnsPayloadBytes(uint32_t chunkSide, uint32_t occupied, uint32_t surfaceCount, bool full, uint32_t flags) {
  const uint64_t N = uint64_t(chunkSide) * chunkSide * chunkSide;
  uint64_t n = kColumnsFixedBytes;
  if (!full) n += N / 8 + columnsLadderBytes(chunkSide);
  if (flags & kFlagSurface) n += N / 8;
  n += 4ull * occupied;
  if (flags & kFlagColor) n += 4ull * (uint64_t(chunkSide) * chunkSide + 1) + 4ull * surfaceCount;
  return n;
}

// ------------------------------------------------------------------ encoder

namespace {

// The surface voxels (every voxel without the surface channel); refuses a
// coloured interior voxel, which the layout cannot store.
uint32_t countSurfaceVoxels(const ChunkVoxels& chunk, uint32_t flags, const ChunkPlace& place) {
  const uint32_t C = chunk.side, N = C * C * C, log2C = uint32_t(std::countr_zero(C));
  const bool color = flags & kFlagColor, surfaceCh = flags & kFlagSurface;
  uint32_t surfaceCount = 0;
  for (uint32_t w = 0; w < N / 64; ++w)
    for (uint64_t word = chunk.bits[w]; word; word &= word - 1) {
      const uint32_t k = w * 64 + uint32_t(std::countr_zero(word));
      if (!surfaceCh || chunk.surface[k]) {
        ++surfaceCount;
      } else if (color && chunk.color[k][3] != 0) {
        const uint32_t x = k & (C - 1), y = (k >> log2C) & (C - 1), z = k >> (2 * log2C);
        throwUsage("the columns layout stores colour for surface voxels only, but voxel (" +
                       std::to_string(place.chunk[0] * C + x) + ", " + std::to_string(place.chunk[1] * C + y) + ", " +
                       std::to_string(place.chunk[2] * C + z) + ") of level " + std::to_string(place.level) +
                       " (chunk (" + std::to_string(place.chunk[0]) + ", " + std::to_string(place.chunk[1]) + ", " +
                       std::to_string(place.chunk[2]) +
                       "), field 'colors') is interior and has a colour; choose the bricks or svo layout",
                   Setting::PageLayout);
      }
    }
  return surfaceCount;
}

// The solid mask (absent when full) and the surface mask (with the surface
// channel). Returns the byte after them.
uint8_t* writeMasks(const ChunkVoxels& chunk, uint32_t flags, uint8_t* p) {
  const uint32_t C = chunk.side, N = C * C * C, log2C = uint32_t(std::countr_zero(C));
  const bool full = chunk.count == N;
  uint8_t* solid = full ? nullptr : p;
  if (!full) p += N / 8;
  uint8_t* surface = (flags & kFlagSurface) ? p : nullptr;
  if (surface) p += N / 8;
  for (uint32_t w = 0; w < N / 64; ++w)
    for (uint64_t word = chunk.bits[w]; word; word &= word - 1) {
      const uint32_t k = w * 64 + uint32_t(std::countr_zero(word));
      const uint32_t x = k & (C - 1), y = (k >> log2C) & (C - 1), z = k >> (2 * log2C);
      const uint32_t bit = z + C * (x + C * y);
      if (solid) setBit(solid, bit);
      if (surface && chunk.surface[k]) setBit(surface, bit);
    }
  return p;
}

// The mip ladder: level m (1 .. log2 C - 1) has side s = C >> m; voxel (x, y, z)
// is set when a level-0 voxel of its 2^m block is occupied. Returns the byte after it.
uint8_t* writeLadder(const ChunkVoxels& chunk, uint8_t* p) {
  const uint32_t C = chunk.side, N = C * C * C, log2C = uint32_t(std::countr_zero(C));
  for (uint32_t m = 1; m < log2C; ++m) {
    const uint32_t s = C >> m;
    for (uint32_t w = 0; w < N / 64; ++w)
      for (uint64_t word = chunk.bits[w]; word; word &= word - 1) {
        const uint32_t k = w * 64 + uint32_t(std::countr_zero(word));
        const uint32_t x = (k & (C - 1)) >> m, y = ((k >> log2C) & (C - 1)) >> m, z = (k >> (2 * log2C)) >> m;
        setBit(p, z + s * (x + s * y));
      }
    p += columnsLadderWordCount(s) * 4;
  }
  return p;
}

// Summary of every occupied voxel, then colour offsets and colours of the
// surface voxels, both in column order (mask-bit order: column x + C * y, then
// ascending z).
void writeVoxelData(const ChunkVoxels& chunk, uint32_t flags, uint8_t* p) {
  const uint32_t C = chunk.side;
  const bool color = flags & kFlagColor, surfaceCh = flags & kFlagSurface;
  uint8_t* sum = p;
  uint8_t* offsets = sum + 4ull * chunk.count;
  uint8_t* colors = offsets + 4ull * (C * C + 1);
  uint32_t rank = 0, colorRank = 0;
  for (uint32_t y = 0; y < C; ++y)
    for (uint32_t x = 0; x < C; ++x) {
      if (color) storeLE<uint32_t>(offsets + 4ull * (x + C * y), colorRank);
      for (uint32_t z = 0; z < C; ++z) {
        const uint32_t k = x + C * (y + C * z);
        if (!chunk.occupied(k)) continue;
        std::memcpy(sum + 4ull * rank++, chunk.summary[k].data(), 4);
        if (color && (!surfaceCh || chunk.surface[k])) std::memcpy(colors + 4ull * colorRank++, chunk.color[k].data(), 4);
      }
    }
  if (color) storeLE<uint32_t>(offsets + 4ull * C * C, colorRank);
}

}  // namespace

std::vector<uint8_t> encodeColumns(const ChunkVoxels& chunk, uint32_t flags, const ChunkPlace& place) {
  const uint32_t C = chunk.side, N = C * C * C;
  const bool full = chunk.count == N;
  const uint32_t surfaceCount = countSurfaceVoxels(chunk, flags, place);
  std::vector<uint8_t> out(columnsPayloadBytes(C, chunk.count, surfaceCount, full, flags), 0);
  storeLE<uint32_t>(out.data() + columns_field::kSurfaceCount, surfaceCount);
  uint8_t* p = writeMasks(chunk, flags, out.data() + kColumnsFixedBytes);
  if (!full) p = writeLadder(chunk, p);
  writeVoxelData(chunk, flags, p);
  return out;
}

// ------------------------------------------------------------------ decoder

namespace {

// Where the parts of a payload start.
struct Sections {
  uint32_t surfaceCount = 0;  // S
  const uint8_t* solid = nullptr;    // all ones for a full chunk
  const uint8_t* surface = nullptr;  // = solid without the surface channel
  const uint8_t* ladder = nullptr;   // null for a full chunk
  const uint8_t* summary = nullptr;
  const uint8_t* colorOffsets = nullptr;
  const uint8_t* colors = nullptr;
};

// Step 1: `surface_count` in range, the size it gives, the sections. A full
// chunk's solid mask is `ones` (all set), which must outlive the sections.
Sections readSections(const ChunkPayload& in, std::vector<uint8_t>& ones) {
  const Header& h = in.header;
  const IndexEntry& e = in.entry;
  const uint8_t* p = in.bytes.data();
  if (in.bytes.size() < kColumnsFixedBytes) in.fail("field 'size': shorter than the columns payload's fixed part");
  const uint32_t C = h.chunkSide(), N = h.chunkVoxels();
  const bool full = e.flags & kChunkFull, surfaceCh = h.flags & kFlagSurface;
  const uint32_t n = e.occupied;
  Sections s;
  s.surfaceCount = loadLE<uint32_t>(p + columns_field::kSurfaceCount);
  const uint32_t S = s.surfaceCount;
  if (S > n || (!surfaceCh && S != n))
    in.fail("columns field 'surface_count': " + std::to_string(S) + ", expected " +
            (surfaceCh ? "0.." + std::to_string(n) : std::to_string(n) + " (no surface channel: every voxel is a surface voxel)"));
  if (loadLE<uint32_t>(p + columns_field::kReserved) != 0) in.fail("columns field 'reserved': must be 0");
  const uint64_t want = columnsPayloadBytes(C, n, S, full, h.flags);
  if (in.bytes.size() != want)
    in.fail("field 'size': " + std::to_string(in.bytes.size()) + " bytes, the columns layout needs " + std::to_string(want) +
            " (occupied " + std::to_string(n) + ", surface_count " + std::to_string(S) + ")");
  p += kColumnsFixedBytes;
  if (full) {
    const auto lim = chunkLimits(h, e);
    if (lim[0] != C || lim[1] != C || lim[2] != C) in.fail("field 'flags': a full chunk that crosses the edge of the domain");
    ones.assign(N / 8, 0xFF);
    s.solid = ones.data();
  } else {
    s.solid = p;
    p += N / 8;
  }
  s.surface = surfaceCh ? p : s.solid;
  if (surfaceCh) p += N / 8;
  if (!full) {
    s.ladder = p;
    p += columnsLadderBytes(C);
  }
  s.summary = p;
  s.colorOffsets = s.summary + 4ull * n;
  s.colors = s.colorOffsets + 4ull * (C * C + 1);
  return s;
}

// Step 2: the solid mask inside the level's domain with `occupied` bits, the
// surface mask inside it with `surface_count` bits.
void checkMasks(const ChunkPayload& in, const Sections& s) {
  const Header& h = in.header;
  const uint32_t C = h.chunkSide(), N = h.chunkVoxels(), log2C = h.chunkLog2;
  const auto lim = chunkLimits(h, in.entry);
  uint64_t solidCount = 0, surfCount = 0;
  for (uint32_t w = 0; w < N / 32; ++w) {
    const uint32_t sw = loadLE<uint32_t>(s.solid + 4 * w), fw = loadLE<uint32_t>(s.surface + 4 * w);
    solidCount += uint32_t(bitCount(sw));
    surfCount += uint32_t(bitCount(fw));
    if (fw & ~sw) in.fail("columns field 'surface_mask': word " + std::to_string(w) + " has a voxel that is not in the solid mask");
    for (uint32_t word = sw; word; word &= word - 1) {
      const uint32_t bit = w * 32 + uint32_t(std::countr_zero(word));
      const uint32_t z = bit & (C - 1), x = (bit >> log2C) & (C - 1), y = bit >> (2 * log2C);
      if (x >= lim[0] || y >= lim[1] || z >= lim[2])
        in.fail("columns field 'solid_mask': voxel (" + std::to_string(x) + ", " + std::to_string(y) + ", " +
                std::to_string(z) + ") of the chunk lies outside the level's dims");
    }
  }
  if (solidCount != in.entry.occupied)
    in.fail("columns field 'solid_mask': " + std::to_string(solidCount) + " bits set, the index says " +
            std::to_string(in.entry.occupied) + " occupied voxels");
  if (surfCount != s.surfaceCount)
    in.fail("columns field 'surface_mask': " + std::to_string(surfCount) + " bits set, surface_count says " +
            std::to_string(s.surfaceCount));
}

// Step 3: the mip ladder equals the one recomputed from the solid mask.
void checkLadder(const ChunkPayload& in, const Sections& s) {
  const uint32_t C = in.header.chunkSide(), N = in.header.chunkVoxels(), log2C = in.header.chunkLog2;
  const uint8_t* p = s.ladder;
  std::vector<uint8_t> expect;
  for (uint32_t m = 1; m < log2C; ++m) {
    const uint32_t side = C >> m, words = columnsLadderWordCount(side);
    expect.assign(4ull * words, 0);
    for (uint32_t w = 0; w < N / 32; ++w)
      for (uint32_t word = loadLE<uint32_t>(s.solid + 4 * w); word; word &= word - 1) {
        const uint32_t bit = w * 32 + uint32_t(std::countr_zero(word));
        const uint32_t z = (bit & (C - 1)) >> m, x = ((bit >> log2C) & (C - 1)) >> m, y = (bit >> (2 * log2C)) >> m;
        setBit(expect.data(), z + side * (x + side * y));
      }
    if (std::memcmp(expect.data(), p, expect.size()) != 0)
      in.fail("columns field 'ladder': level " + std::to_string(m) + " (" + std::to_string(side) +
              "^3) does not match the solid mask");
    p += expect.size();
  }
}

// Step 4: every occupied voxel with its summary, surface bit and (surface
// voxels) colour, column by column; the colour offsets against the running
// count of surface voxels.
std::vector<DecodedVoxel> readVoxels(const ChunkPayload& in, const Sections& s) {
  const uint32_t C = in.header.chunkSide(), log2C = in.header.chunkLog2;
  const bool color = in.header.flags & kFlagColor;
  std::vector<DecodedVoxel> out;
  out.reserve(in.entry.occupied);
  uint32_t rank = 0, colorRank = 0;
  for (uint32_t col = 0; col < C * C; ++col) {
    if (color && loadLE<uint32_t>(s.colorOffsets + 4ull * col) != colorRank)
      in.fail("columns field 'color_offsets': column " + std::to_string(col) + " says " +
              std::to_string(loadLE<uint32_t>(s.colorOffsets + 4ull * col)) + ", the surface mask gives " +
              std::to_string(colorRank));
    for (uint32_t z = 0; z < C; ++z) {
      const uint32_t bit = z + C * col;
      if (!bitOf(s.solid, bit)) continue;
      const uint32_t x = col & (C - 1), y = col >> log2C;
      DecodedVoxel v;
      v.index = x + C * (y + C * z);
      std::memcpy(v.summary.data(), s.summary + 4ull * rank, 4);
      if (v.summary[0] == 0) in.fail("field 'summary': voxel " + std::to_string(v.index) + " is occupied but has class 0");
      ++rank;
      v.surface = bitOf(s.surface, bit);
      if (color && v.surface) {
        std::memcpy(v.color.data(), s.colors + 4ull * colorRank, 4);
        if (const char* why = colorProblem(v.color))
          in.fail(std::string("field 'color': colour ") + std::to_string(colorRank) + ": " + why);
        ++colorRank;
      }
      out.push_back(v);
    }
  }
  if (color && loadLE<uint32_t>(s.colorOffsets + 4ull * C * C) != s.surfaceCount)
    in.fail("columns field 'color_offsets': the sentinel must be surface_count " + std::to_string(s.surfaceCount));
  std::sort(out.begin(), out.end(), [](const DecodedVoxel& a, const DecodedVoxel& b) { return a.index < b.index; });
  return out;
}

}  // namespace

std::vector<DecodedVoxel> decodeColumns(const ChunkPayload& in) {
  std::vector<uint8_t> ones;
  const Sections sections = readSections(in, ones);
  checkMasks(in, sections);
  if (sections.ladder) checkLadder(in, sections);
  return readVoxels(in, sections);
}

}  // namespace vox::pagefile
