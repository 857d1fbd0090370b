// The summary texel of a vote histogram: RGBA8 = (cls, conf, obs, mrg), as the
// UVW atlas layout defines it.
//
//   cls  = the class with the most votes; ties go to the lowest class id
//   conf = round(255 * top / total)
//   obs  = min(255, floor(16 * log2(total + 1)))
//   mrg  = round(255 * (top - second) / total), second = 0 with one class
//   an empty histogram (no votes) gives (0, 0, 0, 0)
//
// Rounding: round(a / b) is half-up, floor((2a + b) / (2b)), in 64-bit integers
// (votes are < 2^32 per class, so totals < 2^40 and 2 * 255 * total < 2^49).
// obs uses floor so that a power of two is exact: total + 1 = 2^m gives 16m;
// it is evaluated against an integer threshold table (the smallest n with
// 16 log2 n >= k), never with floating point at run time.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "libvox/core/scene_header.h"

namespace vox {

struct SummaryTexel {
  uint8_t cls = 0, conf = 0, obs = 0, mrg = 0;
  bool operator==(const SummaryTexel&) const = default;
};

/// `votes` in any order, each class at most once (as VoxelView gives them);
/// entries with 0 votes are ignored; class ids 1..255.
SummaryTexel summarize(std::span<const ClassVotes> votes);

/// floor(16 * log2(n)) clamped to 255, exactly, for n >= 1.
uint8_t observationByte(uint64_t totalPlusOne);

/// A slow reference (long double arithmetic, direct from the formulas) for tests.
SummaryTexel summarizeReference(std::span<const ClassVotes> votes);

}  // namespace vox
