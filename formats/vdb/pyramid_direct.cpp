#include "formats/vdb/pyramid_direct.h"

#include "formats/scene/scene_meta.h"
#include "formats/scene/scene_vdb_direct.h"
#include "libvox/core/error.h"
#include "libvox/core/parallel.h"

// No OpenVDB here: the light module (vox-pack.so) links this file.

namespace vox {

std::optional<MipBlocksLevel> mipBlocksFromLeaves(SceneLeaves&& leaves, unsigned threads) {
  if (!leaves.plainForm) return std::nullopt;
  MipBlocksLevel level;
  level.header = std::move(leaves.header);
  level.colorGrid = leaves.hasColor;
  const size_t n = leaves.occupancy.size();
  level.blocks.resize(n);
  const unsigned pieces = std::max(1u, std::min<unsigned>(threads, unsigned(std::max<size_t>(1, n / 64))));
  parallelPieces(n, pieces, pieces, [&](size_t begin, size_t end, size_t) {
    for (size_t i = begin; i < end; ++i) {
      const OccupancyLeaf& o = leaves.occupancy[i];
      auto b = std::make_unique<VoxelBlock>();
      b->origin = o.origin;
      for (int k = 0; k < kBlockWords; ++k) {
        b->occupied[size_t(k)] = o.mask[size_t(k)];
        b->surface[size_t(k)] = o.surface[size_t(k)] & o.mask[size_t(k)];
      }
      for (const SceneLeaves::Votes& v : leaves.votes) {  // by class id
        if (v.at[i] == SceneLeaves::kNoLeaf) continue;
        const SceneLeaf<int32_t>& l = v.leaves[v.at[i]];
        auto cb = std::make_unique<ClassBlock>();
        cb->classId = v.classId;
        cb->voted = l.mask;
        size_t count = 0;
        for (uint64_t w : l.mask) count += size_t(bitCount(w));
        if (count <= ClassBlock::kCompactCounts) {
          uint16_t seen = 0;
          for (int k = 0; k < kBlockWords; ++k) {
            cb->before[size_t(k)] = seen;
            seen = uint16_t(seen + bitCount(l.mask[size_t(k)]));
          }
          cb->counts.assign(l.values.get(), l.values.get() + count);
        } else {
          cb->dense = true;
          cb->counts.assign(kBlockVoxels, 0);
          size_t t = 0;
          for (int k = 0; k < kBlockWords; ++k)
            for (uint64_t bits = l.mask[size_t(k)]; bits; bits &= bits - 1)
              cb->counts[size_t(k * 64 + __builtin_ctzll(bits))] = uint32_t(l.values[t++]);
        }
        b->classes.push_back(std::move(cb));
      }
      if (leaves.hasColor && leaves.colorAt[i] != SceneLeaves::kNoLeaf) {
        const SceneLeaf<std::array<float, 3>>& l = leaves.colorLeaves[leaves.colorAt[i]];
        size_t count = 0;
        for (uint64_t w : l.mask) count += size_t(bitCount(w));
        b->colored = l.mask;
        b->colors.assign(l.values.get(), l.values.get() + count);  // the leaf's active values, in voxel order
      }
      level.blocks[i] = std::move(b);
    }
  });
  leaves = SceneLeaves{};
  return level;
}

namespace {

DirectScenePart partOf(const MipBlocksLevel& level, size_t index) {
  DirectScenePart part;
  part.header = &level.header;
  for (const auto& b : level.blocks) part.blocks.push_back(b.get());
  part.gridPrefix = pyramidGridPrefix(index);
  if (index > 0) part.gridMetadata = pyramidLevelGridMetadata(level.header.mipLevel);
  part.colorGrid = level.colorGrid;
  return part;
}

}  // namespace

void writePyramidVdbDirect(const std::vector<const MipBlocksLevel*>& levels, MipOccupancy occupancy,
                           const std::string& path, unsigned threads) {
  if (levels.empty()) throw Error(ErrorKind::Internal, "writePyramidVdbDirect: no levels");
  std::vector<DirectScenePart> parts;
  for (size_t n = 0; n < levels.size(); ++n) {
    if (levels[n]->header.mipLevel != int(n) + levels[0]->header.mipLevel)
      throw Error(ErrorKind::Internal, "writePyramidVdbDirect: level " + std::to_string(n) + " has mipLevel " +
                                           std::to_string(levels[n]->header.mipLevel));
    parts.push_back(partOf(*levels[n], n));
  }
  writeScenesVdbDirect(
      parts,
      [&](const std::vector<DirectWriteSummary>& s) {
        std::vector<PyramidLevelEntry> table;
        for (size_t n = 1; n < levels.size(); ++n) {
          const SceneHeader& h = levels[n]->header;
          table.push_back({h.mipLevel, h.dims, h.voxelSize, s[n].occupied});
        }
        MetaEntries meta = sceneFileMetadata(levels[0]->header);
        meta[kPyramidKey] = pyramidMetadata(mipOccupancyName(occupancy), table);
        return meta;
      },
      path, threads, "pyramid");
}

void writeMipLevelVdbDirect(const MipBlocksLevel& level, const std::string& path, unsigned threads) {
  writeScenesVdbDirect({partOf(level, 0)}, [&](const std::vector<DirectWriteSummary>&) { return sceneFileMetadata(level.header); },
                       path, threads, "scene");
}

}  // namespace vox
