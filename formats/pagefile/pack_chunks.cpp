#include "formats/pagefile/pack_chunks.h"

#include <algorithm>
#include <bit>
#include <exception>

#include "formats/pagefile/layouts.h"
#include "formats/pagefile/pack_common.h"
#include "formats/pagefile/pagefile_meta.h"
#include "libvox/core/color.h"
#include "libvox/core/error.h"
#include "libvox/core/morton.h"
#include "libvox/core/parallel.h"
#include "libvox/core/summary_bytes.h"
#include "libvox/core/version.h"
#include "libvox/scene/mip.h"
#include "libvox/scene/scene_grids.h"

namespace vox {

namespace {

using namespace packing;

using BoolLeaf = openvdb::BoolTree::LeafNodeType;
using IntLeaf = openvdb::Int32Tree::LeafNodeType;
using ColorLeaf = openvdb::Vec3STree::LeafNodeType;
using pagefile::ChunkVoxels;

pagefile::Header fileHeader(const std::vector<const Scene*>& levels, const PackSettings& s) {
  bool anyColor = false, anyInterior = false;
  for (const Scene* l : levels) {
    anyColor = anyColor || l->hasColor();
    for (auto it = l->grids().occupancy->cbeginValueOn(); it && !anyInterior; ++it) anyInterior = !*it;
  }
  return packing::fileHeader(levels[0]->header(), s, levels.size(), anyColor, anyInterior);
}

// Non-empty chunks of a level, as sorted Morton keys of their chunk coordinates.
std::vector<uint64_t> chunkKeys(const SceneGrids& g, uint32_t log2C) {
  std::vector<uint64_t> keys;
  for (auto leaf = g.occupancy->tree().cbeginLeaf(); leaf; ++leaf) {
    const openvdb::Coord o = leaf->origin();
    keys.push_back(mortonEncode(uint32_t(o.x()) >> log2C, uint32_t(o.y()) >> log2C, uint32_t(o.z()) >> log2C));
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

// Reads one chunk of a scene into a ChunkVoxels that is reused chunk after chunk.
class ChunkGatherer {
 public:
  ChunkGatherer(const SceneGrids& g, uint32_t side, bool withVotes)
      : g_(g), sc_(chunkBuffers(side, withVotes)), voteLeaves_(g.votes.size()) {}

  // The voxels of the chunk at chunk coordinates `chunk`, leaf by leaf (the
  // 8^3 leaves of the scene's trees).
  const ChunkVoxels& gather(const std::array<uint32_t, 3>& chunk) {
    const uint32_t C = sc_.side, leavesPerAxis = C / 8;
    clearChunk(sc_);
    for (uint32_t a = 0; a < leavesPerAxis; ++a)
      for (uint32_t b = 0; b < leavesPerAxis; ++b)
        for (uint32_t c = 0; c < leavesPerAxis; ++c) {
          const std::array<uint32_t, 3> leafChunkLocal{8 * a, 8 * b, 8 * c};
          const openvdb::Coord leafIndex(int(chunk[0] * C + leafChunkLocal[0]), int(chunk[1] * C + leafChunkLocal[1]),
                                         int(chunk[2] * C + leafChunkLocal[2]));
          gatherLeaf(leafIndex, leafChunkLocal);
        }
    return sc_;
  }

 private:
  // One 8^3 leaf whose first voxel is `leafIndex` in the scene's index space
  // and `leafChunkLocal` in the chunk.
  void gatherLeaf(const openvdb::Coord& leafIndex, const std::array<uint32_t, 3>& leafChunkLocal) {
    const BoolLeaf* occ = g_.occupancy->tree().probeConstLeaf(leafIndex);
    if (!occ) return;
    const size_t nClasses = g_.votes.size();
    for (size_t k = 0; k < nClasses; ++k) voteLeaves_[k] = g_.votes[k].grid->tree().probeConstLeaf(leafIndex);
    const ColorLeaf* col = g_.color ? g_.color->tree().probeConstLeaf(leafIndex) : nullptr;
    const uint32_t C = sc_.side;
    for (auto it = occ->cbeginValueOn(); it; ++it) {
      const openvdb::Index off = it.pos();  // x-major within the leaf (OpenVDB's order)
      const uint32_t x = leafChunkLocal[0] + (off >> 6), y = leafChunkLocal[1] + ((off >> 3) & 7), z = leafChunkLocal[2] + (off & 7);
      votes_.clear();
      for (size_t q = 0; q < nClasses; ++q)
        if (voteLeaves_[q] && voteLeaves_[q]->isValueOn(off))
          votes_.push_back({g_.votes[q].classId, uint32_t(voteLeaves_[q]->getValue(off))});
      const float* color = col && col->isValueOn(off) ? col->getValue(off).asPointer() : nullptr;
      putVoxel(sc_, x + C * (y + C * z), *it, votes_, color);
    }
  }

  const SceneGrids& g_;
  ChunkVoxels sc_;
  std::vector<ClassVotes> votes_;
  std::vector<const IntLeaf*> voteLeaves_;
};

}  // namespace

std::vector<pagefile::ChunkBlob> packLevel(const Scene& scene, int level, const pagefile::Header& h, unsigned threads) {
  const bool withVotes = pagefile::codecOf(h.layout).encoderNeedsVotes;
  const SceneGrids& g = scene.grids();
  struct Gatherer {
    ChunkGatherer g;
    const ChunkVoxels& gather(size_t, const std::array<uint32_t, 3>& cc) { return g.gather(cc); }
  };
  return encodeChunks(chunkKeys(g, h.chunkLog2), level, h, threads,
                      [&] { return Gatherer{ChunkGatherer(g, h.chunkSide(), withVotes)}; });
}

namespace {

// A region part's record for a merge: the settings, and the seam level's voxels
// in full when the part has that level.
pagefile::RegionMips regionMips(const std::vector<const Scene*>& levels, const PackSettings& s) {
  pagefile::RegionMips r;
  r.levelsAsked = s.mipLevelsAsked;
  if (levels.size() <= pagefile::kRegionSeamLevel) return r;
  r.seamLevel = pagefile::kRegionSeamLevel;
  levels[r.seamLevel]->forEachVoxel([&](const VoxelView& v) {
    pagefile::SeamVoxel sv;
    sv.at = {uint32_t(v.at.u), uint32_t(v.at.v), uint32_t(v.at.w)};
    sv.surface = v.surface;
    sv.votes.assign(v.votes.begin(), v.votes.end());
    if (v.color) sv.color = std::array<float, 3>{v.color->r, v.color->g, v.color->b};
    r.voxels.push_back(std::move(sv));
  });
  return r;
}

}  // namespace

int mipLevelsToBuild(const SceneHeader& header, int asked) {
  const int reachable = maxMipLevels(header.dims);
  if (!header.region || asked > reachable) return asked;
  const int seam = std::min<int>(int(pagefile::kRegionSeamLevel), reachable);
  return asked ? std::min(asked, seam) : seam;
}

pagefile::Header packHeader(const std::vector<const Scene*>& levels, const PackSettings& s) {
  checkSettings(s, levels.size());
  return fileHeader(levels, s);
}

PackResult packChunks(const std::vector<const Scene*>& levels, const PackSettings& s) {
  const pagefile::Header h = packHeader(levels, s);
  const SceneHeader& bh = levels[0]->header();
  pagefile::PageMeta meta = packMeta(bh, s);
  if (bh.region && levels.size() > 1) meta.regionMips = regionMips(levels, s);
  PackResult result;
  std::vector<pagefile::ChunkBlob> blobs;
  for (size_t li = 0; li < levels.size(); ++li)
    addLevel(li, levels[li]->header(), h, packLevel(*levels[li], int(li), h, s.threads), blobs, result, meta);
  result.bytes = pagefile::serialize(h, pagefile::writePageMeta(meta), blobs);
  return result;
}


}  // namespace vox
