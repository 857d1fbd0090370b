#include "formats/export/vdb_volume_writer.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/TopologyToLevelSet.h>

#include "formats/core/file_util.h"
#include "libvox/core/error.h"
#include "libvox/scene/scene_grids.h"

namespace vox {

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
  try {
    openvdb::io::File file(path);
    file.write({out});
    file.close();
  } catch (const openvdb::Exception& e) {
    throwIo(path + ": cannot write: " + e.what());
  }
  r.bytes = uint64_t(fileSizeOrMinusOne(path));
  return r;
}

}  // namespace vox
