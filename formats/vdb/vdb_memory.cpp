#include "formats/vdb/vdb_memory.h"

#include <algorithm>

#include "formats/scene/scene_meta.h"
#include "libvox/core/memory_budget.h"

namespace vox {

namespace {
/// Bytes of one value of a tree type that is not bool or mask ("Tree_float_5_4_3"...).
uint64_t valueBytesOf(const std::string& type) {
  if (type.find("vec3d") != std::string::npos) return 24;
  if (type.find("vec3") != std::string::npos) return 12;
  if (type.find("double") != std::string::npos || type.find("int64") != std::string::npos) return 8;
  return 4;
}


/// A leaf's share of the internal nodes: a 16^3 node (32 KB of child table
/// and masks) per up to 4096 leaves; on surfaces it holds a few hundred.
constexpr uint64_t kInternalShare = 160;

/// Resident bytes of an internal node of a tree of this type with 2^(3 log2)
/// children: a table entry per child (a pointer or a tile value, 8 bytes or
/// the value's size rounded up to 8), child and value masks, its malloc header
/// (OpenVDB 10 on x86-64: 270,348 bytes for a 32^3 node, 33,804 for 16^3, as
/// memUsage() gives for int32 and bool trees; twice the table for Vec3s).
double internalNodeBytes(const std::string& type, int log2) {
  const bool bits = type.find("_bool_") != std::string::npos || type.find("_mask_") != std::string::npos;
  const double entry = bits ? 8.0 : double(std::max<uint64_t>(8, (valueBytesOf(type) + 7) / 8 * 8));
  const double children = double(uint64_t(1) << (3 * log2));
  return children * entry + 2 * children / 8 + 16 + 16;
}
}  // namespace

uint64_t vdbLeafBytes(const std::string& type) {
  // OpenVDB 10 on x86-64: a leaf is its origin, value mask and buffer; values
  // of 512 voxels live in a separate heap block (except bool and mask leaves,
  // whose values are bits); and its share of the internal nodes.
  constexpr uint64_t kLeafHeader = 96 + 16, kMalloc = 16;
  if (type.find("_bool_") != std::string::npos) return 64 + 64 + kLeafHeader + kInternalShare;
  if (type.find("_mask_") != std::string::npos) return 64 + kLeafHeader + kInternalShare;
  return 512 * valueBytesOf(type) + kMalloc + kLeafHeader + kInternalShare;
}

double vdbPackedLeafBytes(const std::string& type, double activeVoxels) {
  // x86-64 glibc: a heap block is its size plus 8 bytes rounded up to 16, at
  // least 32. The leaf record: origin, 512-bit mask and the values' pointer
  // (88 bytes), or origin and two masks for the occupancy (144 bytes, values
  // as bits); every other grid joins the occupancy through a 4-byte entry per
  // occupancy leaf, counted here as one per leaf of the grid (about as many).
  constexpr double kBlockOverhead = 8 + 8;  // the block's size word and half a rounding on average
  constexpr double kJoin = 4;
  // The occupancy's record and, while the grids are joined, its entry in the
  // origin map (a 32-byte node and a bucket).
  if (type.find("_bool_") != std::string::npos || type.find("_mask_") != std::string::npos) return 144 + 48;
  return 88 + kJoin + std::max(32.0, activeVoxels * double(valueBytesOf(type)) + kBlockOverhead);
}

double sceneGridBytes(const VdbFrame& frame, bool occupancyOnly, SceneReadForm form) {
  double grids = 0;
  for (const VdbGridFrame& g : frame.grids) {
    if (!g.checked || !g.instanceParent.empty() || (occupancyOnly && g.uniqueName != kOccupancyGridName)) continue;
    if (form == SceneReadForm::Trees) {
      // The internal nodes themselves where they outweigh the leaves' share:
      // a sparse grid (a pyramid's coarse level, a class of few leaves) keeps
      // a 264 KB top node for a handful of leaves (two hamlet pyramids at
      // 256: 42 MiB of nodes, estimated 0.3 MiB; vox diff came out 0.79x).
      const double nodes = double(g.upperNodes) * internalNodeBytes(g.type, 5) +
                           double(g.lowerNodes) * internalNodeBytes(g.type, 4);
      grids += double(g.leafCount) * double(vdbLeafBytes(g.type)) +
               std::max(0.0, nodes - double(g.leafCount) * double(kInternalShare));
    } else if (g.leafCount > 0) {
      const double perLeaf = double(g.activeLeafVoxels) / double(g.leafCount);
      grids += double(g.leafCount) * vdbPackedLeafBytes(g.type, perLeaf);
    }
  }
  return grids;
}

VdbFrame vdbTopologyFrame(const std::string& path) { return VdbTopologyWalk(path).frame(); }

void checkSceneReadMemory(const VdbFrame& frame, bool occupancyOnly, const std::string& path, SceneReadForm form,
                          uint64_t fileBytes) {
  MemoryEstimate e;
  e.add("resident before reading", residentBytesNow());
  e.add("grids", sceneGridBytes(frame, occupancyOnly, form));
  if (form == SceneReadForm::PackedLeaves) e.add("the file, mapped", double(fileBytes));
  checkProcessMemory(e, "reading " + path);
}

}  // namespace vox
