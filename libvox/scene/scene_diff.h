// Comparing two scenes in the voxel's terms, for `vox diff` (docs/diff.md):
// the header field by field, the class table class by class, and the voxels
// with each kind of difference counted separately, so a change of votes is
// reported as a change of votes, not as "every voxel differs".
//
// Kinds of voxel difference (a voxel may have several):
//   * occupancy: occupied in one scene only (counted as only-in-A / only-in-B;
//     such a voxel is not compared for the other kinds);
//   * votes:     occupied in both, and some class's vote count differs by more
//                than `votesTolerance` (votes compared class id by class id);
//   * color:     occupied in both, and a colour is present in one only, or a
//                linear-light channel differs by more than `colorTolerance`;
//   * surface:   occupied in both, and the surface flag differs.
// Magnitudes (for the "worst" voxel): occupancy = total votes of the voxel that
// is present; votes = the largest |difference| of one class, in votes; color =
// the largest |difference| of one channel (1 when one side has no colour);
// surface = 1. The first voxel is the smallest (w, v, u); the worst has the
// largest magnitude, ties going to the smallest (w, v, u). Both are therefore
// the same at any thread count.
//
// Voxels are compared in index space over the union of both scenes' voxels,
// even when the headers differ (dims, voxel size, origin are reported there).
//
// Thread safety: diffScenes reads both scenes from up to `threads` threads.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "libvox/core/scene_header.h"
#include "libvox/scene/scene.h"

namespace vox {

enum class VoxelDiffKind { Occupancy = 0, Votes = 1, Color = 2, Surface = 3 };
inline constexpr int kVoxelDiffKinds = 4;
/// "occupancy", "votes", "color", "surface".
const char* voxelDiffKindName(VoxelDiffKind kind);

/// One scene's content at a voxel.
struct VoxelValues {
  bool occupied = false;
  bool surface = false;
  std::optional<RgbLinear> color;
  std::vector<ClassVotes> votes;  // sorted by class id, votes > 0
  bool operator==(const VoxelValues&) const = default;
};

struct VoxelDiffExample {
  Coord3 at;
  double magnitude = 0;
  VoxelValues a, b;
};

struct VoxelKindDiff {
  uint64_t count = 0;                      // voxels with this kind of difference
  std::optional<VoxelDiffExample> first;   // smallest (w, v, u)
  std::optional<VoxelDiffExample> worst;   // largest magnitude (ties: smallest (w, v, u))
};

/// A header field that differs, values as text ("64 x 64 x 64", "0.1").
struct HeaderFieldDiff {
  std::string field;  // "dims", "voxel_size", "origin", "mip_level", "block_world", "sources"
  std::string a, b;
};

/// A class whose entry differs ("absent" when only one table has it).
struct ClassEntryDiff {
  uint8_t id = 0;
  std::string a, b;  // "Stone #808080" or "absent"
};

struct SceneDiffOptions {
  uint32_t votesTolerance = 0;  // per class, in votes: |a - b| <= tolerance is equal
  double colorTolerance = 0;    // per linear-light channel in [0, 1]
  /// Sources are compared by kind, size and SHA-256 (a different path to the
  /// same bytes is not a difference); `ignoreSources` skips them entirely.
  bool ignoreSources = false;
  unsigned threads = 0;         // 0 = every core
};

struct SceneDiff {
  std::vector<HeaderFieldDiff> header;
  std::vector<ClassEntryDiff> classes;
  uint64_t voxelsA = 0, voxelsB = 0;
  uint64_t voxelsCompared = 0;   // occupied in either scene
  uint64_t voxelsDiffering = 0;  // with at least one kind of difference
  uint64_t onlyInA = 0, onlyInB = 0;
  std::array<VoxelKindDiff, kVoxelDiffKinds> kinds;
  std::optional<VoxelDiffExample> first;  // the smallest (w, v, u) with any difference
  const VoxelKindDiff& kind(VoxelDiffKind k) const { return kinds[size_t(k)]; }
  bool same() const { return header.empty() && classes.empty() && voxelsDiffering == 0; }
};

/// Compares `a` and `b` (see the top of this file).
SceneDiff diffScenes(const Scene& a, const Scene& b, const SceneDiffOptions& options = {});

/// The world position of voxel `c`'s centre: origin + (c + 0.5) * voxelSize.
std::array<double, 3> voxelCentreWorld(const SceneHeader& header, Coord3 c);

/// "empty" or "surface votes{1:40,3:2} color(0.5,0.25,0)", for messages.
std::string describeVoxel(const VoxelValues& v);

}  // namespace vox
