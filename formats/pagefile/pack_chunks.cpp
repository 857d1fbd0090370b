#include "formats/pagefile/pack_chunks.h"

#include <algorithm>
#include <bit>
#include <exception>

#include "formats/pagefile/layouts.h"
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

using BoolLeaf = openvdb::BoolTree::LeafNodeType;
using IntLeaf = openvdb::Int32Tree::LeafNodeType;
using ColorLeaf = openvdb::Vec3STree::LeafNodeType;
using pagefile::ChunkVoxels;

void checkSettings(const PackSettings& s, size_t levelCount) {
  if (s.chunkSide < (1u << pagefile::kMinChunkLog2) || s.chunkSide > (1u << pagefile::kMaxChunkLog2) ||
      !std::has_single_bit(s.chunkSide))
    throwUsage("chunk side " + std::to_string(s.chunkSide) + ": expected 8, 16 or 32", Setting::ChunkSide);
  if (s.alignment < (1u << pagefile::kMinAlignLog2) || s.alignment > (1u << pagefile::kMaxAlignLog2) ||
      !std::has_single_bit(s.alignment))
    throwUsage("payload alignment " + std::to_string(s.alignment) + ": expected a power of two from 8 to 65536",
               Setting::PageAlignment);
  if (!pagefile::findLayout(uint8_t(s.layout)))
    throwUsage("layout " + std::to_string(int(s.layout)) + ": expected " + pagefile::layoutNameList(), Setting::PageLayout);
  if (levelCount == 0 || levelCount > 255) throw Error(ErrorKind::Internal, "packChunks: 1..255 levels");
}

// The file header from the base level; channel flags from every level.
pagefile::Header fileHeader(const std::vector<const Scene*>& levels, const PackSettings& s) {
  const SceneHeader& bh = levels[0]->header();
  pagefile::Header h;
  h.layout = s.layout;
  h.chunkLog2 = uint8_t(std::countr_zero(s.chunkSide));
  h.levelCount = uint8_t(levels.size());
  h.alignLog2 = uint8_t(std::countr_zero(s.alignment));
  h.dims = {bh.dims.x, bh.dims.y, bh.dims.z};
  h.voxelSize = bh.voxelSize;
  h.origin = bh.origin;
  bool anyInterior = false;
  for (const Scene* l : levels) {
    if (l->hasColor()) h.flags |= pagefile::kFlagColor;
    for (auto it = l->grids().occupancy->cbeginValueOn(); it && !anyInterior; ++it) anyInterior = !*it;
  }
  if (anyInterior) h.flags |= pagefile::kFlagSurface;
  return h;
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

// Reads one chunk of a scene into a ChunkVoxels that is reused chunk after
// chunk (its buffers are sized once per worker).
class ChunkGatherer {
 public:
  ChunkGatherer(const SceneGrids& g, uint32_t side, bool withVotes) : g_(g), voteLeaves_(g.votes.size()) {
    const uint32_t N = side * side * side;
    sc_.side = side;
    sc_.bits.assign(N / 64, 0);
    sc_.summary.resize(N);
    sc_.color.resize(N);
    sc_.surface.resize(N);
    sc_.withVotes = withVotes;
    if (withVotes) {
      sc_.voteBegin.resize(N);
      sc_.voteEnd.resize(N);
      sc_.linear.resize(N);
    }
  }

  // The voxels of the chunk at chunk coordinates `chunk`, leaf by leaf (the
  // 8^3 leaves of the scene's trees).
  const ChunkVoxels& gather(const std::array<uint32_t, 3>& chunk) {
    const uint32_t C = sc_.side, leavesPerAxis = C / 8;
    std::fill(sc_.bits.begin(), sc_.bits.end(), 0);
    sc_.votes.clear();
    sc_.count = 0;
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
      const uint32_t k = x + C * (y + C * z);  // chunk-local index
      sc_.bits[k >> 6] |= uint64_t(1) << (k & 63);
      ++sc_.count;
      votes_.clear();
      for (size_t q = 0; q < nClasses; ++q)
        if (voteLeaves_[q] && voteLeaves_[q]->isValueOn(off))
          votes_.push_back({g_.votes[q].classId, uint32_t(voteLeaves_[q]->getValue(off))});
      const SummaryTexel t = summarize(votes_);
      sc_.summary[k] = {t.cls, t.conf, t.obs, t.mrg};
      sc_.surface[k] = *it ? 1 : 0;
      if (sc_.withVotes) {
        sc_.voteBegin[k] = uint32_t(sc_.votes.size());
        sc_.votes.insert(sc_.votes.end(), votes_.begin(), votes_.end());
        sc_.voteEnd[k] = uint32_t(sc_.votes.size());
      }
      if (col && col->isValueOn(off)) {
        const openvdb::Vec3s& v = col->getValue(off);
        sc_.color[k] = {linearToSrgb8(v[0]), linearToSrgb8(v[1]), linearToSrgb8(v[2]), 255};
        if (sc_.withVotes) sc_.linear[k] = {v[0], v[1], v[2]};
      } else {
        sc_.color[k] = {0, 0, 0, 0};
      }
    }
  }

  const SceneGrids& g_;
  ChunkVoxels sc_;
  std::vector<ClassVotes> votes_;
  std::vector<const IntLeaf*> voteLeaves_;
};

