// The one colour a voxel is drawn with where a format has one colour per voxel
// (point clouds, MagicaVoxel palettes): its baked colour encoded to 8-bit sRGB
// (FaceColor::Voxel, when it has one), else its class's display colour.
#pragma once

#include <array>
#include <cstdint>

#include "libvox/core/block_mesh.h"
#include "libvox/core/class_volume.h"
#include "libvox/core/classes.h"

namespace vox {

class VoxelColors {
 public:
  VoxelColors(const ClassTable& classes, FaceColor mode);

  /// The colour of voxel `i` of `brick`. Throws vox::Error (BadInput) when its
  /// class is not in the table. Counts voxels that fell back to the class
  /// colour in Voxel mode; not thread-safe (one per thread).
  Rgb8 operator()(const ClassVolume::Brick& brick, int i);
  uint64_t uncolored() const { return uncolored_; }

 private:
  FaceColor mode_;
  std::array<bool, 256> known_{};
  std::array<Rgb8, 256> display_{};
  uint64_t uncolored_ = 0;
};

}  // namespace vox
