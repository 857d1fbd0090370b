// Reading voxbake's own scene files in one pass.
//
// Why: the scene reader used to walk a file with the bounds-checked walker
// (vdb_structure.h, which decompresses every block to check it) and then let
// openvdb::io::File read and decompress everything again; reading was the
// larger half of `vox pack-chunks` and `vox mip`. Files of the form voxbake
// writes (formats/scene/SCENE.md: grids of bool, int32 or vec3s values, no
// half floats, no instances, trees that are only their leaves: no tiles,
// every inactive value of an internal node the background) are built from the
// walk itself (walkVdbInto): each block is checked and decompressed once, the
// leaves in parallel, straight into the leaves of OpenVDB trees, which are
// then assembled in file order. Metadata and transforms are read by OpenVDB's
// own readers from the walked bytes, so the grids are the ones
// openvdb::io::File gives (tests/test_vdb_direct_read.cpp compares every leaf,
// metadata entry and transform). Other files (other value types, tiles,
// instances, half floats, point grids, foreign .vdb files) are left to
// CheckedVdbFile and OpenVDB's reader, unchanged.
#pragma once

#include <optional>
#include <string>

#include "formats/vdb/vdb_scene_grids.h"

namespace vox {

/// readVdbSceneFile (vdb_scene_grids.h) for a file of the form above: the
/// same metadata, header and grids (file order; with `occupancyOnly` the
/// `occupancy` grid only, and the other grids' blocks are framed but not
/// decompressed). std::nullopt when the file is not of that form, having
/// built nothing: read it with CheckedVdbFile. Throws vox::Error like
/// readVdbSceneFile: BadInput for missing, non-VDB, corrupt and non-scene
/// files (the walk's messages), Resource when the memory guard refuses.
/// Leaves are built on the TBB workers the process allows (the CLI's
/// --threads); the grids do not depend on their number.
std::optional<VdbSceneFile> readVdbSceneFileDirect(const std::string& path, bool occupancyOnly);

/// The same for a file whose topology is already walked (its first pass),
/// finishing that walk.
std::optional<VdbSceneFile> readVdbSceneFileDirect(VdbTopologyWalk& walked, bool occupancyOnly);

}  // namespace vox
