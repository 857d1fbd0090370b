// ClassVolume: the blocks of a box of a scene, as exporters want them: for each
// occupied voxel its winning class (the summary's `cls`: most votes, ties to
// the lowest id) and, when asked for, its colour, in bricks of 8^3 voxels.
//
// Space: index (u, v, w) of the scene the volume was cut from, so a block keeps
// its place in the world (libvox/core/types.h). Only voxels inside `box` (an
// inclusive index box) are kept; everything outside it reads as empty, the way
// the block renderer treats the world outside a chunk as air.
//
// Building: fill Bricks (from a scene: libvox/scene/class_volume_scene.h; from a
// page file: formats/pagefile/pagefile_class_volume.h; by hand in tests), hand
// them to add() in any order, then finish(). A brick's origin is a multiple of
// 8 on each axis (OpenVDB's leaf and page-file brick alignment); voxels of a
// brick outside the box are cleared by finish(). Colour is kept only when the
// volume was made `withColor`.
//
// After finish() the volume is immutable: bricks sorted by (v, w, u) brick
// coordinates, which is the block renderer's loop order (y, then z, then x),
// each linked to its six neighbours; safe to read from any number of threads.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "libvox/core/types.h"

namespace vox {

class ClassVolume {
 public:
  static constexpr int kBrickSide = 8;
  static constexpr int kBrickVoxels = 512;
  /// Voxel (x, y, z) of a brick (brick-local, 0..7) is entry x + 8 * (y + 8 * z),
  /// so one row along u is contiguous.
  static constexpr int voxelIndex(int x, int y, int z) { return x + kBrickSide * (y + kBrickSide * z); }

  struct Brick {
    Coord3 origin;                          // index of brick-local voxel (0, 0, 0)
    std::array<uint8_t, kBrickVoxels> classes{};  // 0 = empty
    std::vector<RgbLinear> colors;          // withColor volumes: kBrickVoxels entries, else empty
    std::array<uint64_t, kBrickVoxels / 64> colored{};  // bit i: voxel i has a colour
    /// The brick across each face, in BlockFace order (+u, -u, +v, -v, +w, -w):
    /// an index into bricks(), or -1 when that brick is empty. Set by finish().
    std::array<int32_t, 6> neighbours{-1, -1, -1, -1, -1, -1};

    bool hasColor(int i) const { return (colored[size_t(i) >> 6] >> (i & 63)) & 1; }
    /// Index-space coordinates of voxel i.
    Coord3 at(int i) const {
      return {origin.u + i % kBrickSide, origin.v + (i / kBrickSide) % kBrickSide, origin.w + i / (kBrickSide * kBrickSide)};
    }
    void setColor(int i, RgbLinear c);
  };

  /// An empty volume over `box` (inclusive index box; may be empty).
  ClassVolume(IndexBox box, bool withColor);

  const IndexBox& box() const { return box_; }
  bool withColor() const { return withColor_; }

  /// A brick at `origin` (multiples of 8), empty, with colour storage when the
  /// volume keeps colour.
  Brick makeBrick(Coord3 origin) const;
  /// Adds a filled brick. Two bricks at the same origin are an error at finish().
  /// Before finish() only; not thread-safe (fill bricks in parallel, add serially).
  void add(Brick brick);
  /// Clears voxels outside the box, drops empty bricks, sorts and links them.
  /// Throws vox::Error (Internal) on a misaligned or repeated brick origin.
  void finish();

  /// Heap bytes of a volume of `bricks` non-empty bricks (each brick's record
  /// and, `withColor`, its 512 colours): for memory guards before building.
  static uint64_t bytesFor(uint64_t bricks, bool withColor) {
    return bricks * (sizeof(Brick) + (withColor ? kBrickVoxels * sizeof(RgbLinear) + 16 : 0));
  }

  const std::vector<Brick>& bricks() const { return bricks_; }
  uint64_t occupiedCount() const { return occupied_; }
  /// The class at `c` (0 when empty or outside the box). O(log bricks): for
  /// tests and spot checks, not for bulk work.
  uint8_t classAt(Coord3 c) const;
  /// The brick holding `c`, or nullptr. O(log bricks).
  const Brick* brickAt(Coord3 c) const;

 private:
  IndexBox box_;
  bool withColor_;
  bool finished_ = false;
  std::vector<Brick> bricks_;
  uint64_t occupied_ = 0;
};

/// Throws vox::Error (BadInput): voxel `at` has class `classId`, which the
/// class table lacks, so it cannot be coloured.
[[noreturn]] void throwClassNotInTable(uint8_t classId, Coord3 at);

}  // namespace vox
