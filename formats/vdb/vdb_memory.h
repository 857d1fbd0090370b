// What a .vdb file's grids take in memory once OpenVDB has read them, from
// the leaf counts of the structure walk (vdb_structure.h) before anything is
// read: the scene and pyramid readers check it against the memory limit
// (libvox/core/memory_budget.h), so every command that reads one is guarded.
#pragma once

#include <cstdint>
#include <string>


namespace vox {

/// Resident bytes of one leaf of a tree of this type ("Tree_int32_5_4_3"...),
/// its buffer allocation and its share of the internal nodes included.
uint64_t vdbLeafBytes(const std::string& treeType);

}  // namespace vox
