// Leaving out of a mesh bake's class table the classes no voxel votes for.
//
// A mesh names more materials than its triangles use (glTF files keep unused
// materials; readers add a default material that may stay unused), and a
// class whose triangles all fall outside --bounds gets no voxel. A scene keeps
// only the classes it holds, so engines and `vox info` never list a class that
// is not there.
//
// Two steps, both deterministic: before voxelizing, the classes no triangle
// uses; after, the classes with no vote in the voxel blocks. Renumbering keeps
// the classes' order (ids stay ascending), so blocks stay sorted by class id.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "libvox/core/classes.h"

namespace vox {

class VoxelBlocks;  // voxel_blocks.h

/// Old class id -> new class id; 0 = left out.
using ClassRemap = std::array<uint8_t, 256>;

enum class ClassIds {
  Dense,  // renumber the classes kept 1, 2, ... in their id order (ids derived from material order)
  Keep,   // keep every id (ids chosen by a class rules file)
};

/// Removes from `table` the classes whose `used[id]` is false; with
/// ClassIds::Dense, renumbers the rest. Returns the remap (identity for kept
/// ids with ClassIds::Keep).
ClassRemap compactClassTable(ClassTable& table, const std::array<bool, 256>& used, ClassIds ids);

/// Which ids appear in a per-triangle class list.
std::array<bool, 256> classesOfTriangles(const std::vector<uint8_t>& triangleClass);

/// Which class ids of `table` have at least one vote in `blocks`. Stops as
/// soon as every class of the table has one (the usual case: a few blocks).
std::array<bool, 256> classesWithVotes(VoxelBlocks& blocks, const ClassTable& table);

/// Rewrites class ids through `remap` in place: per-triangle lists...
void remapTriangleClasses(std::vector<uint8_t>& triangleClass, const ClassRemap& remap);
/// ...and voxel blocks (a class mapped to 0 must have no vote; its empty
/// blocks are removed).
void remapBlockClasses(VoxelBlocks& blocks, const ClassRemap& remap);

/// The after-voxelizing step in one call: leaves out of `table` the classes
/// with no vote in `blocks` and renumbers both (with ClassIds::Dense).
/// Returns true when the table changed.
bool leaveOutClassesWithoutVotes(VoxelBlocks& blocks, ClassTable& table, ClassIds ids);

}  // namespace vox
