// A scene's blocks as a ClassVolume (libvox/core/class_volume.h): the winning
// class of every occupied voxel (most votes, ties to the lowest id: the
// summary's `cls`) and, when asked for, its colour, clipped to an index box.
#pragma once

#include "libvox/core/class_volume.h"
#include "libvox/scene/scene.h"

namespace vox {

/// The part of `scene` inside `box` (inclusive, index space). Leaves are
/// converted in parallel on up to `threads` workers; the result does not
/// depend on `threads`.
ClassVolume classVolumeFromScene(const Scene& scene, const IndexBox& box, bool withColor, unsigned threads);

}  // namespace vox
