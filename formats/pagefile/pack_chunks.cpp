#include "formats/pagefile/pack_chunks.h"

#include <algorithm>
#include <bit>
#include <exception>

#include "formats/pagefile/layouts.h"
#include "formats/pagefile/pagefile_meta.h"
#include "formats/vdb/vdb_scene_leaves.h"
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

// The file header from the base level's header and the channels of all levels.
pagefile::Header fileHeader(const SceneHeader& bh, const PackSettings& s, size_t levelCount, bool anyColor,
                            bool anyInterior) {
  pagefile::Header h;
  h.layout = s.layout;
  h.chunkLog2 = uint8_t(std::countr_zero(s.chunkSide));
  h.levelCount = uint8_t(levelCount);
  h.alignLog2 = uint8_t(std::countr_zero(s.alignment));
  h.dims = {bh.dims.x, bh.dims.y, bh.dims.z};
  h.voxelSize = bh.voxelSize;
  h.origin = bh.origin;
  if (anyColor) h.flags |= pagefile::kFlagColor;
  if (anyInterior) h.flags |= pagefile::kFlagSurface;
  return h;
}

pagefile::Header fileHeader(const std::vector<const Scene*>& levels, const PackSettings& s) {
  bool anyColor = false, anyInterior = false;
  for (const Scene* l : levels) {
    anyColor = anyColor || l->hasColor();
    for (auto it = l->grids().occupancy->cbeginValueOn(); it && !anyInterior; ++it) anyInterior = !*it;
  }
  return fileHeader(levels[0]->header(), s, levels.size(), anyColor, anyInterior);
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

// A ChunkVoxels for chunks of side `side`, reused chunk after chunk (its
// buffers are sized once per worker).
ChunkVoxels chunkBuffers(uint32_t side, bool withVotes) {
  ChunkVoxels sc;
  const uint32_t N = side * side * side;
  sc.side = side;
  sc.bits.assign(N / 64, 0);
  sc.summary.resize(N);
  sc.color.resize(N);
  sc.surface.resize(N);
  sc.withVotes = withVotes;
  if (withVotes) {
    sc.voteBegin.resize(N);
    sc.voteEnd.resize(N);
    sc.linear.resize(N);
  }
  return sc;
}

// Occupied voxel k (chunk-local index) of `sc`: its votes (sorted by class),
// surface flag and linear colour (nullptr: none).
void putVoxel(ChunkVoxels& sc, uint32_t k, bool surface, std::span<const ClassVotes> votes, const float* color) {
  sc.bits[k >> 6] |= uint64_t(1) << (k & 63);
  ++sc.count;
  const SummaryTexel t = summarize(votes);
  sc.summary[k] = {t.cls, t.conf, t.obs, t.mrg};
  sc.surface[k] = surface ? 1 : 0;
  if (sc.withVotes) {
    sc.voteBegin[k] = uint32_t(sc.votes.size());
    sc.votes.insert(sc.votes.end(), votes.begin(), votes.end());
    sc.voteEnd[k] = uint32_t(sc.votes.size());
  }
  if (color) {
    sc.color[k] = {linearToSrgb8(color[0]), linearToSrgb8(color[1]), linearToSrgb8(color[2]), 255};
    if (sc.withVotes) sc.linear[k] = {color[0], color[1], color[2]};
  } else {
    sc.color[k] = {0, 0, 0, 0};
  }
}

// Starts a chunk in `sc`: no voxel.
void clearChunk(ChunkVoxels& sc) {
  std::fill(sc.bits.begin(), sc.bits.end(), 0);
  sc.votes.clear();
  sc.count = 0;
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

namespace {

// The chunks with Morton keys `keys` (ascending) of one level, encoded.
// Workers take contiguous ranges of chunks; each chunk's payload lands in its
// own slot, so the result does not depend on the thread count. A layout's
// refusal is reported for the first chunk in order. `makeGatherer()` gives a
// worker's gatherer, whose gather(ci, chunk coordinates) returns chunk ci's voxels.
template <typename MakeGatherer>
std::vector<pagefile::ChunkBlob> encodeChunks(const std::vector<uint64_t>& keys, int level, const pagefile::Header& h,
                                              unsigned threads, const MakeGatherer& makeGatherer) {
  const pagefile::LayoutCodec& codec = pagefile::codecOf(h.layout);
  const uint32_t N = h.chunkVoxels();
  std::vector<pagefile::ChunkBlob> out(keys.size());
  std::vector<std::exception_ptr> errors(keys.size());
  parallelPieces(keys.size(), threads, 0, [&](size_t begin, size_t end, size_t) {
    auto gatherer = makeGatherer();
    for (size_t ci = begin; ci < end; ++ci) {
      const auto cc = mortonDecode(keys[ci]);
      const ChunkVoxels& sc = gatherer.gather(ci, cc);
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

namespace {

// The page file's metadata but its levels, from the base level's header.
pagefile::PageMeta packMeta(const SceneHeader& bh, const PackSettings& s) {
  pagefile::PageMeta meta;
  meta.toolVersion = kToolVersion;
  meta.classes = bh.classes;
  meta.sources = bh.sources;
  meta.mipOccupancy = s.mipOccupancy;
  meta.blockWorld = bh.blockWorld;
  meta.region = bh.region;
  return meta;
}

// Level `li` (header `sh`, chunks `levelBlobs`) added to the file's blobs, the
// result's counts and the metadata.
void addLevel(size_t li, const SceneHeader& sh, const pagefile::Header& h, std::vector<pagefile::ChunkBlob> levelBlobs,
              std::vector<pagefile::ChunkBlob>& blobs, PackResult& result, pagefile::PageMeta& meta) {
  const auto expectDims = h.levelDims(int(li));
  if (sh.dims.x != expectDims[0] || sh.dims.y != expectDims[1] || sh.dims.z != expectDims[2])
    throw Error(ErrorKind::Internal, "packChunks: level " + std::to_string(li) + " has the wrong dims");
  PackResult::Level lv;
  lv.level = int(li);
  for (pagefile::ChunkBlob& b : levelBlobs) {
    ++lv.chunks;
    lv.fullChunks += b.full ? 1 : 0;
    lv.voxels += b.occupied;
    lv.payloadBytes += b.bytes.size();
    blobs.push_back(std::move(b));
  }
  result.levels.push_back(lv);
  meta.levels.push_back({uint32_t(li), {sh.dims.x, sh.dims.y, sh.dims.z}, sh.voxelSize, lv.chunks, lv.voxels});
}

// Reads one chunk of a scene's leaves (SceneLeaves) into a ChunkVoxels reused
// chunk after chunk. Chunk ci is the occupancy leaves order[start[ci]] ..
// order[start[ci + 1] - 1], in the order ChunkGatherer visits them.
class LeavesGatherer {
 public:
  LeavesGatherer(const SceneLeaves& scene, const std::vector<uint32_t>& order, const std::vector<size_t>& start,
                 uint32_t side, bool withVotes)
      : s_(scene), order_(order), start_(start), sc_(chunkBuffers(side, withVotes)), voteLeaves_(scene.votes.size()),
        voteRank_(scene.votes.size()) {}

  const ChunkVoxels& gather(size_t ci, const std::array<uint32_t, 3>& chunk) {
    clearChunk(sc_);
    for (size_t j = start_[ci]; j < start_[ci + 1]; ++j) gatherLeaf(order_[j], chunk);
    return sc_;
  }

 private:
  // Occupancy leaf i. The vote and colour masks are subsets of the occupancy
  // mask (readSceneLeaves checks it), so walking the occupied voxels in
  // ascending order walks each grid's values in order.
  void gatherLeaf(uint32_t i, const std::array<uint32_t, 3>& chunk) {
    const OccupancyLeaf& o = s_.occupancy[i];
    const uint32_t C = sc_.side;
    const uint32_t lx = uint32_t(o.origin[0]) - chunk[0] * C, ly = uint32_t(o.origin[1]) - chunk[1] * C,
                   lz = uint32_t(o.origin[2]) - chunk[2] * C;
    const size_t nClasses = s_.votes.size();
    for (size_t q = 0; q < nClasses; ++q) {
      const uint32_t at = s_.votes[q].at[i];
      voteLeaves_[q] = at == SceneLeaves::kNoLeaf ? nullptr : &s_.votes[q].leaves[at];
      voteRank_[q] = 0;
    }
    const SceneLeaf<std::array<float, 3>>* col = nullptr;
    if (s_.hasColor && s_.colorAt[i] != SceneLeaves::kNoLeaf) col = &s_.colorLeaves[s_.colorAt[i]];
    size_t colRank = 0;
    for (uint32_t w = 0; w < 8; ++w)
      for (uint64_t bits = o.mask[w]; bits; bits &= bits - 1) {
        const uint32_t b = uint32_t(std::countr_zero(bits)), off = w * 64 + b;  // x-major within the leaf
        const uint32_t x = lx + (off >> 6), y = ly + ((off >> 3) & 7), z = lz + (off & 7);
        votes_.clear();
        for (size_t q = 0; q < nClasses; ++q)
          if (voteLeaves_[q] && (voteLeaves_[q]->mask[w] >> b & 1))
            votes_.push_back({s_.votes[q].classId, uint32_t(voteLeaves_[q]->values[voteRank_[q]++])});
        const float* color = nullptr;
        if (col && (col->mask[w] >> b & 1)) color = col->values[colRank++].data();
        putVoxel(sc_, x + C * (y + C * z), o.surface[w] >> b & 1, votes_, color);
      }
  }

  const SceneLeaves& s_;
  const std::vector<uint32_t>& order_;
  const std::vector<size_t>& start_;
  ChunkVoxels sc_;
  std::vector<ClassVotes> votes_;
  std::vector<const SceneLeaf<int32_t>*> voteLeaves_;
  std::vector<size_t> voteRank_;
};

}  // namespace

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

PackResult packChunks(const SceneLeaves& scene, const PackSettings& s) {
  checkSettings(s, 1);
  bool anyInterior = false;
  for (const OccupancyLeaf& o : scene.occupancy)
    for (size_t w = 0; w < 8; ++w) anyInterior = anyInterior || (o.mask[w] & ~o.surface[w]);
  const pagefile::Header h = fileHeader(scene.header, s, 1, scene.hasColor, anyInterior);
  pagefile::PageMeta meta = packMeta(scene.header, s);

  // The chunks in Morton order, each its leaves in ChunkGatherer's order (x, then y, then z).
  const uint32_t log2C = h.chunkLog2, L = h.chunkSide() / 8;
  struct Entry {
    uint64_t key;
    uint32_t sub, leaf;
  };
  std::vector<Entry> entries;
  entries.reserve(scene.occupancy.size());
  for (size_t i = 0; i < scene.occupancy.size(); ++i) {
    const OccupancyLeaf& o = scene.occupancy[i];
    uint64_t any = 0;
    for (uint64_t w : o.mask) any |= w;
    if (!any) continue;  // no voxel
    const std::array<uint32_t, 3> at{uint32_t(o.origin[0]), uint32_t(o.origin[1]), uint32_t(o.origin[2])};
    const uint32_t sub = (((at[0] >> 3) & (L - 1)) * L + ((at[1] >> 3) & (L - 1))) * L + ((at[2] >> 3) & (L - 1));
    entries.push_back({mortonEncode(at[0] >> log2C, at[1] >> log2C, at[2] >> log2C), sub, uint32_t(i)});
  }
  std::sort(entries.begin(), entries.end(),
            [](const Entry& a, const Entry& b) { return a.key != b.key ? a.key < b.key : a.sub < b.sub; });
  std::vector<uint64_t> keys;
  std::vector<size_t> start;
  std::vector<uint32_t> order(entries.size());
  for (size_t j = 0; j < entries.size(); ++j) {
    if (j == 0 || entries[j].key != entries[j - 1].key) {
      keys.push_back(entries[j].key);
      start.push_back(j);
    }
    order[j] = entries[j].leaf;
  }
  start.push_back(entries.size());

  const bool withVotes = pagefile::codecOf(h.layout).encoderNeedsVotes;
  PackResult result;
  std::vector<pagefile::ChunkBlob> blobs;
  addLevel(0, scene.header, h,
           encodeChunks(keys, 0, h, s.threads,
                        [&] { return LeavesGatherer(scene, order, start, h.chunkSide(), withVotes); }),
           blobs, result, meta);
  result.bytes = pagefile::serialize(h, pagefile::writePageMeta(meta), blobs);
  return result;
}

}  // namespace vox
