#include "libvox/scene/voxelize_sdf.h"

#include <openvdb/tools/LevelSetUtil.h>
#include <openvdb/tools/MeshToVolume.h>

#include <cmath>

#include "libvox/core/error.h"
#include "libvox/scene/scene_grids.h"

namespace vox {

namespace {

/// Our mesh as OpenVDB's MeshDataAdapter, in OpenVDB index space (voxel centres
/// at integers: index = (world - origin) / voxelSize - 0.5).
struct Adapter {
  const Mesh& mesh;
  const SceneHeader& h;
  size_t polygonCount() const { return mesh.triangles.size(); }
  size_t pointCount() const { return mesh.positions.size(); }
  size_t vertexCount(size_t) const { return 3; }
  void getIndexSpacePoint(size_t n, size_t v, openvdb::Vec3d& pos) const {
    const auto& p = mesh.positions[mesh.triangles[n][v]];
    pos = openvdb::Vec3d((p[0] - h.origin[0]) / h.voxelSize - 0.5, (p[1] - h.origin[1]) / h.voxelSize - 0.5,
                         (p[2] - h.origin[2]) / h.voxelSize - 0.5);
  }
};

}  // namespace

Scene voxelizeMeshSdf(const Mesh& mesh, const std::vector<uint8_t>& triangleClass, const SceneHeader& header,
                      const VoxelizeSettings& settings) {
  ensureOpenVdbInitialized();
  SceneBuilder builder(header);
  if (mesh.triangles.empty()) return std::move(builder).build();
  for (const auto& p : mesh.positions)
    for (double c : p)
      if (!std::isfinite(c))
        throwBadInput("a vertex has a non-finite coordinate; drop the triangles that touch it", Setting::DropInvalid);
  openvdb::math::Transform::Ptr xform = voxelCentreTransform(header.voxelSize, header.origin);
  openvdb::Int32Grid closest(0);
  const Adapter adapter{mesh, header};
  openvdb::FloatGrid::Ptr sdf = openvdb::tools::meshToVolume<openvdb::FloatGrid>(adapter, *xform, 2.0f, 2.0f, 0, &closest);
  if (settings.progress) settings.progress(0.6);
  const float halfDiagonal = float(std::sqrt(3.0) / 2.0 * header.voxelSize);
  const Dims d = header.dims;
  auto inDomain = [&](const openvdb::Coord& c) {
    return c.x() >= 0 && c.y() >= 0 && c.z() >= 0 && uint32_t(c.x()) < d.x && uint32_t(c.y()) < d.y && uint32_t(c.z()) < d.z;
  };
  auto classAt = [&](const openvdb::Coord& c, openvdb::Int32Grid::ConstAccessor& acc) -> uint8_t {
    const int32_t i = acc.getValue(c);
    return i >= 0 && size_t(i) < triangleClass.size() ? triangleClass[size_t(i)] : triangleClass[0];
  };
  auto acc = closest.getConstAccessor();
  for (auto it = sdf->cbeginValueOn(); it; ++it) {
    if (std::abs(*it) > halfDiagonal || !it.isVoxelValue() || !inDomain(it.getCoord())) continue;
    const openvdb::Coord c = it.getCoord();
    builder.addVotes({c.x(), c.y(), c.z()}, classAt(c, acc), kInteriorVotes, true);
  }
  if (settings.fill == FillMode::Solid) {
    // Interior: OpenVDB's inside mask (value < 0, tiles included); the class of
    // the nearest band voxel's closest triangle is not known deep inside, so
    // interior voxels take the class of the closest triangle of the nearest
    // band voxel along -z, or the first triangle's.
    openvdb::BoolGrid::Ptr inside = openvdb::tools::sdfInteriorMask(*sdf);
    for (auto it = inside->cbeginValueOn(); it; ++it) {
      openvdb::CoordBBox box;
      it.getBoundingBox(box);
      for (auto ci = box.begin(); ci; ++ci) {
        const openvdb::Coord c = *ci;
        if (!inDomain(c)) continue;
        float v = 0;
        if (sdf->tree().probeValue(c, v) && std::abs(v) <= halfDiagonal) continue;  // already surface
        openvdb::Coord below = c;
        uint8_t cls = triangleClass[0];
        for (int k = 0; k < 64 && below.z() > -8; ++k) {
          below.z() -= 1;
          int32_t idx;
          if (acc.probeValue(below, idx)) {
            cls = classAt(below, acc);
            break;
          }
        }
        builder.addVotes({c.x(), c.y(), c.z()}, cls, kInteriorVotes, false);
      }
    }
  }
  if (settings.progress) settings.progress(1.0);
  if (settings.leaveOutClassesWithoutVotes) builder.leaveOutClassesWithoutVotes(*settings.leaveOutClassesWithoutVotes);
  return std::move(builder).build();
}

}  // namespace vox
