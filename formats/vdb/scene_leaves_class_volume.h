// A scene read as leaves (formats/vdb/vdb_scene_leaves.h) as a ClassVolume
// (libvox/core/class_volume.h), for exporters that run without OpenVDB: the
// same volume classVolumeFromScene (libvox/scene/class_volume_scene.h) builds
// from the scene's trees.
#pragma once

#include "formats/vdb/vdb_scene_leaves.h"
#include "libvox/core/class_volume.h"

namespace vox {

/// The part of `scene` inside `box` (inclusive, index space): the winning
/// class of every occupied voxel (most votes, ties to the lowest id: the
/// summary's `cls`) and, with `withColor`, its colour where the scene has
/// one. `scene` must have been read with SceneLeafParts::All. Leaves are
/// converted in parallel on up to `threads` workers; the result does not
/// depend on `threads`.
ClassVolume classVolumeFromLeaves(const SceneLeaves& scene, const IndexBox& box, bool withColor, unsigned threads);

}  // namespace vox
