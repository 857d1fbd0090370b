// The metadata of a page file (formats/pagefile/PAGEFILE.md, "Metadata"): the
// JSON text between the index and the payloads. One writer (packChunks) and
// one reader (`vox info`, renders of page files) so that both agree.
//
// The text is a JSON object with sorted keys and no whitespace (nlohmann's
// dump()), so the same PageMeta always gives the same bytes.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "libvox/core/scene_header.h"

namespace vox::pagefile {

/// The `format` value of every page file's metadata.
inline constexpr char kMetaFormat[] = "voxbake-pages";

/// One entry of `levels`: what the index holds for a level.
struct LevelMeta {
  uint32_t level = 0;
  std::array<uint32_t, 3> dims{};
  double voxelSize = 1.0;  // world units
  uint64_t chunks = 0, voxels = 0;
  bool operator==(const LevelMeta&) const = default;
};

struct PageMeta {
  std::string toolVersion;              // of the vox that wrote the file
  ClassTable classes;                   // as the scene's `vox:classes`
  std::vector<SceneSource> sources;     // as the scene's `vox:sources`
  std::vector<LevelMeta> levels;
  std::string mipOccupancy;             // "any", "majority" or "from FILE"; empty: no mips, key absent
  std::optional<BlockWorldPlacement> blockWorld;
  std::optional<SceneRegion> region;    // as the scene's `vox:region`: the file is a part of a region bake
  bool operator==(const PageMeta&) const = default;
};

/// The metadata text of `meta` (with `format` = kMetaFormat).
std::string writePageMeta(const PageMeta& meta);

/// Parses a page file's metadata text. Absent keys give empty values; unknown
/// keys are ignored. Throws vox::Error (BadInput) naming `fileName` and the key
/// when the text is not JSON, `format` is not kMetaFormat, or a value has the
/// wrong type or range (class ids 1..255, colours [r, g, b] of 0..255, a face
/// palette with all of top, bottom and side or none).
PageMeta readPageMeta(const std::string& text, const std::string& fileName);

}  // namespace vox::pagefile
