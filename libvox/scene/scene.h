// The scene: a sparse voxel grid with a class histogram per occupied voxel.
//
// A Scene is the data model every subcommand reads and writes; on disk it is
// formats/scene/SCENE.md.
//   * Domain: index coordinates (u, v, w) in [0, X) x [0, Y) x [0, Z) (see types.h).
//   * World placement: voxel (u, v, w) covers world
//       origin + [u, u+1] * voxelSize  (likewise v, w),
//     i.e. `origin` is the world position of the min corner of voxel (0, 0, 0) and
//     the voxel's centre is origin + (u + 0.5) * voxelSize. This is OpenVDB's
//     convention (index i is a voxel centre) with a half-voxel translation.
//   * Per occupied voxel: integer votes per class (1..2^31-1 each, class ids
//     1..255 from the class table), a surface flag (true: a source surface crosses
//     the voxel or it borders empty space; false: interior fill), and, only when
//     the scene has colour, a linear-light RGB colour (interior voxels have none).
//   * An occupied voxel has at least one vote; an unoccupied voxel has none.
//
// Storage is OpenVDB trees (see scene_grids.h for direct access; this header does
// not include OpenVDB so that most translation units stay cheap to compile).
//
// Thread safety: a const Scene may be read from many threads at once; building
// is done through SceneBuilder (one per thread, then merge()).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "libvox/core/scene_header.h"

namespace vox {

struct SceneGrids;  // scene_grids.h
class VoxelBlocks;  // voxel_blocks.h
enum class ClassIds;  // libvox/mesh/class_compaction.h

/// Counts for `vox info`.
struct SceneStats {
  uint64_t occupied = 0;
  uint64_t surface = 0;
  uint64_t colored = 0;
  IndexBox bounds;  // of occupied voxels; empty() when the scene is empty
  struct PerClass {
    uint8_t classId = 0;
    uint64_t voxelsWithVotes = 0;  // voxels where this class has >= 1 vote
    uint64_t modeVoxels = 0;       // voxels where this class wins (ties: lowest id)
    uint64_t votes = 0;            // sum over voxels
  };
  std::vector<PerClass> perClass;  // classes present in the grids, by id
  uint64_t memoryBytes = 0;        // of the OpenVDB trees
};

class Scene {
 public:
  Scene();
  Scene(Scene&&) noexcept;
  Scene& operator=(Scene&&) noexcept;
  ~Scene();

  const SceneHeader& header() const { return header_; }
  SceneHeader& header() { return header_; }

  bool hasColor() const;
  uint64_t occupiedCount() const;
  /// Occupied voxels with the surface flag; counted from the leaf masks (fast).
  uint64_t surfaceCount() const;
  /// Class ids that have a vote grid, ascending.
  std::vector<uint8_t> classesPresent() const;

  /// The voxel at `c`, or nullopt when it is empty or outside the domain.
  /// Convenient, not fast: use forEachVoxel or scene_grids.h for bulk work.
  std::optional<VoxelView> voxel(Coord3 c, std::vector<ClassVotes>& storage) const;

  /// Calls `fn` once per occupied voxel in a deterministic order (OpenVDB leaf
  /// order, then x, y, z within a leaf). Serial.
  void forEachVoxel(const std::function<void(const VoxelView&)>& fn) const;

  SceneStats stats() const;

  SceneGrids& grids() { return *grids_; }
  const SceneGrids& grids() const { return *grids_; }

 private:
  friend class SceneBuilder;
  SceneHeader header_;
  std::unique_ptr<SceneGrids> grids_;
};

/// Accumulates voxels into a scene. Votes add up (saturating at
/// kMaxVotesPerClass); the surface flag is OR-ed; the last colour set wins.
/// All these are order-independent except colour, so builders filled by
/// different threads and merged give the same scene in any merge order as long
/// as no two builders set the colour of the same voxel.
class SceneBuilder {
 public:
  explicit SceneBuilder(SceneHeader header);
  /// A builder that starts from blocks filled elsewhere (voxel_blocks.h).
  SceneBuilder(VoxelBlocks&& blocks, SceneHeader header);
  SceneBuilder(SceneBuilder&&) noexcept;
  ~SceneBuilder();

  /// Adds `votes` votes for `classId` at `c` (which must be inside the domain and
  /// classId in the class table; checked in build()). Votes of 0 are ignored.
  void addVotes(Coord3 c, uint8_t classId, uint32_t votes, bool surface);
  /// The same votes for `length` voxels from `start` along +w (a run of a
  /// column); equivalent to that many addVotes calls, at a fraction of the cost.
  void addRun(Coord3 start, uint32_t length, uint8_t classId, uint32_t votes, bool surface);
  void setColor(Coord3 c, RgbLinear color);
  /// Moves the content of `other` (same header) into this builder.
  void merge(SceneBuilder&& other);
  /// Leaves out of the header's class table the classes that have no vote so
  /// far, renumbering the rest as `ids` says (libvox/mesh/class_compaction.h).
  /// Returns true when the table changed.
  bool leaveOutClassesWithoutVotes(ClassIds ids);

  /// Finishes the scene: checks every voxel lies in the domain and every class id
  /// is in the table (vox::Error otherwise), prunes the trees.
  Scene build() &&;

 private:
  SceneHeader header_;
  std::unique_ptr<VoxelBlocks> blocks_;  // votes accumulated in dense 8^3 blocks until build()
};

/// Result of comparing two scenes voxel for voxel (the basis of `vox diff`).
struct SceneDifference {
  bool headerDiffers = false;
  std::string headerNote;  // first differing header field, human-readable
  uint64_t voxelsCompared = 0;
  uint64_t voxelsDiffering = 0;
  std::optional<Coord3> firstDifference;  // smallest (w, v, u) among differing voxels
  std::string firstNote;                  // what differs there
  bool same() const { return !headerDiffers && voxelsDiffering == 0; }
};

/// Compares header (ignoring `sources` when `ignoreSources`) and every voxel.
SceneDifference compareScenes(const Scene& a, const Scene& b, bool ignoreSources = false);

}  // namespace vox
