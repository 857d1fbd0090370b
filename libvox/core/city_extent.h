// The demo city's name, placement constants and extent limits: what the CLI
// checks before any work (in the light module too, which cannot include the
// generator, libvox/scene/demo_city.h). One place for these values.
#pragma once

#include <array>
#include <cstdint>
#include <string>

namespace vox {

/// The city's name as an input ("demo:city"), recorded as its source (kind "demo").
inline constexpr const char* kCityName = "demo:city";

/// World units (metres) per voxel edge, whatever the extent: a street is 16 m
/// wide, a storey 3 m, a street block 96 m.
inline constexpr double kCityVoxelSize = 0.5;

/// Largest extent per horizontal axis (x, z) and vertically (y), in voxels.
inline constexpr uint32_t kCityMaxHorizontal = 65536;
inline constexpr uint32_t kCityMaxHeight = 4096;
inline constexpr std::array<uint32_t, 3> kCityDefaultExtent{1024, 256, 1024};

/// Why `extent` (voxels along x, y, z) is not a valid city extent, "" when it
/// is: every axis >= 1, x and z <= kCityMaxHorizontal, y <= kCityMaxHeight.
inline std::string cityExtentProblem(const std::array<uint32_t, 3>& extent) {
  const char* axes = "XYZ";
  for (size_t a = 0; a < 3; ++a) {
    const uint32_t limit = a == 1 ? kCityMaxHeight : kCityMaxHorizontal;
    if (extent[a] < 1 || extent[a] > limit)
      return std::string("extent ") + axes[a] + " = " + std::to_string(extent[a]) + " is outside 1.." +
             std::to_string(limit) + (a == 1 ? " (the height)" : " (a horizontal side)");
  }
  return {};
}

}  // namespace vox
