// OpenVDB volumes of a ClassVolume's occupancy for renderers (vdb_render,
// Blender, Houdini), which draw float grids but not a scene's bool and int
// grids (docs/export.md):
//   * fog: FloatGrid "density", class fog volume, 1 in every occupied voxel and
//     background 0 elsewhere;
//   * level set: FloatGrid "surface", class level set, a narrow band of
//     `halfWidth` voxels on each side of the occupied voxels' boundary
//     (OpenVDB's topologyToLevelSet), distances in world units.
// Both carry the scene's placement: index (i, j, k) is the centre of voxel
// (u, v, w) = (i, j, k), at origin + (index + 0.5) * voxel size
// (formats/scene/SCENE.md), so they line up with the scene and its exports.
#pragma once

#include <cstdint>
#include <string>

#include "libvox/core/class_volume.h"
#include "libvox/render/render.h"

namespace vox {

enum class VdbVolumeKind { Fog, LevelSet };

struct VdbVolumeResult {
  uint64_t activeVoxels = 0;  // of the float grid (the level set's band included)
  IndexBox activeBox;         // index bounding box of its active voxels
  uint64_t bytes = 0;
};

/// Leaves of 8^3 the float grid of writeVdbVolume spans: one per brick of
/// `volume` for a fog volume; for a level set also the leaves within
/// ceil(halfWidth / 8) leaves of one on every axis (a superset of OpenVDB's
/// face-neighbour dilation by `halfWidth` voxels, which the band reaches
/// before the interior is taken out). The dilation is enumerated up to
/// `maxKeys` leaf keys (8 bytes each, twice); past that (a band of some 100 GB)
/// the count is an upper bound: x (2r + 1) per axis left, capped by the
/// dilated bounding box of the leaves.
uint64_t vdbVolumeLeafCount(const ClassVolume& volume, VdbVolumeKind kind, int halfWidth,
                            size_t maxKeys = size_t(1) << 25);

/// Peak working memory of writeVdbVolume (bytes, beyond `volume` itself) for
/// that many leaves: per leaf a float leaf, and for a level set OpenVDB's
/// mask copies and the second buffer its distance normalisation keeps
/// (calibrated in docs/reliability.md).
double vdbVolumeWorkBytes(uint64_t leafCount, VdbVolumeKind kind);

/// Writes the volume to `path`. `halfWidth` (voxels, >= 1) is used for level sets.
/// Throws vox::Error (Io) when writing fails.
VdbVolumeResult writeVdbVolume(const ClassVolume& volume, const GridFrame& frame, VdbVolumeKind kind,
                               int halfWidth, const std::string& path);

}  // namespace vox
