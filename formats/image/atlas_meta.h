// The metadata of atlases and occupancy bitmaps (formats/image/ATLAS.md,
// "Metadata"): the one writer and the one reader of
//   * the `vox:atlas` text entry every atlas image carries (PNG tEXt chunk,
//     EXR string attribute):
//       {"layout": {AtlasLayout::toJson()}, "content": "summary", "format": "rgba8",
//        "layer": 0, "scene": "hamlet.vdb", "class_id": 3 (votes only),
//        "bits_per_voxel": 1 or 2 (bitmaps only)}
//   * the `STEM.atlas.json` sidecar beside a set of atlases (for engines that
//     do not read PNG text chunks): the layout once and one entry per file,
//       {"scene": ..., "layout": {...}, "files": [{"file": "STEM.summary.png",
//        "content": ..., "format": ..., "layer": ..., ...}, ...]}
// Both are written by `vox build-atlas` (and the touched bitmap of
// `vox render-canonical`), read by `vox info` and `vox verify-bijection`.
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "formats/image/image.h"
#include "libvox/core/atlas_content.h"
#include "libvox/core/atlas_mapping.h"

namespace vox {

inline constexpr const char* kAtlasTextKey = "vox:atlas";

/// What one atlas image holds.
struct AtlasImageInfo {
  AtlasLayout layout;
  AtlasContent content = AtlasContent::Summary;
  /// Texel format name (texel_formats.h), "r8", "r16" or "r32ui" for vote
  /// layers, "bitmap" for bitmaps.
  std::string format;
  uint32_t layer = 0;   // < layout.layers
  uint8_t classId = 0;  // Votes only: the class of the layer
  std::string scene;    // the scene it was built from, as given
  bool operator==(const AtlasImageInfo&) const = default;
};

/// The `vox:atlas` entry of an image, as a JSON object (keys sorted).
nlohmann::json atlasInfoJson(const AtlasImageInfo& info);
/// The text entries an atlas image is written with: `vox:atlas` and `Software`.
std::vector<std::pair<std::string, std::string>> atlasImageText(const AtlasImageInfo& info);

/// Parses a `vox:atlas` entry. Throws vox::Error (BadInput) naming `context`
/// on malformed JSON, a missing or mistyped key, an unknown content, an
/// inconsistent layout or a layer past the layout's layers.
AtlasImageInfo atlasInfoFromJson(const std::string& text, const std::string& context);

/// The shape of an atlas image: what its layout, content and format give.
struct AtlasImageShape {
  uint32_t width = 0, height = 0, channels = 0;
  SampleType type = SampleType::U8;
};
/// Throws vox::Error (BadInput) naming `context` when `info.format` is not a
/// format its content is written in (summary and colour: rgba8; identity: a
/// texel format; votes: r8, r16, r32ui; bitmaps: bitmap).
AtlasImageShape atlasImageShape(const AtlasImageInfo& info, const std::string& context);

/// The one reader of an atlas image's entry, for every command that reads
/// atlases (info, diff, verify-bijection): the `vox:atlas` entry of a decoded
/// image, checked against the image. std::nullopt when the image has no
/// entry. Throws vox::Error (BadInput) naming `path` on a malformed entry
/// (atlasInfoFromJson) or an image whose size, channel count or sample type
/// is not the atlasImageShape of its entry (a file changed after vox wrote it).
std::optional<AtlasImageInfo> atlasInfoOfImage(const Image& image, const std::string& path);

/// Reads a PNG or EXR written with atlasImageText and its entry. Throws
/// vox::Error (BadInput) when there is no regular file at `path`
/// (requireRegularFile), the file is not an image, lacks a `vox:atlas` entry,
/// or atlasInfoOfImage refuses it.
Image readAtlasImage(const std::string& path, AtlasImageInfo& info);

/// One file of a sidecar: the image's info and its file name (no directory).
struct AtlasSidecarEntry {
  AtlasImageInfo info;
  std::string file;
  bool operator==(const AtlasSidecarEntry&) const = default;
};
/// The sidecar text (pretty-printed, newline-terminated) for images of one
/// layout and scene.
std::string atlasSidecarJson(const std::string& scene, const AtlasLayout& layout,
                             const std::vector<AtlasSidecarEntry>& files);
/// Parses a sidecar. Throws vox::Error (BadInput) naming `context` on the
/// same faults as atlasInfoFromJson, per file.
std::vector<AtlasSidecarEntry> atlasSidecarFromJson(const std::string& text, const std::string& context);

}  // namespace vox
