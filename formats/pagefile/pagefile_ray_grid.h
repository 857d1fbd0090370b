// A page file as a render source: one level's occupancy as a RayGrid and the
// summary bytes it stores, for render-canonical and picking (no OpenVDB).
#pragma once

#include <span>
#include <vector>

#include "formats/pagefile/pagefile.h"
#include "libvox/core/summary_bytes.h"
#include "libvox/render/ray_grid.h"

namespace vox {

/// Level `level` of a page file as a RayGrid (every layout the reader decodes).
RayGrid rayGridFromPages(const pagefile::Reader& reader, int level);

/// Summary bytes stored in a page file for `voxels` of `level` (empty: zero).
/// `voxels` must be sorted by (w, v, u) or any order: each chunk is decoded once
/// per call.
std::vector<SummaryTexel> pageSummaries(const pagefile::Reader& reader, int level, std::span<const Coord3> voxels);

/// The colour bytes stored for `voxels` of `level` (sRGB8 + alpha 255, or all
/// zero for a voxel without colour, an empty voxel, or a file without colour).
std::vector<std::array<uint8_t, 4>> pageColors(const pagefile::Reader& reader, int level,
                                               std::span<const Coord3> voxels);

}  // namespace vox
