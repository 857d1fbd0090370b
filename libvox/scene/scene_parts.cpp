#include "libvox/scene/scene_parts.h"

#include "libvox/core/error.h"
#include "libvox/core/regions.h"
#include "libvox/scene/scene_grids.h"

namespace vox {

namespace {

bool inside(const IndexBox& b, Coord3 c) {
  return c.u >= b.min.u && c.u <= b.max.u && c.v >= b.min.v && c.v <= b.max.v && c.w >= b.min.w && c.w <= b.max.w;
}

std::string partName(const std::vector<std::string>& names, size_t i) {
  return i < names.size() ? names[i] : "part " + std::to_string(i);
}

/// Bit i set for the voxels of the 8^3 leaf at `origin` inside `box`.
std::array<uint64_t, kBlockWords> leafMaskInside(const openvdb::Coord& origin, const IndexBox& box) {
  std::array<uint64_t, kBlockWords> m{};
  const openvdb::Coord lo = origin, hi = origin.offsetBy(kBlockDim - 1);
  if (lo.x() >= box.min.u && hi.x() <= box.max.u && lo.y() >= box.min.v && hi.y() <= box.max.v &&
      lo.z() >= box.min.w && hi.z() <= box.max.w) {
    m.fill(~uint64_t(0));
    return m;
  }
  for (int i = 0; i < kBlockVoxels; ++i) {
    const Coord3 c{origin.x() + (i >> 6), origin.y() + ((i >> 3) & 7), origin.z() + (i & 7)};
    if (inside(box, c)) m[size_t(i >> 6)] |= uint64_t(1) << (i & 63);
  }
  return m;
}

/// Adds the voxels of `scene` (those inside `box` when given) to `out` leaf by
/// leaf: masks and values copied word for word (OpenVDB's leaves and the
/// blocks share the voxel order), votes summed. Returns the first voxel found
/// outside `box`, if any.
std::optional<Coord3> addLeaves(const Scene& scene, const IndexBox* box, VoxelBlocks& out) {
  const SceneGrids& g = scene.grids();
  std::optional<Coord3> outside;
  for (auto leaf = g.occupancy->tree().cbeginLeaf(); leaf; ++leaf) {
    const openvdb::Coord origin = leaf->origin();
    std::array<uint64_t, kBlockWords> keep;
    keep.fill(~uint64_t(0));
    if (box) keep = leafMaskInside(origin, *box);
    std::array<uint64_t, kBlockWords> occ, surf;
    bool any = false;
    for (int k = 0; k < kBlockWords; ++k) {
      const uint64_t on = leaf->getValueMask().template getWord<openvdb::Index64>(openvdb::Index(k));
      if (!outside && (on & ~keep[size_t(k)])) {
        const int i = k * 64 + __builtin_ctzll(on & ~keep[size_t(k)]);
        outside = Coord3{origin.x() + (i >> 6), origin.y() + ((i >> 3) & 7), origin.z() + (i & 7)};
      }
      occ[size_t(k)] = on & keep[size_t(k)];
      surf[size_t(k)] = leaf->buffer().data()[k] & occ[size_t(k)];
      any = any || occ[size_t(k)];
    }
    if (!any) continue;
    VoxelBlock* b = out.blockAt({origin.x(), origin.y(), origin.z()});
    if (!b) continue;  // beyond any domain; validate() reports it
    for (int k = 0; k < kBlockWords; ++k) b->occupied[size_t(k)] |= occ[size_t(k)], b->surface[size_t(k)] |= surf[size_t(k)];
    for (const ClassGrid& cg : g.votes) {
      const auto* vl = cg.grid->tree().probeConstLeaf(origin);
      if (!vl) continue;
      ClassBlock* cb = nullptr;
      const int32_t* values = vl->buffer().data();
      for (int k = 0; k < kBlockWords; ++k)
        for (uint64_t bits = vl->getValueMask().template getWord<openvdb::Index64>(openvdb::Index(k)) & occ[size_t(k)];
             bits; bits &= bits - 1) {
          const int i = k * 64 + __builtin_ctzll(bits);
          if (!cb) cb = &classBlock(*b, cg.classId);
          cb->add(i, uint32_t(values[i]));
        }
    }
    if (g.color)
      if (const auto* cl = g.color->tree().probeConstLeaf(origin)) {
        const openvdb::Vec3s* values = cl->buffer().data();
        for (int k = 0; k < kBlockWords; ++k)
          for (uint64_t bits = cl->getValueMask().template getWord<openvdb::Index64>(openvdb::Index(k)) & occ[size_t(k)];
               bits; bits &= bits - 1) {
            const int i = k * 64 + __builtin_ctzll(bits);
            setBlockColor(*b, i, {values[i][0], values[i][1], values[i][2]});  // voxel order: appended
          }
      }
  }
  return outside;
}

}  // namespace

VoxelBlocks sceneBlocks(const Scene& scene, const IndexBox* box) {
  VoxelBlocks out;
  addLeaves(scene, box, out);
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
  if (const std::optional<Coord3> where = addLeaves(part, &box, into))
    throwBadInput(name + ": voxel " + toString(*where) + " lies outside the part's region box; the file is not a part "
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
  SceneHeader world = headers[worldHeaderPart(parts)];
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
