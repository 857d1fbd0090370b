// Where a voxel grid sits in world space for a mesh (or any box-shaped input).
//
// The grid covers the box [bmin, bmax] (the input's bounding box, or the given bounds):
// voxel size = the given one, or the box's longest side / resolution; dims =
// ceil(side / voxel size) per axis (at least 1), plus `pad` + 1 voxels on every
// side when pad > 0; origin = bmin - (pad + 1) * voxelSize then. So with
// resolution N the longest axis has exactly N voxels (plus padding), and a flat
// input (zero thickness on an axis) gets one voxel layer on that axis.
//
// Why pad + 1: the box's faces lie on voxel faces, and a surface voxelization
// takes the voxels on both sides of a face a triangle lies on (closed boxes),
// so the first layer outside the box is touched wherever the input reaches its
// box; `pad` more layers beyond it are empty (of the input's geometry; with
// --bounds the input may reach past the box).
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "libvox/core/scene_header.h"

namespace vox {

struct PlacementOptions {
  uint32_t resolution = 0;  // voxels on the longest axis, or
  double voxelSize = 0;     // world units per voxel (exactly one of the two)
  uint32_t pad = 0;         // empty voxel layers on every side (pad + 1 layers added when pad > 0)
  std::optional<std::array<double, 6>> bounds;  // xmin, ymin, zmin, xmax, ymax, zmax (world)
};

inline constexpr uint32_t kMaxGridAxis = 65536;

/// Fills dims, voxelSize and origin of a header. Throws vox::Error (Usage) for
/// inconsistent options, (BadInput) for an empty or degenerate box that needs
/// an explicit voxel size, and refuses grids beyond kMaxGridAxis per axis.
void placeGrid(const std::array<double, 3>& bmin, const std::array<double, 3>& bmax, const PlacementOptions& options,
               SceneHeader& header);

}  // namespace vox
