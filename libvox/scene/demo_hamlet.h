// The built-in demo scene: a procedural hamlet like the one the UVW atlas
// layout's demo shows (ground slab, a diagonal path, four hollow buildings,
// eight trees, a well), so the whole pipeline runs with nothing to download.
//
// Geometry is defined on a 256-unit design cube (x, z horizontal, y up, like the
// block-map format's block world) and sampled at voxel centres, so any resolution
// gives the same hamlet. Classes are the block palette (vox::blockPalette()).
// Votes vary per voxel (a coordinate hash, never a random generator), so the
// summary bytes conf, obs and mrg take many values; boundaries between materials
// get mixed votes. Surface voxels are occupied voxels with an empty 6-neighbour
// (outside the domain counts as empty). The scene carries no colour.
#pragma once

#include <cstdint>
#include <optional>

#include "libvox/core/progress.h"
#include "libvox/mesh/voxel_blocks.h"
#include "libvox/scene/scene.h"

namespace vox {

/// The hamlet's name as an input ("demo:hamlet"), recorded as its source.
inline constexpr const char* kHamletName = "demo:hamlet";

struct HamletOptions {
  uint32_t resolution = 256;  // voxels per axis; the scene is resolution^3, >= 1
  unsigned threads = 1;       // 1 = serial; the result does not depend on it
  ProgressFn progress;        // optional, called with the fraction of slices done
  /// Only the voxels inside this inclusive index box (a region bake's tile):
  /// exactly the whole hamlet's voxels there (the surface test reads the
  /// neighbours from the design, not from the voxels made), in time and memory
  /// of the box. Absent: the whole hamlet.
  std::optional<IndexBox> box;
};

/// Builds the hamlet. World placement: voxel size 1 / resolution * 25.6, so the
/// hamlet is 25.6 world units (metres) across at any resolution, origin at
/// (-12.8, 0, -12.8) (centred on x and z, ground at y = 0).
Scene buildHamlet(const HamletOptions& options);

/// The same hamlet as voxel blocks and its header (what the direct scene
/// writer takes), without building OpenVDB trees.
VoxelBlocks buildHamletBlocks(const HamletOptions& options, SceneHeader& header);

}  // namespace vox
