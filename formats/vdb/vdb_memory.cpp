#include "formats/vdb/vdb_memory.h"

#include <algorithm>

#include "formats/core/file_util.h"
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
}  // namespace

uint64_t vdbLeafBytes(const std::string& type) {
  // OpenVDB 10 on x86-64: a leaf is its origin, value mask and buffer; values
  // of 512 voxels live in a separate heap block (except bool and mask leaves,
  // whose values are bits). Internal nodes: a 16^3 node (32 KB of child
  // table and masks) per up to 4096 leaves; on surfaces it holds a few
  // hundred, so about 160 bytes per leaf.
  constexpr uint64_t kLeafHeader = 96 + 16, kMalloc = 16, kInternalShare = 160;
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
      grids += double(g.leafCount) * double(vdbLeafBytes(g.type));
    } else if (g.leafCount > 0) {
      const double perLeaf = double(g.activeLeafVoxels) / double(g.leafCount);
      grids += double(g.leafCount) * vdbPackedLeafBytes(g.type, perLeaf);
    }
  }
  return grids;
}

namespace {
/// Keeps the frame the walk hands over once the topology is walked, then
/// ends the walk before any leaf buffer.
class TopologySink final : public VdbWalkSink {
 public:
  struct Walked {};
  void fileMetadata(const uint8_t*, size_t) override {}
  std::vector<VdbLeafUse> topologyWalked(const VdbFrame& frame, const std::vector<VdbGridLayout>&) override {
    frame_ = frame;
    throw Walked{};
  }
  void leaf(size_t, size_t, const VdbLeafValues&) override {}
  void gridDone(size_t) override {}
  VdbFrame frame_;
};
}  // namespace

VdbFrame vdbTopologyFrame(const std::string& path) {
  checkVdbFileOpenable(path);
  const FileView file(path);  // mapped: only the topology's pages are touched
  TopologySink sink;
  try {
    walkVdbInto(reinterpret_cast<const uint8_t*>(file.data()), file.size(), path, sink);
  } catch (const TopologySink::Walked&) {
    return sink.frame_;
  }
  return sink.frame_;
}

void checkSceneReadMemory(const VdbFrame& frame, bool occupancyOnly, const std::string& path, SceneReadForm form,
                          uint64_t fileBytes) {
  MemoryEstimate e;
  e.add("resident before reading", residentBytesNow());
  e.add("grids", sceneGridBytes(frame, occupancyOnly, form));
  if (form == SceneReadForm::PackedLeaves) e.add("the file, mapped", double(fileBytes));
  checkProcessMemory(e, "reading " + path);
}

}  // namespace vox
