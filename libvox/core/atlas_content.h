// What each kind of atlas stores at a voxel's texel. Shared by build-atlas and
// by verify-bijection --atlas, so the checker compares against the same
// definitions the builder documents (README "Atlases").
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "libvox/core/color.h"  // linearToSrgb8, for the colour atlas
#include "libvox/core/scene_header.h"
#include "libvox/core/texel_formats.h"

namespace vox {

enum class AtlasContent {
  Summary,     // RGBA8 (cls, conf, obs, mrg); empty: 0, 0, 0, 0
  Identity,    // RGBA (u, v, w, 1 at full scale: 255 / 65535 / 2^32-1 / 1.0); empty: 0, 0, 0, 0
  Color,       // RGBA8 sRGB of the voxel's linear colour, alpha 255; uncoloured or empty: 0, 0, 0, 0
  Votes,       // one channel: the voxel's votes for one class (0 when none)
  Occupancy,   // 1-bit bitmap (bitmap_packing.h)
  Occupancy2,  // 2-bit bitmap, occupied + touched
};

const char* atlasContentName(AtlasContent c);  // "summary", "identity", "color", "votes", "occupancy", "occupancy2"
std::optional<AtlasContent> parseAtlasContent(const std::string& name);

/// Channel values (as unsigned integers, or float bit patterns for float
/// formats are NOT used here: identity in float formats holds u, v, w as
/// numbers, compared by value) for image atlases. `voxel` is null when empty.
/// For Votes, `classId` selects the class.
std::array<uint64_t, 4> atlasTexel(AtlasContent content, const VoxelView* voxel, TexelFormat identityFormat,
                                   uint8_t classId = 0);

}  // namespace vox
