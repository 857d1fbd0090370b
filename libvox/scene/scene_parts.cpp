#include "libvox/scene/scene_parts.h"

#include "libvox/core/error.h"
#include "libvox/core/regions.h"

namespace vox {

namespace {

bool inside(const IndexBox& b, Coord3 c) {
  return c.u >= b.min.u && c.u <= b.max.u && c.v >= b.min.v && c.v <= b.max.v && c.w >= b.min.w && c.w <= b.max.w;
}

void addVoxel(const VoxelView& v, VoxelBlocks& out) {
  for (const ClassVotes& cv : v.votes) out.addVotes(v.at, cv.classId, cv.votes, v.surface);
  if (v.color) out.setColor(v.at, *v.color);
}

std::string partName(const std::vector<std::string>& names, size_t i) {
  return i < names.size() ? names[i] : "part " + std::to_string(i);
}

}  // namespace

VoxelBlocks sceneBlocks(const Scene& scene, const IndexBox* box) {
  VoxelBlocks out;
  scene.forEachVoxel([&](const VoxelView& v) {
    if (!box || inside(*box, v.at)) addVoxel(v, out);
  });
  return out;
}

Scene cropScene(const Scene& scene, const IndexBox& box) {
  return SceneBuilder(sceneBlocks(scene, &box), scene.header()).build();
}

void addPartBlocks(const Scene& part, const std::string& name, VoxelBlocks& into) {
  const SceneHeader& h = part.header();
  if (!h.region)
    throwBadInput(name + ": not a part of a region bake (no region record); merge the files that vox voxelize "
                         "--region wrote");
  if (h.mipLevel != 0)
    throwBadInput(name + ": a pyramid (mip level " + std::to_string(h.mipLevel) +
                  "); vox merge joins level-0 parts: merge them, then run vox mip on the world");
  const IndexBox box = h.region->box;
  bool outside = false;
  Coord3 where{};
  part.forEachVoxel([&](const VoxelView& v) {
    if (inside(box, v.at)) addVoxel(v, into);
    else if (!outside) outside = true, where = v.at;
  });
  if (outside)
    throwBadInput(name + ": voxel " + toString(where) + " lies outside the part's region box; the file is not a part "
                         "as vox voxelize --region writes it");
}

SceneHeader mergedHeader(const std::vector<SceneHeader>& headers, const std::vector<std::string>& names) {
  if (headers.empty()) throw Error(ErrorKind::Usage, "no parts to merge");
  std::vector<RegionPart> parts;
  for (size_t i = 0; i < headers.size(); ++i) parts.push_back({partName(names, i), &headers[i]});
  for (size_t i = 0; i < headers.size(); ++i)
    if (headers[i].region && headers[i].mipLevel != 0)
      throwBadInput(partName(names, i) + ": a pyramid (mip level " + std::to_string(headers[i].mipLevel) +
                    "); vox merge joins level-0 parts: merge them, then run vox mip on the world");
  checkRegionParts(parts);
  SceneHeader world = headers[0];
  world.region.reset();
  return world;
}

Scene mergeSceneParts(std::vector<Scene>&& parts, const std::vector<std::string>& names) {
  std::vector<SceneHeader> headers;
  for (const Scene& p : parts) headers.push_back(p.header());
  SceneHeader world = mergedHeader(headers, names);
  VoxelBlocks blocks;
  for (size_t i = 0; i < parts.size(); ++i) {
    addPartBlocks(parts[i], partName(names, i), blocks);
    parts[i] = Scene();  // release as we go
  }
  return SceneBuilder(std::move(blocks), std::move(world)).build();
}

}  // namespace vox
