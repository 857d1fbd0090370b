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

/// The mip level whose voxels a region part stores in full (votes, linear
/// colour) for a merge: level-n voxels of n <= 5 lie in one 32-voxel tile cell,
/// and the svo mip bricks of level-n chunks below it reach level n + 2 <= 5, so
/// every chunk of the levels below it joins from the parts' decoded chunks;
/// this level and the coarser ones are rebuilt from these voxels
/// (PAGEFILE.md, "Merging the parts of a region bake").
inline constexpr uint32_t kRegionSeamLevel = 4;

/// One voxel of a part's seam level, as the pyramid holds it.
struct SeamVoxel {
  std::array<uint32_t, 3> at{};                 // index coordinates at the seam level
  bool surface = false;
  std::vector<ClassVotes> votes;                // by class id, each >= 1
  std::optional<std::array<float, 3>> color;    // linear
  bool operator==(const SeamVoxel&) const = default;
};

/// What a part packed with mips records for a merge (key `region_mips`).
struct RegionMips {
  uint32_t levelsAsked = 0;        // `--levels` of the pack (0: automatic)
  uint32_t seamLevel = 0;          // level of `voxels`; 0: none (the part stores every level the world can have)
  std::vector<SeamVoxel> voxels;   // the part's voxels at seamLevel, in the scene's voxel order
  bool operator==(const RegionMips&) const = default;
};

struct PageMeta {
  std::string toolVersion;              // of the vox that wrote the file
  ClassTable classes;                   // as the scene's `vox:classes`
  std::vector<SceneSource> sources;     // as the scene's `vox:sources`
  std::vector<LevelMeta> levels;
  std::string mipOccupancy;             // "any", "majority" or "from FILE"; empty: no mips, key absent
  std::optional<BlockWorldPlacement> blockWorld;
  std::optional<SceneRegion> region;    // as the scene's `vox:region`: the file is a part of a region bake
  std::optional<RegionMips> regionMips; // parts packed with mips only
  // Parts only: the alignment the part was packed with (`--align`; 0: auto),
  // which its merge lays the world's file out with (key `region_align`:
  // "auto" or the bytes). Absent in older parts: the header's alignment.
  std::optional<uint32_t> regionAlign;
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