// Every non-empty chunk of one level, encoded, in Morton order. Workers take
// contiguous ranges of chunks; each chunk's payload lands in its own slot, so
// the result does not depend on the thread count. A layout's refusal is
// reported for the first chunk in order.
}  // namespace

std::vector<pagefile::ChunkBlob> packLevel(const Scene& scene, int level, const pagefile::Header& h, unsigned threads) {
  const pagefile::LayoutCodec& codec = pagefile::codecOf(h.layout);
  const SceneGrids& g = scene.grids();
  const std::vector<uint64_t> keys = chunkKeys(g, h.chunkLog2);
  const uint32_t C = h.chunkSide(), N = h.chunkVoxels();
  std::vector<pagefile::ChunkBlob> out(keys.size());
  std::vector<std::exception_ptr> errors(keys.size());
  parallelPieces(keys.size(), threads, 0, [&](size_t begin, size_t end, size_t) {
    ChunkGatherer gatherer(g, C, codec.encoderNeedsVotes);
    for (size_t ci = begin; ci < end; ++ci) {
      const auto cc = mortonDecode(keys[ci]);
      const ChunkVoxels& sc = gatherer.gather(cc);
      pagefile::ChunkBlob& blob = out[ci];
      blob.level = uint8_t(level);
      blob.key = keys[ci];
      blob.occupied = sc.count;
      blob.full = sc.count == N;
      if (sc.count == 0) continue;  // a leaf without active voxels
      try {
        blob.bytes = codec.encode(sc, h.flags, {level, cc});
      } catch (...) {
        errors[ci] = std::current_exception();
      }
    }
  });
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
  std::erase_if(out, [](const pagefile::ChunkBlob& b) { return b.occupied == 0; });  // leaves without active voxels
  return out;
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
  pagefile::PageMeta meta;
  meta.toolVersion = kToolVersion;
  meta.classes = bh.classes;
  meta.sources = bh.sources;
  meta.mipOccupancy = s.mipOccupancy;
  meta.blockWorld = bh.blockWorld;
  meta.region = bh.region;
  if (bh.region && levels.size() > 1) meta.regionMips = regionMips(levels, s);

  PackResult result;
  std::vector<pagefile::ChunkBlob> blobs;
  for (size_t li = 0; li < levels.size(); ++li) {
    const Scene& scene = *levels[li];
    const SceneHeader& sh = scene.header();
    const auto expectDims = h.levelDims(int(li));
    if (sh.dims.x != expectDims[0] || sh.dims.y != expectDims[1] || sh.dims.z != expectDims[2])
      throw Error(ErrorKind::Internal, "packChunks: level " + std::to_string(li) + " has the wrong dims");
    PackResult::Level lv;
    lv.level = int(li);
    for (pagefile::ChunkBlob& b : packLevel(scene, int(li), h, s.threads)) {
      ++lv.chunks;
      lv.fullChunks += b.full ? 1 : 0;
      lv.voxels += b.occupied;
      lv.payloadBytes += b.bytes.size();
      blobs.push_back(std::move(b));
    }
    result.levels.push_back(lv);
    meta.levels.push_back({uint32_t(li), {sh.dims.x, sh.dims.y, sh.dims.z}, sh.voxelSize, lv.chunks, lv.voxels});
  }
  result.bytes = pagefile::serialize(h, pagefile::writePageMeta(meta), blobs);
  return result;
}

}  // namespace vox
