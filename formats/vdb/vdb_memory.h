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

/// The guard of a scene read, before any grid is read: resident bytes now
/// plus the grids of `frame` the read loads (checked, not instances; with
/// `occupancyOnly` the `occupancy` grid only). Throws vox::Error (Resource)
/// "reading PATH needs about ..." over the limit.
void checkSceneReadMemory(const VdbFrame& frame, bool occupancyOnly, const std::string& path);

}  // namespace vox
