// Small value types shared by every part of libvox. No dependencies.
//
// Coordinate spaces (used in names throughout the project):
//   index  (u, v, w): integer voxel coordinates, u in [0, X), v in [0, Y), w in [0, Z).
//                     Following OpenVDB, index (i, j, k) is the voxel's centre and the
//                     voxel covers [i-0.5, i+0.5] on each axis.
//   world  (x, y, z): metres (or whatever unit the source used), via SceneTransform.
//   texel  (layer, x, y): pixel addresses in an atlas or bitmap.
#pragma once

#include <array>
#include <cstdint>
#include <string>

namespace vox {

/// Scene extent in voxels. Every axis is >= 1 in a valid scene.
struct Dims {
  uint32_t x = 0, y = 0, z = 0;
  uint64_t count() const { return uint64_t(x) * y * z; }
  uint32_t maxAxis() const { return x > y ? (x > z ? x : z) : (y > z ? y : z); }
  bool operator==(const Dims&) const = default;
};

/// An index-space voxel coordinate. Signed so that bounding-box arithmetic and
/// neighbour lookups just outside the domain are representable.
struct Coord3 {
  int32_t u = 0, v = 0, w = 0;
  bool operator==(const Coord3&) const = default;
};

/// Inclusive index-space box; empty when min > max on any axis.
struct IndexBox {
  Coord3 min{1, 1, 1}, max{0, 0, 0};
  bool empty() const { return min.u > max.u || min.v > max.v || min.w > max.w; }
  bool operator==(const IndexBox&) const = default;
};

/// 8-bit sRGB-encoded colour, as stored in class tables and images.
struct Rgb8 {
  uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb8&) const = default;
};

/// Linear-light RGB in [0, 1].
struct RgbLinear {
  float r = 0, g = 0, b = 0;
  bool operator==(const RgbLinear&) const = default;
};

std::string toString(const Dims& d);    // "X x Y x Z"
std::string toString(const Coord3& c);  // "(u, v, w)"

}  // namespace vox
