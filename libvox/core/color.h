// The sRGB transfer function, in one place (IEC 61966-2-1): decoding 8-bit and
// [0, 1] sRGB-encoded values to linear light, and encoding linear light to
// 8-bit sRGB correctly rounded.
//
// Decoding: c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055)^2.4, evaluated in
// double and rounded once to float. Encoding: the 8-bit value nearest to
// 255 * (c <= 0.0031308 ? 12.92 c : 1.055 c^(1/2.4) - 0.055), ties away from
// zero, after clamping c to [0, 1] (NaN gives 0) - exact for every float,
// because it compares c with the 255 float thresholds where the correctly
// rounded result steps up (tests/test_color.cpp checks each threshold against
// an extended-precision reference, which covers every float in [0, 1]).
//
// Thread safety: pure functions; the tables are built once, thread-safely.
#pragma once

#include <cstdint>

namespace vox {

/// sRGB-encoded value in [0, 1] (not clamped) to linear light.
float srgbToLinear(double encoded);

/// 8-bit sRGB-encoded value to linear light: srgbToLinear(byte / 255.0), from a table.
float srgb8ToLinear(uint8_t encoded);

/// Linear light to the correctly rounded 8-bit sRGB value (clamped to [0, 1]).
uint8_t linearToSrgb8(float linear);

/// The smallest float that linearToSrgb8 maps to `k` (k in 1..255), for tests.
float srgb8Threshold(int k);

}  // namespace vox
