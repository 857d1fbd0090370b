// What the page-file container and its layouts share to read and write bytes:
// little-endian fields, LSB-first bit arrays, and the checks every decoder
// makes (a chunk's part inside the level's domain, the colour rule).
// Internal to formats/pagefile.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>

#include "formats/pagefile/pagefile.h"

namespace vox::pagefile {

/// A little-endian field at `p` (the format is little-endian on every host).
template <typename T>
T loadLE(const uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  if constexpr (std::endian::native == std::endian::big && sizeof(T) > 1) {
    uint8_t b[sizeof(T)];
    std::memcpy(b, &v, sizeof v);
    std::reverse(b, b + sizeof(T));
    std::memcpy(&v, b, sizeof v);
  }
  return v;
}

template <typename T>
void storeLE(uint8_t* p, T v) {
  if constexpr (std::endian::native == std::endian::big && sizeof(T) > 1) {
    uint8_t b[sizeof(T)];
    std::memcpy(b, &v, sizeof v);
    std::reverse(b, b + sizeof(T));
    std::memcpy(p, b, sizeof v);
  } else {
    std::memcpy(p, &v, sizeof v);
  }
}

/// Bit `bit` of an LSB-first bit array (bit b is bit b % 8 of byte b / 8).
inline bool bitOf(const uint8_t* bytes, uint64_t bit) { return (bytes[bit >> 3] >> (bit & 7)) & 1; }
inline void setBit(uint8_t* bytes, uint64_t bit) { bytes[bit >> 3] |= uint8_t(1u << (bit & 7)); }

/// Chunk-local voxels of `entry` that lie inside its level's domain: [0, lim) per axis.
inline std::array<uint32_t, 3> chunkLimits(const Header& h, const IndexEntry& entry) {
  const auto ld = h.levelDims(entry.level);
  const auto c = entry.chunk();
  const uint32_t C = h.chunkSide();
  return {std::min(C, ld[0] - c[0] * C), std::min(C, ld[1] - c[1] * C), std::min(C, ld[2] - c[2] * C)};
}

/// What is wrong with a stored colour (alpha 0 or 255, RGB 0 without colour), or nullptr.
inline const char* colorProblem(const std::array<uint8_t, 4>& c) {
  if (c[3] != 0 && c[3] != 255) return "alpha must be 0 or 255";
  if (c[3] == 0 && (c[0] | c[1] | c[2])) return "an uncoloured voxel must be 0,0,0,0";
  return nullptr;
}

}  // namespace vox::pagefile
