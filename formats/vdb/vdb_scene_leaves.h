// A voxbake scene file read into its leaves only, without OpenVDB trees: what
// `vox pack-chunks` needs, read in one pass.
//
// Why: building OpenVDB trees costs a packer more than it uses them. A leaf of
// an int32 or vec3s tree holds 512 values (2 KB, 6 KB) whatever its active
// count; allocating and first touching them (about 140 MB for a 1024^3 surface
// scene with 3.6 M voxels) was the largest part of reading, the checks then
// looked leaves up tree by tree, the packer looked them up again, and the
// process freed every leaf at exit. Here each leaf keeps its active-voxel mask
// and its active values only, packed in voxel order, and the grids are joined
// leaf to leaf once.
//
// The file is walked and every block decompressed and checked exactly as the
// one-pass reader does (vdb_structure.h's walkVdbInto; the same form: grids of
// bool, int32 or vec3s, no half floats, no instances, trees that are only their
// leaves). The scene checks are levelGridsFromVdb's (vdb_scene_grids.h: grid
// types and names, vote counts >= 1, active voxels inside the dims, votes and
// colour only at occupied voxels, a vote at every occupied voxel). When the
// file is not of the form or fails a scene check the reader returns
// std::nullopt, and the caller reads the file the usual way (readSceneVdb),
// which accepts exactly what passes here and names what does not. A corrupt
// block (vdb_structure.h) throws here with the walk's message, as there.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "formats/scene/scene_meta.h"
#include "libvox/core/scene_header.h"

namespace vox {

/// One 8^3 leaf of a grid: its origin (index space, a multiple of 8), its
/// active voxels (bit `off` of the 512-bit mask, off = 64 x + 8 y + z within
/// the leaf: OpenVDB's order) and the values of those voxels in ascending
/// `off`, `T` per voxel (values[rank of off among the set bits]).
template <typename T>
struct SceneLeaf {
  std::array<int32_t, 3> origin{};
  std::array<uint64_t, 8> mask{};
  std::unique_ptr<T[]> values;  // popcount(mask) values
};

/// The occupancy grid's leaf: the active voxels and their values (the surface
/// flag), both as 512-bit masks.
struct OccupancyLeaf {
  std::array<int32_t, 3> origin{};
  std::array<uint64_t, 8> mask{};
  std::array<uint64_t, 8> surface{};  // value bits; only the bits of `mask` mean anything
};

/// A scene as leaves. The joins: for occupancy leaf i, vote grid k's leaf at
/// the same origin is votes[k].leaves[votes[k].at[i]] (kNoLeaf: none), the
/// colour leaf colorLeaves[colorAt[i]]. Leaves of the vote and colour grids
/// that hold no active voxel are not joined. Occupancy leaves may hold none.
struct SceneLeaves {
  static constexpr uint32_t kNoLeaf = UINT32_MAX;
  MetaEntries metadata;
  SceneHeader header;
  std::vector<OccupancyLeaf> occupancy;  // file order
  struct Votes {
    uint8_t classId = 0;
    std::vector<SceneLeaf<int32_t>> leaves;
    std::vector<uint32_t> at;  // per occupancy leaf
  };
  std::vector<Votes> votes;  // sorted by class id, as SceneGrids::votes
  bool hasColor = false;     // the file has a colour grid (even an empty one)
  std::vector<SceneLeaf<std::array<float, 3>>> colorLeaves;
  std::vector<uint32_t> colorAt;  // per occupancy leaf
  /// The leaves hold all a rewrite of the scene keeps (readSceneVdb then
  /// writeSceneVdb, which keep what the file has): every leaf of every scene
  /// grid has active voxels and every vote grid has leaves, the occupancy has
  /// no value bits at inactive voxels, the backgrounds and inactive values are
  /// 0, and the grids carry no metadata beyond the keys voxbake's writers
  /// give them. So a writer of these leaves (formats/scene/scene_vdb_direct.h)
  /// gives the bytes OpenVDB would. True for every scene voxbake writes.
  bool plainForm = false;
};

/// What readSceneLeaves reads. OccupancyOnly mirrors readSceneVdb's
/// SceneParts::OccupancyOnly (formats/vdb/scene_vdb.h), for renders that need
/// where voxels are, not what they are: the occupancy leaves only (`votes`
/// and `colorLeaves` empty, `hasColor` false, `plainForm` false, no joins); the other grids'
/// blocks are framed but not decompressed and the vote/colour topology is not
/// checked. The grid names and types are checked as for All, and every
/// grid's stored name must be its "name" metadata (the two readers pick the
/// occupancy grid by one and the other).
enum class SceneLeafParts { All, OccupancyOnly };

/// Reads `path` into leaves, or std::nullopt when the file is not of the form
/// above or fails a scene check (read it with readSceneVdb, which says why).
/// Throws vox::Error like readSceneVdb for what the walk refuses (BadInput:
/// missing, non-VDB, truncated or corrupt files) and for the memory guard
/// (Resource; the estimate counts these packed leaves, their active values
/// from the walk's leaf masks, and the mapped file: vdb_memory.h). Leaves are
/// decoded on the TBB workers the process allows; the result does not depend
/// on their number.
std::optional<SceneLeaves> readSceneLeaves(const std::string& path, SceneLeafParts parts = SceneLeafParts::All);

}  // namespace vox
