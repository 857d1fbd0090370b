// packChunks of scene leaves, and what both packers share (pack_common.h).
// No OpenVDB here: the light pack module links this file (docs/startup.md).
#include <algorithm>
#include <bit>

#include "formats/pagefile/pack_common.h"
#include "formats/vdb/vdb_scene_leaves.h"
#include "libvox/core/color.h"
#include "libvox/core/error.h"
#include "libvox/core/summary_bytes.h"
#include "libvox/core/version.h"

namespace vox {

namespace packing {

using pagefile::ChunkVoxels;

void checkSettings(const PackSettings& s, size_t levelCount) {
  if (s.chunkSide < (1u << pagefile::kMinChunkLog2) || s.chunkSide > (1u << pagefile::kMaxChunkLog2) ||
      !std::has_single_bit(s.chunkSide))
    throwUsage("chunk side " + std::to_string(s.chunkSide) + ": expected 8, 16 or 32", Setting::ChunkSide);
  if (s.alignment != 0 && (s.alignment < (1u << pagefile::kMinAlignLog2) ||
                           s.alignment > (1u << pagefile::kMaxAlignLog2) || !std::has_single_bit(s.alignment)))
    throwUsage("payload alignment " + std::to_string(s.alignment) + ": expected auto or a power of two from 8 to 65536",
               Setting::PageAlignment);
  if (!pagefile::findLayout(uint8_t(s.layout)))
    throwUsage("layout " + std::to_string(int(s.layout)) + ": expected " + pagefile::layoutNameList(), Setting::PageLayout);
  if (levelCount == 0 || levelCount > 255) throw Error(ErrorKind::Internal, "packChunks: 1..255 levels");
}

pagefile::Header fileHeader(const SceneHeader& bh, const PackSettings& s, size_t levelCount, bool anyColor,
                            bool anyInterior) {
  if (const std::string problem = pageFileDimsProblem(bh.dims); !problem.empty()) throwBadInput(problem);
  pagefile::Header h;
  h.layout = s.layout;
  h.chunkLog2 = uint8_t(std::countr_zero(s.chunkSide));
  h.levelCount = uint8_t(levelCount);
  h.alignLog2 = s.alignment ? uint8_t(std::countr_zero(s.alignment)) : pagefile::kAlignAuto;
  h.dims = {bh.dims.x, bh.dims.y, bh.dims.z};
  h.voxelSize = bh.voxelSize;
  h.origin = bh.origin;
  if (anyColor) h.flags |= pagefile::kFlagColor;
  if (anyInterior) h.flags |= pagefile::kFlagSurface;
  return h;
}


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

void clearChunk(ChunkVoxels& sc) {
  std::fill(sc.bits.begin(), sc.bits.end(), 0);
  sc.votes.clear();
  sc.count = 0;
}

pagefile::PageMeta packMeta(const SceneHeader& bh, const PackSettings& s) {
  pagefile::PageMeta meta;
  meta.toolVersion = kToolVersion;
  meta.classes = bh.classes;
  meta.sources = bh.sources;
  meta.mipOccupancy = s.mipOccupancy;
  meta.blockWorld = bh.blockWorld;
  meta.region = bh.region;
  if (bh.region) meta.regionAlign = s.alignment;
  return meta;
}

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


}  // namespace packing

namespace {

using namespace packing;
using pagefile::ChunkVoxels;

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

std::string pageFileDimsProblem(const Dims& dims) {
  const uint32_t d[3] = {dims.x, dims.y, dims.z};
  for (int a = 0; a < 3; ++a)
    if (d[a] > pagefile::kMaxDim)
      return "the scene is " + std::to_string(d[a]) + " voxels along " + "xyz"[a] + " (dims " + std::to_string(d[0]) +
             " x " + std::to_string(d[1]) + " x " + std::to_string(d[2]) + ") and a page file holds at most " +
             std::to_string(pagefile::kMaxDim) + " (2^20) per axis: pack a scene at most that wide (a block map's " +
             "positions along " + "xyz"[a] + " below " + std::to_string(pagefile::kMaxDim) +
             "; split a wider map, as region bakes keep the world's dims)";
  return {};
}

PlannedPack packChunks(const SceneLeaves& scene, const PackSettings& s) {
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
  PackResult counts;
  PlannedPack out;
  addLevel(0, scene.header, h,
           encodeChunks(keys, 0, h, s.threads,
                        [&] { return LeavesGatherer(scene, order, start, h.chunkSide(), withVotes); }),
           out.chunks, counts, meta);
  out.levels = std::move(counts.levels);
  out.plan = pagefile::planChunks(h, pagefile::writePageMeta(meta), out.chunks);
  return out;
}


}  // namespace vox
