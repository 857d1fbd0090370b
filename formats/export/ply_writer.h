// Binary PLY point clouds of a ClassVolume: one vertex per occupied voxel at its
// centre, with colour and class, for any point viewer (docs/export.md):
//
//   ply
//   format binary_little_endian 1.0
//   comment voxbake vox export: occupied voxel centres (world units), colour (sRGB), class id
//   element vertex N
//   property float x / y / z          world = (index + 0.5) * voxel size + origin
//   property uchar red / green / blue 8-bit sRGB (libvox/core/voxel_colors.h)
//   property uchar class              the voxel's winning class id
//   end_header
//
// Vertices come brick by brick in the volume's order (bricks by v, w, u; within
// a brick u fastest, then v, then w): 16 bytes each, no padding.
#pragma once

#include <cstdint>
#include <string>

#include "libvox/core/voxel_colors.h"

namespace vox {

struct PlyWriteResult {
  uint64_t points = 0, bytes = 0, uncolored = 0;
};

/// Throws vox::Error (BadInput) for a class missing from `classes`, (Io) when writing fails.
PlyWriteResult writeVoxelPly(const ClassVolume& volume, const ClassTable& classes, FaceColor color,
                             const GridFrame& frame, const std::string& path);

}  // namespace vox
