// Meshes and headers shared by the voxelizer's unit tests.
#pragma once

#include <array>
#include <vector>

#include "libvox/core/scene_header.h"
#include "libvox/mesh/mesh.h"

namespace voxtest {

/// A header of `dims` voxels of size `voxelSize` at `origin`, with classes 1 "a" and 2 "b".
inline vox::SceneHeader twoClassHeader(vox::Dims dims, double voxelSize = 1.0, std::array<double, 3> origin = {0, 0, 0}) {
  vox::SceneHeader h;
  h.dims = dims;
  h.voxelSize = voxelSize;
  h.origin = origin;
  h.classes.add({1, "a", {255, 0, 0}, std::nullopt});
  h.classes.add({2, "b", {0, 255, 0}, std::nullopt});
  return h;
}

/// A mesh of these triangles: one material (default), one part.
inline vox::Mesh meshOf(const std::vector<std::array<double, 3>>& pos, const std::vector<std::array<uint32_t, 3>>& tris) {
  vox::Mesh m;
  m.positions = pos;
  m.triangles = tris;
  m.triangleMaterial.assign(tris.size(), 0);
  m.trianglePart.assign(tris.size(), 0);
  m.materials.push_back({});
  m.parts.push_back({"part", "mesh"});
  return m;
}

/// A 2 x 2 nearest-filtered texture with a known colour per texel: top row red,
/// green; bottom row blue, sRGB 188 grey (each texel one voxel of a 2 x 2 square).
inline vox::MeshTexture quadrantTexture() {
  vox::MeshTexture tex;
  tex.width = tex.height = 2;
  tex.nearest = true;
  tex.rgba = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 188, 188, 188, 255};
  return tex;
}

}  // namespace voxtest
