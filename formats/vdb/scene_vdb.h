// Reading and writing scenes as OpenVDB .vdb files. The grids and metadata keys
// are specified in formats/scene/SCENE.md.
#pragma once

#include <string>

#include "formats/vdb/vdb_structure.h"  // looksLikeVdb
#include "libvox/scene/scene.h"

namespace vox {

/// Writes `scene` to `path` (overwriting it). Callers that need atomic outputs
/// pass a temporary path and rename it (tools/cli/cli.h does). Throws vox::Error (Io).
void writeSceneVdb(const Scene& scene, const std::string& path);

/// Reads a scene written by writeSceneVdb. Throws vox::Error (BadInput) naming the
/// file and the grid or metadata key when the file is missing, unreadable,
/// truncated, not a .vdb, or not a voxbake scene (missing grids, wrong types,
/// metadata out of range, voxels outside the dims, votes of 0 or negative).
Scene readSceneVdb(const std::string& path);

/// What readSceneVdb loads. OccupancyOnly reads the header and the occupancy
/// grid and leaves the vote and colour grids in the file (the returned scene
/// has no vote grids, so it breaks the "every occupied voxel has a vote"
/// invariant: for renderers and tools that need where voxels are, not what
/// they are). It is checked like a full read otherwise, except that the
/// other grids' blocks of a file voxbake wrote are framed (sizes, Blosc
/// headers) but not decompressed (vdb_scene_direct_read.h).
enum class SceneParts { All, OccupancyOnly };
Scene readSceneVdb(const std::string& path, SceneParts parts);

/// readSceneVdb (All) of a file whose topology is already walked, finishing
/// that walk: the same scene and errors, the file read once (vox merge
/// estimates every part's memory from its topology before reading any).
Scene readSceneVdb(VdbTopologyWalk& walked);


}  // namespace vox
