#include "formats/vdb/vdb_memory.h"

#include "formats/scene/scene_meta.h"
#include "libvox/core/memory_budget.h"

namespace vox {

uint64_t vdbLeafBytes(const std::string& type) {
  // OpenVDB 10 on x86-64: a leaf is its origin, value mask and buffer; values
  // of 512 voxels live in a separate heap block (except bool and mask leaves,
  // whose values are bits). Internal nodes: a 16^3 node (32 KB of child
  // table and masks) per up to 4096 leaves; on surfaces it holds a few
  // hundred, so about 160 bytes per leaf.
  constexpr uint64_t kLeafHeader = 96 + 16, kMalloc = 16, kInternalShare = 160;
  uint64_t valueBytes = 4;
  if (type.find("_bool_") != std::string::npos) return 64 + 64 + kLeafHeader + kInternalShare;
  if (type.find("_mask_") != std::string::npos) return 64 + kLeafHeader + kInternalShare;
  if (type.find("vec3d") != std::string::npos) valueBytes = 24;
  else if (type.find("vec3") != std::string::npos) valueBytes = 12;
  else if (type.find("double") != std::string::npos || type.find("int64") != std::string::npos) valueBytes = 8;
  return 512 * valueBytes + kMalloc + kLeafHeader + kInternalShare;
}

void checkSceneReadMemory(const VdbFrame& frame, bool occupancyOnly, const std::string& path) {
  MemoryEstimate e;
  e.add("resident before reading", residentBytesNow());
  double grids = 0;
  for (const VdbGridFrame& g : frame.grids)
    if (g.checked && g.instanceParent.empty() && (!occupancyOnly || g.uniqueName == kOccupancyGridName))
      grids += double(g.leafCount) * double(vdbLeafBytes(g.type));
  e.add("grids", grids);
  checkProcessMemory(e, "reading " + path);
}

}  // namespace vox
