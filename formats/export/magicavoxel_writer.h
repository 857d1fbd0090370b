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
// Only tiles that hold voxels are kept (in memory too), so a wide, sparse box
// costs its voxels, not its tiles.
//
// Limits: chunk sizes are 32-bit signed (the spec's `int`), so the MAIN
// chunk, which holds every other, ends at 2^31 - 1 bytes: about 536 million
// voxels. Translations (int32) and node ids reach far beyond what that holds.
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

/// The largest chunk (content + children) a .vox file holds.
inline constexpr uint64_t kMagicaVoxelMaxChunkBytes = 0x7FFFFFFF;

/// What a file will take, known before its voxel lists are allocated.
struct MagicaVoxelPlan {
  uint64_t models = 0, voxels = 0;
  uint64_t fileBytes = 0;    // the whole file; its MAIN chunk is fileBytes - 20
  uint64_t memoryBytes = 0;  // the models held while writing (voxel lists, scene graph)
};

/// Writes every voxel of `volume` (inside its box) with the palette index
/// `indexOf(brick, i)` (1..255) and `palette` (entry k is index k + 1).
/// `check`, when given, sees the plan first and may throw to refuse it (a
/// memory guard). Throws vox::Error (BadInput) when the file would exceed the
/// format's chunk size, before anything is written, and (Io) when writing fails.
MagicaVoxelResult writeMagicaVoxel(const ClassVolume& volume, const std::array<Rgb8, 255>& palette,
                                   const std::function<uint8_t(const ClassVolume::Brick&, int)>& indexOf,
                                   const std::string& path,
                                   const std::function<void(const MagicaVoxelPlan&)>& check = nullptr);

}  // namespace vox
