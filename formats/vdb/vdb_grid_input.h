// OpenVDB grids (level sets and fog volumes from other tools) to scenes.
//
// * Level set (grid class "level set"): inside where the trilinearly sampled
//   signed distance at a voxel centre is <= 0.
// * Float and double grids are read, each sampled in its own precision.
// * Fog volume or any other scalar grid: inside where the sampled density is
//   >= the threshold, which must be given (there is no universal default);
//   a level set refuses one (it would change nothing).
// The output grid covers the world bounding box of the input's active region
// (level sets: the narrow band), with the requested resolution on its longest
// axis or the given voxel size; origin = that box's minimum corner.
// Surface voxels are inside voxels with an outside 6-neighbour. Each inside
// voxel gets kInteriorVotes votes of one class named after the grid, no colour.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "libvox/core/progress.h"
#include "libvox/scene/scene.h"

namespace vox {

struct VdbGridInputOptions {
  std::string gridName;              // empty: the file's first float or double grid
  std::optional<double> threshold;   // required for grids that are not level sets, refused for level sets
  uint32_t resolution = 0;           // voxels on the longest axis, or
  double voxelSize = 0;              // world units per voxel (one of the two > 0)
  unsigned threads = 1;
  ProgressFn progress;
  /// A region bake: called with the world's header (dims, placement, class,
  /// source) once it is known, returns the inclusive index box to resample
  /// (nullopt: the whole grid). Only the box and a 1-voxel halo around it are
  /// sampled (the surface flag reads the 6 neighbours), so the scene is the
  /// whole resampling cropped to the box, in the box's time and memory.
  std::function<std::optional<IndexBox>(const SceneHeader&)> regionOf;
};

/// Throws vox::Error (BadInput) naming the file and grid, (Usage) for a fog
/// volume without a threshold, a level set with one, or a missing resolution.
Scene readVdbGridAsScene(const std::string& path, const VdbGridInputOptions& options);

}  // namespace vox
