// The names and metadata of a scene file (formats/scene/SCENE.md): the one
// writer and the one reader of the `vox:*` keys, and the grid names.
//
// Three writers produce scene files: the OpenVDB scene writer and the pyramid
// writer (formats/vdb, through openvdb::MetaMap) and the direct writer
// (scene_vdb_direct.h, bytes of its own). All three take their keys from
// sceneFileMetadata() and their grid metadata from the *GridMetadata()
// functions; both readers (scene and pyramid) parse the keys with
// sceneHeaderFromMetadata(). This header is light (no OpenVDB): values are
// plain types, named as OpenVDB names them in a file.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "libvox/core/scene_header.h"

namespace vox {

/// A metadata value of a type the other side of the format does not know (a
/// file written by another tool): only its OpenVDB type name, for messages.
struct ForeignMetaValue {
  std::string typeName;
  bool operator==(const ForeignMetaValue&) const = default;
};

/// One metadata value: OpenVDB's string, int32, double, vec3i or vec3d.
using MetaValue = std::variant<std::string, int32_t, double, std::array<int32_t, 3>, std::array<double, 3>,
                               ForeignMetaValue>;

/// "string", "int32", "double", "vec3i", "vec3d", or a foreign value's type name.
std::string metaTypeName(const MetaValue& value);

/// Metadata by key, in key order (the order OpenVDB writes them in).
using MetaEntries = std::map<std::string, MetaValue>;

// ---------------------------------------------------------------- grid names

inline constexpr const char* kOccupancyGridName = "occupancy";
inline constexpr const char* kColorGridName = "color";
/// "votes.<id>", the id in decimal without leading zeros.
std::string voteGridName(uint8_t classId);
/// The class id of a grid named exactly "votes.<id 1..255>", else nullopt.
std::optional<uint8_t> classIdOfVoteGridName(const std::string& name);
/// True when `name` starts with "votes.": a vote grid, well named or not.
bool looksLikeVoteGridName(const std::string& name);

// ---------------------------------------------------------------- JSON values
// The JSON documents of the keys, also embedded as they are in other files'
// metadata (a page file's, formats/pagefile/PAGEFILE.md). The class table's
// is class_table_json.h's; these add the same for the other two.

/// `vox:classes`: classTableToJson(table) as text.
std::string classTableJson(const ClassTable& table);
/// `vox:sources`: [{"path", "kind", "sha256", "bytes"}, ...].
std::string sourcesJson(const std::vector<SceneSource>& sources);
/// `vox:block_world`: {"worldScale": s, "gridSize": [X, Y, Z]}.
std::string blockWorldJson(const BlockWorldPlacement& placement);
/// The readers of those two. Every key is required; throw vox::Error
/// (BadInput) "WHERE ..." naming the entry and the key.
std::vector<SceneSource> sourcesFromJson(const nlohmann::json& sources, const std::string& where);
BlockWorldPlacement blockWorldFromJson(const nlohmann::json& placement, const std::string& where);
/// `vox:region`: {"index": I, "count": N, "box": [umin, vmin, wmin, umax, vmax, wmax] or null
/// when the tile is empty, "world_key": hex}; a part of a region bake (libvox/core/regions.h).
std::string regionJson(const SceneRegion& region);
/// Its reader: checks 0 <= index < count, a box inside `dims` (inclusive, min <= max)
/// and a non-empty key; throws vox::Error (BadInput) "WHERE ..." naming the key.
SceneRegion regionFromJson(const nlohmann::json& region, const Dims& dims, const std::string& where);

// ---------------------------------------------------------------- writing

/// Every file-level key of a scene with header `h`: vox:format,
/// vox:format_version, vox:tool_version, vox:dims, vox:voxel_size,
/// vox:origin, vox:mip_level, vox:classes, vox:sources and, when the scene
/// comes from a block map, vox:block_world.
MetaEntries sceneFileMetadata(const SceneHeader& h);

/// Grid metadata of `votes.<id>`: vox:class_id and vox:class_name (the
/// class's name in `classes`, "" when it has none).
MetaEntries voteGridMetadata(const ClassTable& classes, uint8_t classId);
/// Grid metadata of `color`: vox:color_space = "linear".
MetaEntries colorGridMetadata();
/// Grid metadata a pyramid adds to every grid of level n >= 1: vox:mip_level.
MetaEntries pyramidLevelGridMetadata(int mipLevel);

/// A pyramid file's metadata key (formats/scene/SCENE.md "Pyramids").
inline constexpr const char* kPyramidKey = "vox:pyramid";
/// The prefix of level n's grid names: "" for level 0, else "mip<n>." (a
/// prefix, not a suffix, so that the scene reader, which refuses any
/// "votes.*" grid it cannot parse, skips them).
std::string pyramidGridPrefix(size_t level);
/// True for a grid name with a level prefix of n >= 1 ("mip<n>.", digits then
/// a dot): a pyramid's grid above level 0.
bool hasPyramidLevelPrefix(const std::string& gridName);
/// One entry of `vox:pyramid`'s level list.
struct PyramidLevelEntry {
  int level = 0;
  Dims dims;
  double voxelSize = 0;
  uint64_t occupied = 0;
};
/// The value of `vox:pyramid`: {"occupancy": occupancy, "levels": [...]}
/// (levels above 0) as JSON text.
std::string pyramidMetadata(const std::string& occupancy, const std::vector<PyramidLevelEntry>& levels);

// ---------------------------------------------------------------- reading

/// The header the keys describe. Throws vox::Error (BadInput) naming `path`
/// and the key: a missing or mistyped key, a format other than
/// "voxbake-scene", a version newer than this vox, dims < 1, a voxel size
/// that is not finite and > 0, a malformed class table (class_table_json.h),
/// sources or block-world placement. Keys it does not know are ignored.
SceneHeader sceneHeaderFromMetadata(const MetaEntries& meta, const std::string& path);

}  // namespace vox
