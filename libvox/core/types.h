// Small value types shared by every part of libvox, and the coordinate spaces
// they live in. No dependencies.
//
// Coordinate spaces. Where two meet, names carry the space (`originWorld`,
// `rayGrid`, `texelX`, `chunkLocal`), the way OpenVDB writes intersectsIS /
// intersectsWS. docs/conventions.md has the same list with figures.
//   world  (x, y, z)      doubles in the source's unit. A scene places its grid
//                         in world space by SceneHeader::voxelSize and
//                         SceneHeader::origin, the world position of the MIN
//                         CORNER of voxel (0, 0, 0).
//   grid   (gx, gy, gz)   doubles, g = (world - origin) / voxelSize: voxel
//                         (u, v, w) is the closed box [u, u+1] x [v, v+1] x
//                         [w, w+1] and its centre is (u + 0.5, v + 0.5, w + 0.5).
//                         The voxelizer, the ray caster and the renderer work here.
//   index  (u, v, w)      integers (Coord3), the voxel itself, u in [0, X),
//                         v in [0, Y), w in [0, Z) (Dims). OpenVDB's index space
//                         puts index i at the voxel's CENTRE (i covers
//                         [i - 0.5, i + 0.5]), so the .vdb transform translates by
//                         origin + voxelSize / 2 (formats/scene/SCENE.md).
//   texel  (layer, x, y)  pixel addresses in an atlas or bitmap, row 0 first
//                         (libvox/core/atlas_mapping.h: the UVW atlas layout).
//   pixel  (x, y)         render image pixels, row 0 at the top, rays through
//                         pixel centres (x + 0.5, y + 0.5) (libvox/render/camera.h).
//   chunk  (cx, cy, cz)   index / C for page files with C^3 chunks; the chunk
//                         key is the Morton code of (cx, cy, cz) (libvox/core/morton.h).
//   chunk-local (x, y, z) index - C * chunk, in [0, C); the voxel's bit in a
//                         chunk bitmap is x + C * (y + C * z) (formats/pagefile/PAGEFILE.md).
//   page                  byte offsets in a page file (header, index, payloads).
// "origin" alone means SceneHeader::origin (world, min corner of voxel 0). The
// block-map format's world origin (-X/2, 0, -Z/2) * worldScale is the same
// point for scenes made from map.json; a ray's start is its "start", not origin.
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

/// An index-space voxel coordinate (u, v, w). Signed so that bounding-box arithmetic and
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

/// The whole domain of a scene, [0, dims) as an inclusive box.
inline IndexBox domainBox(const Dims& dims) {
  return {{0, 0, 0}, {int32_t(dims.x) - 1, int32_t(dims.y) - 1, int32_t(dims.z) - 1}};
}

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
