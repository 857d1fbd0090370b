// The OpenVDB side of the scene format, shared by the scene file
// (scene_vdb.h) and the pyramid file (pyramid_vdb.h), which is a scene file
// plus one set of prefixed grids per level (formats/scene/SCENE.md):
//   * metadata: formats/scene/scene_meta.h's entries to and from an
//     openvdb::MetaMap (file metadata and grid metadata alike);
//   * writing: the grids of one level, each with the level's transform and
//     its grid metadata, and the file with voxbake's compression;
//   * reading: a file's metadata and grids, and the grids of one level turned
//     back into checked SceneGrids.
#pragma once

#include <openvdb/openvdb.h>

#include <string>

#include "formats/scene/scene_meta.h"
#include "formats/vdb/vdb_structure.h"
#include "libvox/scene/scene.h"
#include "libvox/scene/scene_grids.h"

namespace vox {

/// Inserts every entry into `into` (a file's MetaMap or a grid).
void insertVdbMetadata(openvdb::MetaMap& into, const MetaEntries& entries);
/// Every entry of `meta`; values of other types become ForeignMetaValue.
MetaEntries metaEntriesOf(const openvdb::MetaMap& meta);

/// Appends `scene`'s grids (occupancy, votes.<id> by id, color) to `out`,
/// named `namePrefix` + the scene grid name, each a shallow copy (the scene is
/// not modified) carrying the world transform of `scene`'s header (voxel
/// centre at origin + (i + 0.5) * voxel size), its grid metadata and `extra`.
void appendSceneGrids(const Scene& scene, const std::string& namePrefix, const MetaEntries& extra,
                      openvdb::GridPtrVec& out);

/// Writes `grids` and `meta` to `path` with Blosc and active-mask compression.
/// Throws vox::Error (Io) "PATH: cannot write the WHAT: ...".
void writeVdbFile(const std::string& path, const openvdb::GridPtrVec& grids, const openvdb::MetaMap& meta,
                  const std::string& what);

/// A scene file as read: its metadata, the header they describe, its grids.
struct VdbSceneFile {
  MetaEntries metadata;
  SceneHeader header;
  openvdb::GridPtrVec grids;
};
/// Which reader readVdbSceneFile uses. Auto: files of the form voxbake
/// writes are built in one pass from the structure walk
/// (vdb_scene_direct_read.h), others are walked and then read by OpenVDB
/// (CheckedVdbFile). OpenVdb: always the latter (tests compare the two).
enum class VdbSceneReader { Auto, OpenVdb };

/// Reads `path`, refusing missing, non-VDB and truncated files
/// (vdb_structure.h) and files without valid scene metadata
/// (sceneHeaderFromMetadata). With `occupancyOnly`, reads the `occupancy`
/// grid only. Throws vox::Error (BadInput) naming the file, (Resource) when
/// the memory guard refuses the grids.
VdbSceneFile readVdbSceneFile(const std::string& path, bool occupancyOnly,
                              VdbSceneReader reader = VdbSceneReader::Auto);

/// readVdbSceneFile (Auto) of a file whose topology is already walked,
/// finishing that walk; a file not of the form voxbake writes is read again
/// by OpenVDB (readVdbSceneFileChecked).
VdbSceneFile readVdbSceneFile(VdbTopologyWalk& walked, bool occupancyOnly);

/// readVdbSceneFile with VdbSceneReader::OpenVdb: the walk, then OpenVDB's reader.
VdbSceneFile readVdbSceneFileChecked(const std::string& path, bool occupancyOnly);

/// The checked grids of one level with header `h`: the grids of `fileGrids`
/// named `namePrefix` + a scene grid name ("" for a scene, "mip2." for level 2
/// of a pyramid; other names are ignored). Checks grid types, vote grid names
/// with ids of h's class table, one vote grid per class, counts >= 1, active
/// voxels inside h.dims; with `checkTopology` also votes and colour only at
/// occupied voxels and a vote at every occupied voxel. Expands tiles, renames
/// the grids to their scene names and gives them the identity transform.
/// Throws vox::Error (BadInput) "WHERE: grid 'NAME' ...".
SceneGrids levelGridsFromVdb(const openvdb::GridPtrVec& fileGrids, const std::string& namePrefix,
                             const SceneHeader& h, const std::string& where, bool checkTopology);

}  // namespace vox
