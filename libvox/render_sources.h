// What render-canonical renders from: a scene (.vdb, demo, map) or a page file
// (.vpk). Both become a RayGrid for the rays, a GridFrame for the camera, a
// class table, and a per-voxel lookup of the summary bytes (for class and
// shaded renders and for picking).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "libvox/render.h"
#include "libvox/scene.h"
#include "libvox/summary_bytes.h"

namespace vox {

namespace pagefile {
class Reader;
}

/// Occupancy of `scene` (every occupied voxel, interior too) as a RayGrid.
/// OpenVDB leaves become bricks word for word; active tiles are expanded.
RayGrid rayGridFromScene(const Scene& scene);

/// Summary bytes (seed 000: winning class, confidence, observations, margin) of
/// each voxel in `voxels` (empty voxels: all zero). Serial, one accessor per grid.
std::vector<SummaryTexel> sceneSummaries(const Scene& scene, std::span<const Coord3> voxels);

/// Level `level` of a page file as a RayGrid (every layout the reader decodes).
RayGrid rayGridFromPages(const pagefile::Reader& reader, int level);

/// Summary bytes stored in a page file for `voxels` of `level` (empty: zero).
/// `voxels` must be sorted by (w, v, u) or any order: each chunk is decoded once
/// per call.
std::vector<SummaryTexel> pageSummaries(const pagefile::Reader& reader, int level, std::span<const Coord3> voxels);

}  // namespace vox
