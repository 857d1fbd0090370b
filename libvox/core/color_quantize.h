// A palette of at most N colours for a set of 8-bit sRGB colours (MagicaVoxel
// holds 255), by median cut, with the error it costs.
//
// When the set has at most N distinct colours the palette is exactly those
// colours (ascending by 0xRRGGBB) and the error is 0. Otherwise boxes of
// colours are split until there are N: each step takes the box with the
// widest channel range (ties: the earlier box), sorts its colours along that
// channel (ties by 0xRRGGBB) and splits it where the voxel count crosses half.
// A box's palette entry is the voxel-weighted mean of its colours, rounded;
// every colour then maps to its nearest entry (Euclidean in 8-bit sRGB, ties:
// the lower index). Deterministic: integer arithmetic, fixed orders.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "libvox/core/types.h"

namespace vox {

inline uint32_t packRgb(Rgb8 c) { return uint32_t(c.r) << 16 | uint32_t(c.g) << 8 | c.b; }
inline Rgb8 unpackRgb(uint32_t p) { return {uint8_t(p >> 16), uint8_t(p >> 8), uint8_t(p)}; }

/// Voxels per distinct colour (key: packRgb).
using ColorHistogram = std::unordered_map<uint32_t, uint64_t>;

struct QuantizedPalette {
  std::vector<Rgb8> colors;                      // at most maxColors entries
  std::unordered_map<uint32_t, uint32_t> slotOf;  // packRgb(colour) -> index into colors
  bool exact = true;                             // every colour is in the palette
  double meanError = 0;  // voxel-weighted mean distance to the palette entry, 8-bit sRGB units
  double maxError = 0;   // largest distance of any colour
};

/// The palette of `histogram` (non-empty counts) with at most `maxColors` (>= 1) entries.
QuantizedPalette quantizeColors(const ColorHistogram& histogram, size_t maxColors);

}  // namespace vox
