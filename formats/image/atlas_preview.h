// Viewable previews of atlases and occupancy bitmaps (`vox build-atlas
// --preview`, formats/image/ATLAS.md "Previews"): what a GPU samples, drawn for
// a person, one preview texel per atlas texel (no filtering, no scaling).
//
//   summary     three panels the atlas's size side by side: class colours,
//               confidence, observations (the margin byte is left out: a
//               fourth panel would cost a third more), bytes through ramp()
//   identity    (u, v, w) scaled to 0..255 over the dims (255 = the last voxel)
//   color       the sRGB colour as stored
//   votes       gray: the layer's votes divided by its largest, through grayRamp
//   occupancy   1-bit: white = occupied, black = empty; unpacked, one byte per texel
//   occupancy2  2-bit, 4 greys: 0 empty, 85 touched only, 170 occupied, 255 both
// Empty texels and padding are black in every preview; ramps start at a dark
// violet, never black, so an occupied texel stays visible.
//
// RGB8 images (bitmaps and votes: gray8; summary: indexed colour), with a `vox:preview` text entry naming the
// atlas and what the panels hold. Deterministic: integer arithmetic only.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "formats/image/atlas_meta.h"
#include "formats/image/image.h"
#include "libvox/core/classes.h"

namespace vox {

inline constexpr const char* kPreviewTextKey = "vox:preview";
/// Class colour of a class id not in the table (a scene/atlas mismatch).
inline constexpr Rgb8 kUnknownClassColor{255, 0, 255};

/// A perceptual ramp (viridis at 9 stops, interpolated in integers): index
/// 0..255 -> RGB. ramp(0) = (68, 1, 84), ramp(255) = (253, 231, 37).
std::array<uint8_t, 3> ramp(uint8_t index);

/// A gray ramp that keeps 0 visible against black: 48 + round(207 * index / 255)
/// (half up: (207 * index + 127) / 255), so 0 -> 48 and 255 -> 255.
uint8_t grayRamp(uint8_t index);

/// A preview: an image, and for an indexed-colour one its palette (`image`
/// then holds 1-channel indices into it).
struct AtlasPreview {
  Image image;
  std::vector<std::array<uint8_t, 3>> palette;
  /// The colour of preview pixel (x, y), for any kind (gray g gives (g, g, g)).
  std::array<uint8_t, 3> rgb(uint32_t x, uint32_t y) const;
};

/// The preview of `atlas` (an image written by build-atlas, described by
/// `info`); `classes` colours the summary's class panel. The summary preview
/// is indexed colour (a third of RGB's bytes): black, one entry per class of
/// the table and one for unknown ids, the rest a ramp of 256 - 2 - classes
/// levels (byte v -> level round(v (L - 1) / 255) -> ramp(round(level 255 /
/// (L - 1))), exact at 0 and 255); a table of more than 190 classes leaves
/// fewer than 64 levels, and the preview is RGB with the exact ramp instead.
AtlasPreview atlasPreview(const Image& atlas, const AtlasImageInfo& info, const ClassTable& classes,
                          const std::string& atlasFileName);

/// Writes a preview as PNG (zlib level 1: previews are mostly black),
/// deflated in row slices on `threads` threads; the bytes do not depend on
/// `threads`. Throws vox::Error (Io).
void writeAtlasPreview(const AtlasPreview& preview, const std::string& path, unsigned threads);

/// "DIR/h.summary.png" -> "DIR/h.summary.preview.png" (any extension).
std::string previewPath(const std::string& atlasPath);

}  // namespace vox
