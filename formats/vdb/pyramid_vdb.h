// LOD pyramids in one OpenVDB file (formats/scene/SCENE.md, section "Pyramids").
//
// The file is a complete level-0 scene (grids `occupancy`, `votes.<id>`,
// `color` and every `vox:*` key of a scene, so readSceneVdb and every VDB tool
// read it as the full-resolution scene) plus, for each level n >= 1, the grids
// `mip<n>.occupancy`, `mip<n>.votes.<id>`, `mip<n>.color`, each with its own transform (voxel
// size * 2^n) and grid metadata `vox:mip_level` = n, and the file metadata
// `vox:pyramid` (JSON) listing the levels.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "formats/vdb/vdb_structure.h"
#include "libvox/scene/mip.h"
#include "libvox/scene/scene.h"

namespace vox {

/// Writes `levels[0]` (the level-0 scene) and `levels[1..]` (levels 1, 2, ...)
/// to `path`. `occupancy` is recorded in `vox:pyramid`.
void writePyramidVdb(const std::vector<const Scene*>& levels, MipOccupancy occupancy, const std::string& path);

/// True when `path` is an OpenVDB file with a `vox:pyramid` key (cheap: reads
/// the framing only). False for a plain scene or a non-VDB file.
bool isPyramidVdb(const std::string& path);

/// The same for a file's walked frame (its file metadata's names).
bool isPyramidFrame(const VdbFrame& frame);

/// The `vox:pyramid` JSON text of a pyramid file (reads the metadata only), or
/// an empty string for a plain scene.
std::string readPyramidMetadata(const std::string& path);

/// What `vox:pyramid` says of a pyramid file's stored levels.
struct PyramidLevels {
  MipOccupancy occupancy = MipOccupancy::Any;
  int levels = 0;  // stored above level 0
};

/// The occupancy and the number of the stored levels (reads the metadata
/// only), or std::nullopt for a plain scene. Throws vox::Error (BadInput)
/// naming the file and the key when `vox:pyramid` is not JSON with an
/// `occupancy` of "any" or "majority" and a `levels` array.
std::optional<PyramidLevels> readPyramidLevels(const std::string& path);

/// Reads every level, level 0 first. A plain scene file gives one level.
/// Throws vox::Error (BadInput) naming the file, the level and the grid.
std::vector<Scene> readPyramidVdb(const std::string& path);

}  // namespace vox
