// A scene as a render source: its occupancy as a RayGrid for the rays and a
// per-voxel lookup of the summary bytes (for class and shaded renders and for
// picking). The page-file source is formats/pagefile/pagefile_ray_grid.h.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "libvox/render/render.h"
#include "libvox/render/render_modes.h"
#include "libvox/core/summary_bytes.h"
#include "libvox/scene/scene.h"

namespace vox {

/// Occupancy of `scene` (every occupied voxel, interior too) as a RayGrid.
/// OpenVDB leaves become bricks word for word; active tiles are expanded.
RayGrid rayGridFromScene(const Scene& scene);

/// The summary bytes (libvox/core/summary_bytes.h: winning class, confidence,
/// observations, margin) of each voxel in `voxels` (empty voxels: all zero).
/// Serial, one accessor per grid.
std::vector<SummaryTexel> sceneSummaries(const Scene& scene, std::span<const Coord3> voxels);

/// The colour of each voxel in `voxels` as displayed (render_modes.h
/// VoxelColor8): the scene's linear colour encoded to 8-bit sRGB
/// (linearToSrgb8, as page files store it), alpha 255; all zero for a voxel
/// without colour and for every voxel of a scene without colour. Serial.
std::vector<VoxelColor8> sceneColors(const Scene& scene, std::span<const Coord3> voxels);

}  // namespace vox
