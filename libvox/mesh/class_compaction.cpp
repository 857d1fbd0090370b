#include "libvox/mesh/class_compaction.h"

#include <algorithm>

#include "libvox/core/error.h"
#include "libvox/mesh/voxel_blocks.h"

namespace vox {

ClassRemap compactClassTable(ClassTable& table, const std::array<bool, 256>& used, ClassIds ids) {
  ClassRemap remap{};
  ClassTable kept;
  uint8_t next = 1;
  for (const ClassInfo& c : table.classes()) {  // ascending ids: the order is kept
    if (!used[c.id]) continue;
    ClassInfo k = c;
    if (ids == ClassIds::Dense) k.id = next++;
    remap[c.id] = k.id;
    kept.add(std::move(k));
  }
  table = std::move(kept);
  return remap;
}

std::array<bool, 256> classesOfTriangles(const std::vector<uint8_t>& triangleClass) {
  std::array<bool, 256> used{};
  for (uint8_t c : triangleClass) used[c] = true;
  used[0] = false;
  return used;
}

std::array<bool, 256> classesWithVotes(VoxelBlocks& blocks, const ClassTable& table) {
  std::array<bool, 256> used{}, wanted{};
  size_t missing = 0;
  for (const ClassInfo& c : table.classes()) wanted[c.id] = true, ++missing;
  auto mark = [&](uint8_t id) {
    if (wanted[id] && !used[id]) used[id] = true, --missing;
  };
  for (const VoxelBlock* b : blocks.sortedBlocks()) {
    if (missing == 0) break;
    for (const auto& cb : b->classes)
      if (!used[cb->classId] && !cb->empty())
        mark(cb->classId);
    if (b->runVotes != 0 && b->hasRuns()) mark(b->runClass);
  }
  return used;
}

void remapTriangleClasses(std::vector<uint8_t>& triangleClass, const ClassRemap& remap) {
  for (uint8_t& c : triangleClass) {
    if (c != 0 && remap[c] == 0)
      throw Error(ErrorKind::Internal, "remapTriangleClasses: a used class " + std::to_string(c) + " was left out");
    c = remap[c];
  }
}

void remapBlockClasses(VoxelBlocks& blocks, const ClassRemap& remap) {
  for (VoxelBlock* b : blocks.sortedBlocks()) {
    auto& cls = b->classes;
    cls.erase(std::remove_if(cls.begin(), cls.end(), [&](const std::unique_ptr<ClassBlock>& cb) { return remap[cb->classId] == 0; }),
              cls.end());
    for (auto& cb : cls) cb->classId = remap[cb->classId];
    if (b->hasRuns()) {
      if (remap[b->runClass] == 0) {
        if (b->runVotes != 0)
          throw Error(ErrorKind::Internal, "remapBlockClasses: class " + std::to_string(b->runClass) + " has votes");
        b->runMask = {};
      } else {
        b->runClass = remap[b->runClass];
      }
    }
  }
}

bool leaveOutClassesWithoutVotes(VoxelBlocks& blocks, ClassTable& table, ClassIds ids) {
  const size_t before = table.size();
  const ClassRemap remap = compactClassTable(table, classesWithVotes(blocks, table), ids);
  if (table.size() == before) return false;
  remapBlockClasses(blocks, remap);
  return true;
}

}  // namespace vox
