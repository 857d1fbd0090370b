// `vox mip` without OpenVDB: a scene read as leaves (vdb_scene_leaves.h) as
// level-0 blocks, and pyramid files written by the direct writer
// (formats/scene/scene_vdb_direct.h): the file writePyramidVdb (pyramid_vdb.h)
// writes for the same levels, byte for byte except the UUID.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "formats/vdb/vdb_scene_leaves.h"
#include "libvox/scene/mip_blocks.h"

namespace vox {

/// The scene as level-0 blocks, or std::nullopt when the leaves are not in
/// the plain form (SceneLeaves::plainForm: a rewrite would keep something
/// the blocks cannot hold). Consumes `leaves`; blocks are built on `threads`.
std::optional<MipBlocksLevel> mipBlocksFromLeaves(SceneLeaves&& leaves, unsigned threads = 1);

/// Writes `levels` (level 0 first, then levels 1, 2, ...) to `path` as one
/// pyramid file (pyramid_vdb.h), `occupancy` recorded in `vox:pyramid`.
/// Throws vox::Error (Io) when the file cannot be written.
void writePyramidVdbDirect(const std::vector<const MipBlocksLevel*>& levels, MipOccupancy occupancy,
                           const std::string& path, unsigned threads = 1);

/// Writes one level as a plain scene file (what writeSceneVdb writes for it).
void writeMipLevelVdbDirect(const MipBlocksLevel& level, const std::string& path, unsigned threads = 1);

}  // namespace vox
