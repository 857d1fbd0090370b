// Counting set bits in the 64-bit words of voxel masks (8^3 blocks, bricks,
// packed leaves), where ranks pick a voxel's value out of a packed array.
#pragma once

#include <cstdint>

namespace vox {

/// Set bits of `x`, inline. The build targets baseline x86-64, which has no
/// POPCNT instruction: std::popcount and __builtin_popcountll are then a call
/// into libgcc (__popcountdi2), which showed in the profiles of the loops that
/// rank voxels (the surface pass's vote blocks, fuse's tracked bricks).
inline int bitCount(uint64_t x) {
  x = x - ((x >> 1) & 0x5555555555555555ull);
  x = (x & 0x3333333333333333ull) + ((x >> 2) & 0x3333333333333333ull);
  x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0full;
  return int((x * 0x0101010101010101ull) >> 56);
}

}  // namespace vox
