// MagicaVoxel `.vox` files of a ClassVolume (the format's public spec,
// version 150 with the scene-graph extension; docs/export.md).
//
// Axes: MagicaVoxel's z is up, voxbake's y, so voxel (u, v, w) of the exported
// box is MagicaVoxel voxel (x, y, z) = (u - umin, wmax - w, v - vmin): a
// rotation about x (no mirror), so shapes keep their handedness.
//
// A model holds at most 256 voxels per axis, so the box is cut into tiles of
// 256^3 (the last ones smaller); each tile with voxels becomes one model
// (SIZE = the tile's extent, XYZI = its voxels), placed by the scene graph
// root nTRN -> nGRP -> one nTRN + nSHP per model. MagicaVoxel puts a model's
// voxel (x, y, z) at  translation + (x, y, z) - floor(size / 2), so a tile at
// offset o gets translation o + floor(size / 2) - floor(box size / 2): the
// models fit together and the whole box is centred as MagicaVoxel centres a
// single model (one model: translation 0).
//
// Palette: the RGBA chunk's 255 entries are palette indices 1..255.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>

#include "libvox/core/class_volume.h"

namespace vox {

struct MagicaVoxelResult {
  uint32_t models = 0;
  uint64_t voxels = 0, bytes = 0;
  std::array<uint32_t, 3> size{};  // of the box in MagicaVoxel axes
};

/// Writes every voxel of `volume` (inside its box) with the palette index
/// `indexOf(brick, i)` (1..255) and `palette` (entry k is index k + 1).
/// Throws vox::Error (Io) when writing fails.
MagicaVoxelResult writeMagicaVoxel(const ClassVolume& volume, const std::array<Rgb8, 255>& palette,
                                   const std::function<uint8_t(const ClassVolume::Brick&, int)>& indexOf,
                                   const std::string& path);

}  // namespace vox
