// Fused scenes on disk (`vox fuse`, docs/fuse.md): a scene file
// (formats/scene/SCENE.md) plus one int32 grid named `free` holding each
// voxel's free-space count (active where the count is > 0, occupied or not).
// Scene readers ignore the extra grid, so a fused scene is an ordinary scene.
#pragma once

#include <string>

#include "libvox/scene/fuse_scene.h"
#include "libvox/scene/scene.h"

namespace vox {

inline constexpr const char* kFreeGridName = "free";

/// Writes `scene` and its free counts (inside the dims; clamped to 2^31 - 1)
/// to `path`, emptying `free` brick by brick as the grid is built (one copy
/// in memory at a time). Throws vox::Error (Io).
void writeFusedSceneVdb(const Scene& scene, FuseCounts&& free, const std::string& path);

/// Adds the `free` grid of a scene file to `into` (nothing when the file has
/// none), leaf by leaf into its bricks. Throws vox::Error (BadInput) naming
/// the file when the grid is not int32, holds a count <= 0 or a voxel outside
/// the dims.
void readFreeGrid(const std::string& path, FuseCounts& into);

}  // namespace vox
