#include "libvox/core/voxel_colors.h"

#include "libvox/core/color.h"
#include "libvox/core/error.h"

namespace vox {

VoxelColors::VoxelColors(const ClassTable& classes, FaceColor mode) : mode_(mode) {
  for (const ClassInfo& c : classes.classes()) {
    known_[c.id] = true;
    display_[c.id] = c.color;
  }
}

Rgb8 VoxelColors::operator()(const ClassVolume::Brick& brick, int i) {
  const uint8_t cls = brick.classes[size_t(i)];
  if (mode_ == FaceColor::Voxel) {
    if (brick.hasColor(i)) {
      const RgbLinear& c = brick.colors[size_t(i)];
      return {linearToSrgb8(c.r), linearToSrgb8(c.g), linearToSrgb8(c.b)};
    }
    ++uncolored_;
  }
  if (!known_[cls]) throwClassNotInTable(cls, brick.at(i));
  return display_[cls];
}

}  // namespace vox
