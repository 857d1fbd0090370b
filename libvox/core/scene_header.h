// What describes a scene and one of its voxels, without the scene model:
// the header (dims, placement, class table, sources), per-class votes and the
// view of one voxel. Light: the mesh bake, the direct scene writer and the
// atlas contents use these without linking OpenVDB (libvox/scene/scene.h is the
// scene model that stores them).
#pragma once

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "libvox/core/classes.h"
#include "libvox/core/types.h"

namespace vox {

/// A file the scene was made from, for provenance and `vox info`.
struct SceneSource {
  std::string path;    // as given on the command line, or "demo:hamlet"
  std::string kind;    // "mesh", "vdb", "blockmap", "demo"
  std::string sha256;  // hex digest of the file's bytes; empty for built-in scenes
  uint64_t bytes = 0;
  bool operator==(const SceneSource&) const = default;
};

/// The block world's grid (blocks per axis) of the block-map format when none
/// is given: the one place this default lives.
inline constexpr std::array<uint32_t, 3> kDefaultBlockWorldGrid{64, 48, 64};

/// How a scene made from a block map (`map.json`) sits in its block world;
/// renderers use it to line up the block-map format's cameras
/// (`metadata.json`).
struct BlockWorldPlacement {
  double worldScale = 1.0;
  std::array<uint32_t, 3> gridSize = kDefaultBlockWorldGrid;
  bool operator==(const BlockWorldPlacement&) const = default;
};

/// The range of placements a scene may have: voxel edges from kMinVoxelSize
/// world units (OpenVDB refuses a transform whose scale cubed is below 3e-15,
/// as nearly singular: edges under 1.45e-5) and every grid corner within
/// +-kMaxWorldCoordinate (beyond it doubles no longer resolve a unit, so no
/// position is exact).
inline constexpr double kMinVoxelSize = 1.5e-5;
inline constexpr double kMaxWorldCoordinate = 1e15;

/// Why (voxelSize, origin, dims) is outside that range, or "" when it fits.
inline std::string placementProblem(double voxelSize, const std::array<double, 3>& origin, const Dims& dims) {
  if (!std::isfinite(voxelSize) || !(voxelSize >= kMinVoxelSize)) {
    char text[160];
    std::snprintf(text, sizeof text,
                  std::isfinite(voxelSize) ? "the voxel size %g is below 1.5e-5 world units, the smallest an OpenVDB "
                                             "transform holds"
                                           : "the voxel size %g is not finite",
                  voxelSize);
    return text;
  }
  const double extent[3] = {double(dims.x), double(dims.y), double(dims.z)};
  for (int a = 0; a < 3; ++a) {
    const double lo = origin[size_t(a)], hi = lo + extent[a] * voxelSize;
    if (!std::isfinite(lo) || !(std::fabs(lo) <= kMaxWorldCoordinate) || !(std::fabs(hi) <= kMaxWorldCoordinate)) {
      char text[160];
      std::snprintf(text, sizeof text, "the grid would span %g..%g world units on axis %c, beyond +-1e15", lo, hi,
                    "xyz"[a]);
      return text;
    }
  }
  return {};
}

/// What a scene part holds when it is one region of a larger bake
/// (libvox/core/regions.h): the tile, the voxels it may hold, and the key of
/// the world bake it belongs to. A part keeps the world's dims and placement,
/// so its index coordinates are the world's and parts join by union.
struct SceneRegion {
  uint32_t index = 0;    // tile index, 0 <= index < count
  uint32_t count = 1;    // tiles in the bake
  IndexBox box;          // inclusive index box of the tile (empty(): the tile holds no voxel)
  std::string worldKey;  // hex digest of everything that decides the world's voxels (regionWorldKey)
  bool operator==(const SceneRegion&) const = default;
};

struct SceneHeader {
  Dims dims;                             // every axis >= 1
  double voxelSize = 1.0;                // world units per voxel edge, > 0
  std::array<double, 3> origin{0, 0, 0};  // world min corner of voxel (0,0,0)
  ClassTable classes;
  std::vector<SceneSource> sources;
  int mipLevel = 0;                      // 0 = full resolution; level n has voxels 2^n wide
  std::optional<BlockWorldPlacement> blockWorld;
  std::optional<SceneRegion> region;     // set on a part of a region bake; absent on whole scenes
  bool operator==(const SceneHeader&) const = default;
};

struct ClassVotes {
  uint8_t classId = 0;
  uint32_t votes = 0;
  bool operator==(const ClassVotes&) const = default;
};

/// Largest vote count one class can hold in one voxel (stored as int32 in the .vdb
/// so that every VDB reader shows it as a non-negative integer). Builders saturate.
inline constexpr uint32_t kMaxVotesPerClass = 0x7fffffffu;

/// One occupied voxel as seen by Scene::forEachVoxel. `votes` is sorted by class
/// id and only holds classes with votes > 0; it is valid during the callback only.
struct VoxelView {
  Coord3 at;
  bool surface = false;
  std::optional<RgbLinear> color;
  std::span<const ClassVotes> votes;
  uint64_t totalVotes() const {
    uint64_t t = 0;
    for (const ClassVotes& c : votes) t += c.votes;
    return t;
  }
};

}  // namespace vox
