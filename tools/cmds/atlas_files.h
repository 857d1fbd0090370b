// Naming and metadata of the files build-atlas writes, shared with the checker
// and with `vox info`. Every image carries a PNG tEXt chunk / EXR string
// attribute "vox:atlas" holding this JSON:
//   {"layout": {AtlasLayout::toJson()}, "content": "summary", "format": "rgba8",
//    "layer": 0, "class_id": 3 (votes only), "scene": "hamlet.vdb", "bits_per_voxel": 1 (bitmaps)}
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "formats/image/image.h"
#include "libvox/core/atlas_content.h"
#include "libvox/core/atlas_mapping.h"

namespace voxcli {

inline constexpr const char* kAtlasTextKey = "vox:atlas";

struct AtlasImageInfo {
  vox::AtlasLayout layout;
  vox::AtlasContent content = vox::AtlasContent::Summary;
  std::string format;  // texel format name, or "r8", "r16", "r32ui" for vote layers, "bitmap" for bitmaps
  uint32_t layer = 0;
  uint8_t classId = 0;
  std::string scene;
};

/// Reads a PNG or EXR written by build-atlas. Throws vox::Error (BadInput) when
/// the file is not an image or lacks (or has a malformed) "vox:atlas" entry.
vox::Image readAtlasImage(const std::string& path, AtlasImageInfo& info);

nlohmann::json atlasInfoJson(const AtlasImageInfo& info);

}  // namespace voxcli
