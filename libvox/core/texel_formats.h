// The byte-depth ladder of atlas pixel formats (of the UVW atlas layout) and
// which integers each holds exactly.
//
//   rgba8     8-bit PNG            exact for 0..255
//   rgba16    16-bit PNG           exact for 0..65535
//   rgba32ui  EXR UINT             exact for 0..2^32-1
//   rgba16f   EXR HALF             exact for 0..2048 (2049 rounds to 2048)
//   rgba32f   EXR FLOAT            exact for 0..2^24 (2^24+1 rounds to 2^24)
//
// maxExactInteger() does not assume those numbers: it measures them by
// round-tripping integers through each format's storage (the half conversion is
// our own round-to-nearest-even, identical to OpenEXR's), so a test can compare
// them with the table above.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

namespace vox {

enum class TexelFormat { Rgba8, Rgba16, Rgba32ui, Rgba16f, Rgba32f };

/// Every format, narrowest integer format first (the order above).
inline constexpr std::array<TexelFormat, 5> kTexelFormats{TexelFormat::Rgba8, TexelFormat::Rgba16, TexelFormat::Rgba32ui,
                                                          TexelFormat::Rgba16f, TexelFormat::Rgba32f};

const char* texelFormatName(TexelFormat f);  // "rgba8", ...
std::optional<TexelFormat> parseTexelFormat(const std::string& name);
bool isFloatFormat(TexelFormat f);

/// Stores `value` as the format would and reads it back.
uint64_t roundTrip(TexelFormat f, uint64_t value);

/// The largest N such that every integer 0..N round-trips exactly, found by
/// checking every integer up to the first failure (all 2^32 for rgba32ui, on
/// `threads` threads).
uint64_t maxExactInteger(TexelFormat f, unsigned threads = 1);

/// The narrowest integer format holding 0..maxCoordinate exactly.
TexelFormat narrowestExactFormat(uint64_t maxCoordinate);

/// The largest integer each format holds exactly, as documented above (what
/// maxExactInteger measures); used on hot paths.
uint64_t documentedMaxExact(TexelFormat f);

/// IEEE half conversion, round to nearest even (for tests and EXR HALF output).
uint16_t floatToHalf(float f);
float halfToFloat(uint16_t h);

}  // namespace vox
