// Morton (Z-order) keys of 3D chunk coordinates: 21 bits per axis interleaved,
// x in bit 0, y in bit 1, z in bit 2, then x in bit 3, ... (so a key is < 2^63).
// Used by page files to sort chunks so that neighbours in space are near in
// the file (as sparse-voxel-octree renderers order their bricks).
#pragma once

#include <array>
#include <cstdint>

namespace vox {

inline constexpr uint32_t kMortonAxisBits = 21;
inline constexpr uint32_t kMortonAxisMax = (1u << kMortonAxisBits) - 1;

/// Spreads the low 21 bits of v so that bit i lands on bit 3i.
constexpr uint64_t mortonSpread(uint32_t v) {
  uint64_t x = v & 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffull;
  x = (x | x << 16) & 0x1f0000ff0000ffull;
  x = (x | x << 8) & 0x100f00f00f00f00full;
  x = (x | x << 4) & 0x10c30c30c30c30c3ull;
  x = (x | x << 2) & 0x1249249249249249ull;
  return x;
}

/// Inverse of mortonSpread: gathers bits 0, 3, 6, ... into the low 21 bits.
constexpr uint32_t mortonCompact(uint64_t x) {
  x &= 0x1249249249249249ull;
  x = (x | x >> 2) & 0x10c30c30c30c30c3ull;
  x = (x | x >> 4) & 0x100f00f00f00f00full;
  x = (x | x >> 8) & 0x1f0000ff0000ffull;
  x = (x | x >> 16) & 0x1f00000000ffffull;
  x = (x | x >> 32) & 0x1fffffull;
  return uint32_t(x);
}

/// Key of (x, y, z), each <= kMortonAxisMax.
constexpr uint64_t mortonEncode(uint32_t x, uint32_t y, uint32_t z) {
  return mortonSpread(x) | mortonSpread(y) << 1 | mortonSpread(z) << 2;
}

constexpr std::array<uint32_t, 3> mortonDecode(uint64_t key) {
  return {mortonCompact(key), mortonCompact(key >> 1), mortonCompact(key >> 2)};
}

}  // namespace vox
