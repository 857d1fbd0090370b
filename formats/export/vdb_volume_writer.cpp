#include "formats/export/vdb_volume_writer.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/TopologyToLevelSet.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <cstdint>
#include <vector>

#include "formats/core/file_util.h"
#include "formats/vdb/vdb_memory.h"
#include "formats/vdb/vdb_structure.h"
#include "formats/scene/vdb_content_uuid.h"
#include "libvox/core/error.h"
#include "libvox/scene/scene_grids.h"

namespace vox {

namespace {
// Level sets: bytes per float leaf of the dilated set (measured, docs/reliability.md).
constexpr double kLevelSetBytesPerFloatLeaf = 1.85;
}  // namespace

uint64_t vdbVolumeLeafCount(const ClassVolume& volume, VdbVolumeKind kind, int halfWidth, size_t maxKeys) {
  // Leaf keys, 21 bits per axis biased so the dilation never goes negative.
  constexpr int64_t kBias = int64_t(1) << 20;
  auto key = [](int64_t a, int64_t b, int64_t c) { return uint64_t(a) << 42 | uint64_t(b) << 21 | uint64_t(c); };
  std::vector<uint64_t> leaves;
  leaves.reserve(volume.bricks().size());
  for (const ClassVolume::Brick& b : volume.bricks())
    leaves.push_back(key((b.origin.u >> 3) + kBias, (b.origin.v >> 3) + kBias, (b.origin.w >> 3) + kBias));
  std::sort(leaves.begin(), leaves.end());
  leaves.erase(std::unique(leaves.begin(), leaves.end()), leaves.end());
  if (kind == VdbVolumeKind::Fog) return leaves.size();
  // The cube of radius r leaves is the product of three intervals: dilate one
  // axis at a time (each pass sorted and deduplicated), far cheaper than
  // (2r + 1)^3 offsets per leaf.
  const int64_t r = (std::max(halfWidth, 1) + 7) / 8;
  // Scattered leaves multiply by up to (2r + 1)^3: past maxKeys keys the
  // passes left are bounded instead of enumerated, so counting never costs
  // more than about 16 bytes a key.
  int64_t lo[3] = {INT64_MAX, INT64_MAX, INT64_MAX}, hi[3] = {INT64_MIN, INT64_MIN, INT64_MIN};
  for (uint64_t k : leaves)
    for (int a = 0; a < 3; ++a) {
      const int64_t c = int64_t(k >> (42 - 21 * a)) & ((int64_t(1) << 21) - 1);
      lo[a] = std::min(lo[a], c);
      hi[a] = std::max(hi[a], c);
    }
  int passesLeft = 3;
  for (int shift : {42, 21, 0}) {
    if (leaves.size() * size_t(2 * r + 1) > maxKeys) {
      double bound = double(leaves.size()), box = 1;
      for (int i = 0; i < passesLeft; ++i) bound *= double(2 * r + 1);
      for (int a = 0; a < 3; ++a) box *= double(hi[a] - lo[a] + 1 + 2 * r);
      return uint64_t(std::min(bound, box));
    }
    --passesLeft;
    std::vector<uint64_t> next;
    next.reserve(leaves.size() * size_t(2 * r + 1));
    for (uint64_t k : leaves)
      for (int64_t d = -r; d <= r; ++d) next.push_back(uint64_t(int64_t(k) + d * (int64_t(1) << shift)));
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end()), next.end());
    leaves.swap(next);
  }
  return leaves.size();
}

double vdbVolumeWorkBytes(uint64_t leafCount, VdbVolumeKind kind) {
  const double floatLeaf = double(vdbLeafBytes("Tree_float_5_4_3"));
  return double(leafCount) * (kind == VdbVolumeKind::Fog ? floatLeaf : kLevelSetBytesPerFloatLeaf * floatLeaf);
}

VdbVolumeResult writeVdbVolume(const ClassVolume& volume, const GridFrame& frame, VdbVolumeKind kind,
                               int halfWidth, const std::string& path) {
  ensureOpenVdbInitialized();
  openvdb::math::Transform::Ptr xf = voxelCentreTransform(frame.voxelSize, frame.origin);
  // Occupancy: a brick is an OpenVDB leaf (8^3 at a multiple of 8).
  openvdb::BoolGrid::Ptr occupancy = openvdb::BoolGrid::create(false);
  occupancy->setTransform(xf);
  for (const ClassVolume::Brick& b : volume.bricks()) {
    auto* leaf = occupancy->tree().touchLeaf(openvdb::Coord(b.origin.u, b.origin.v, b.origin.w));
    for (int i = 0; i < ClassVolume::kBrickVoxels; ++i)
      if (b.classes[size_t(i)]) {
        const Coord3 c = b.at(i);
        leaf->setValueOn(openvdb::Coord(c.u, c.v, c.w), true);
      }
  }
  openvdb::FloatGrid::Ptr out;
  if (kind == VdbVolumeKind::Fog) {
    out = openvdb::FloatGrid::create(0.f);
    out->tree().topologyUnion(occupancy->tree());
    for (auto it = out->tree().beginValueOn(); it; ++it) it.setValue(1.f);
    out->setGridClass(openvdb::GRID_FOG_VOLUME);
    out->setName("density");
  } else {
    // topologyToLevelSet measures distances with the input's transform.
    out = openvdb::tools::topologyToLevelSet(*occupancy, halfWidth, 0, 0, 0);
    out->setName("surface");
  }
  out->setTransform(xf);
  VdbVolumeResult r;
  r.activeVoxels = out->activeVoxelCount();
  if (r.activeVoxels) {
    const openvdb::CoordBBox bb = out->evalActiveVoxelBoundingBox();
    r.activeBox = {{bb.min().x(), bb.min().y(), bb.min().z()}, {bb.max().x(), bb.max().y(), bb.max().z()}};
  }
  int writeErrno = 0;  // the stream hides it; a failed write leaves it in errno
  try {
    openvdb::io::File file(path);
    errno = 0;
    file.write({out});
    file.close();
    writeErrno = errno;
  } catch (const std::exception& e) {
    throwIo(outputName(path) + ": cannot write: " + e.what());
  }
  // OpenVDB's std::ofstream failures go unchecked: a full disk or a file size
  // limit leaves a truncated file and no error. Its framing must end in the file.
  try {
    checkVdbStructure(path, VdbCheck::Framing);
  } catch (const Error&) {
    const bool known = writeErrno == ENOSPC || writeErrno == EFBIG || writeErrno == EDQUOT || writeErrno == EIO;
    throwIo(outputName(path) + ": the volume was not written completely (the file on disk ends early: " +
            (known ? std::string(std::strerror(writeErrno)) : std::string("is the disk full?")) + ")");
  }
  stampVdbContentUuid(path, outputName(path));  // OpenVDB's is random: the same volume, the same bytes
  r.bytes = uint64_t(fileSizeOrMinusOne(path));
  return r;
}

}  // namespace vox
