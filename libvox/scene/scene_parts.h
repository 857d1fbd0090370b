// Parts of a region bake (libvox/core/regions.h): cropping a scene to a box,
// and joining parts back into the world.
//
// A part keeps the world's header (dims, placement, class table, sources) and
// holds only the voxels inside its box, with exactly the values the whole bake
// gives them; parts join by union. The join goes through VoxelBlocks, the
// form the direct scene writer (formats/scene/scene_vdb_direct.h) streams, so
// a merged world is written byte for byte as the single-process bake writes it.
#pragma once

#include <string>
#include <vector>

#include "libvox/core/types.h"
#include "libvox/mesh/voxel_blocks.h"
#include "libvox/scene/scene.h"

namespace vox {

/// The voxels of `scene` as blocks (votes, surface flags, colours); with
/// `box`, only those inside it (inclusive). Deterministic; serial.
VoxelBlocks sceneBlocks(const Scene& scene, const IndexBox* box = nullptr);

/// `scene` cropped to `box` (inclusive): same header (region record untouched),
/// only the voxels inside the box.
Scene cropScene(const Scene& scene, const IndexBox& box);

/// One part's contribution to a merge, added to `into`: throws vox::Error
/// (BadInput) naming `name` when the part is not one (no region record), is a
/// pyramid level (mip level > 0) or holds a voxel outside its region box.
void addPartBlocks(const Scene& part, const std::string& name, VoxelBlocks& into);

/// The header of the world the parts join into: the parts' header without the
/// region record, taken from the part worldHeaderPart picks
/// (libvox/core/regions.h), so the order of `headers` does not change it.
/// Checks the set first (checkRegionParts: missing, repeated, overlapping or
/// foreign parts; vox::Error BadInput naming the part) and refuses pyramid
/// levels (mip level > 0). `names` are the parts' files, for messages.
SceneHeader mergedHeader(const std::vector<SceneHeader>& headers, const std::vector<std::string>& names);

/// The union of `parts` (checked as mergedHeader and addPartBlocks do), as a
/// Scene. `names` may be empty (parts are then called "part 0", "part 1"...).
Scene mergeSceneParts(std::vector<Scene>&& parts, const std::vector<std::string>& names = {});

}  // namespace vox
