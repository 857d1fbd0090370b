// What a .vdb file's grids take in memory once OpenVDB has read them, from
// the leaf counts of the structure walk (vdb_structure.h) before anything is
// read: the scene and pyramid readers check it against the memory limit
// (libvox/core/memory_budget.h), so every command that reads one is guarded.
#pragma once

#include <cstdint>
#include <string>

#include "formats/vdb/vdb_structure.h"

namespace vox {

/// Resident bytes of one leaf of a tree of this type ("Tree_int32_5_4_3"...),
/// its buffer allocation and its share of the internal nodes included.
uint64_t vdbLeafBytes(const std::string& treeType);

/// Resident bytes of one leaf as the leaf reader keeps it (SceneLeaf or
/// OccupancyLeaf, vdb_scene_leaves.h: origin, masks and a heap block of its
/// active values only), `activeVoxels` being the leaves' active voxels on
/// average; its join entries included.
double vdbPackedLeafBytes(const std::string& treeType, double activeVoxels);

/// What a read keeps of each leaf: OpenVDB trees (readSceneVdb and the
/// one-pass reader: 512 values a leaf whatever its active count) or the leaf
/// reader's packed leaves (readSceneLeaves: the active values only, the file
/// mapped while it reads).
enum class SceneReadForm { Trees, PackedLeaves };

/// Resident bytes of the grids of `frame` read in `form` (checked grids, not
/// instances; with `occupancyOnly` the `occupancy` grid only): the "grids"
/// part of checkSceneReadMemory, and what `vox info` reports per form.
double sceneGridBytes(const VdbFrame& frame, bool occupancyOnly, SceneReadForm form);

/// The frame of the .vdb at `path` once the topology of its grids is walked
/// (leaf counts and active leaf voxels as a Full walk gives them), without
/// decompressing a leaf buffer: for an estimate of several files that will
/// be resident together, made before any is read (`vox diff`). A fault in a
/// leaf buffer is left to the read; one in the framing or topology throws
/// the walk's vox::Error (BadInput) naming the file.
VdbFrame vdbTopologyFrame(const std::string& path);

/// The guard of a scene read, before any grid is read: resident bytes now
/// plus the grids of `frame` the read loads (checked, not instances; with
/// `occupancyOnly` the `occupancy` grid only) in `form`; for packed leaves
/// also the `fileBytes` of the mapped file, whose pages count while they are
/// read. Throws vox::Error (Resource) "reading PATH needs about ..." over the
/// limit. The estimate's "grids" part is what commands scale their working
/// copies by (Run::checkWorkMemory).
void checkSceneReadMemory(const VdbFrame& frame, bool occupancyOnly, const std::string& path,
                          SceneReadForm form = SceneReadForm::Trees, uint64_t fileBytes = 0);

}  // namespace vox
