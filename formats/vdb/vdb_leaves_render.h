// A scene read as leaves (vdb_scene_leaves.h) as a render source, without
// OpenVDB: the RayGrid, summary bytes and colours that
// libvox/scene/render_scene.h gives for the same scene read with OpenVDB,
// bit for bit, so that the light render module (tools/cmds/render_main.cpp)
// writes the images vox-cmds.so writes.
#pragma once

#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include "formats/vdb/vdb_scene_leaves.h"
#include "libvox/core/summary_bytes.h"
#include "libvox/render/ray_grid.h"
#include "libvox/render/render_modes.h"

namespace vox {

/// rayGridFromScene for the leaves: every occupancy leaf becomes its brick
/// word for word (leaves with a negative origin coordinate are skipped, as
/// there; readSceneLeaves accepts no tiles).
RayGrid rayGridFromLeaves(const SceneLeaves& scene);

/// Per-voxel lookups in `scene` (which must outlive this): sceneSummaries and
/// sceneColors of render_scene.h. Serial; const calls are thread-safe.
class SceneLeavesLookup {
 public:
  explicit SceneLeavesLookup(const SceneLeaves& scene);
  /// Summary bytes of each voxel (empty voxels: zero). Needs the votes (a read of SceneLeafParts::All).
  std::vector<SummaryTexel> summaries(std::span<const Coord3> voxels) const;
  /// sRGB8 colour and alpha 255 of each voxel with a colour, else zeros.
  std::vector<VoxelColor8> colors(std::span<const Coord3> voxels) const;

 private:
  /// The occupancy leaf holding voxel c and c's bit in it, or false.
  bool find(const Coord3& c, uint32_t& leaf, uint32_t& bit) const;
  const SceneLeaves& s_;
  std::unordered_map<uint64_t, uint32_t> byOrigin_;  // leaf key -> occupancy leaf
};

}  // namespace vox
