#include "libvox/scene/mip_blocks.h"

#include <algorithm>
#include <array>

#include "libvox/core/parallel.h"

// No OpenVDB here: the light module (vox-pack.so) links this file.

namespace vox {

Dims mipDims(Dims d, int level) {
  auto f = [level](uint32_t a) { return uint32_t((uint64_t(a) + (uint64_t(1) << level) - 1) >> level); };
  return {f(d.x), f(d.y), f(d.z)};
}

int maxMipLevels(Dims d) {
  int n = 0;
  while (d.maxAxis() > 1) {
    d = mipDims(d, 1);
    ++n;
  }
  return n;
}

SceneHeader coarserMipHeader(const SceneHeader& fine) {
  SceneHeader h = fine;
  h.dims = mipDims(fine.dims, 1);
  h.voxelSize = fine.voxelSize * 2;
  h.mipLevel = fine.mipLevel + 1;
  if (h.region && !h.region->box.empty()) {
    // A region bake's part: the coarse voxels its box's voxels reduce into. Past
    // the tiling's 32-voxel cells, parts share coarse voxels: such levels of a
    // part are partial (docs/scale.md).
    IndexBox& b = h.region->box;
    b.min = {b.min.u >> 1, b.min.v >> 1, b.min.w >> 1};
    b.max = {b.max.u >> 1, b.max.v >> 1, b.max.w >> 1};
  }
  return h;
}

uint64_t MipBlocksLevel::occupiedCount() const {
  uint64_t n = 0;
  for (const auto& b : blocks)
    for (uint64_t w : b->occupied) n += uint64_t(bitCount(w));
  return n;
}

namespace {

/// Coarse voxel of fine voxel i of the child block at position d (x, y, z
/// bits 2, 1, 0) of its coarse block: kCoarseOf[d][i].
struct CoarseMap {
  std::array<std::array<uint16_t, kBlockVoxels>, 8> at;
  CoarseMap() {
    for (int d = 0; d < 8; ++d)
      for (int i = 0; i < kBlockVoxels; ++i) {
        const int cx = (8 * ((d >> 2) & 1) + (i >> 6)) >> 1, cy = (8 * ((d >> 1) & 1) + ((i >> 3) & 7)) >> 1,
                  cz = (8 * (d & 1) + (i & 7)) >> 1;
        at[size_t(d)][size_t(i)] = uint16_t(cx << 6 | cy << 3 | cz);
      }
  }
};

/// A class block holding `values` (one per set bit of `voted`, in voxel order):
/// compact up to ClassBlock::kCompactCounts, else one count per voxel.
std::unique_ptr<ClassBlock> makeClassBlock(uint8_t id, const std::array<uint64_t, kBlockWords>& voted,
                                           const std::vector<uint32_t>& values) {
  auto cb = std::make_unique<ClassBlock>();
  cb->classId = id;
  cb->voted = voted;
  if (values.size() <= ClassBlock::kCompactCounts) {
    uint16_t seen = 0;
    for (int k = 0; k < kBlockWords; ++k) {
      cb->before[size_t(k)] = seen;
      seen = uint16_t(seen + bitCount(voted[size_t(k)]));
    }
    cb->counts = values;
    return cb;
  }
  cb->dense = true;
  cb->counts.assign(kBlockVoxels, 0);
  size_t t = 0;
  for (int k = 0; k < kBlockWords; ++k)
    for (uint64_t bits = voted[size_t(k)]; bits; bits &= bits - 1) cb->counts[size_t(k * 64 + __builtin_ctzll(bits))] = values[t++];
  return cb;
}

// Scratch space of one worker, reused across coarse blocks.
struct Scratch {
  std::array<uint8_t, kBlockVoxels> count{};  // occupied children
  std::array<uint64_t, kBlockWords> surface{};
  std::array<int16_t, 256> slotOf{};          // class id -> slot in votes, -1: untouched
  std::vector<uint8_t> ids;                   // touched class ids
  std::vector<std::array<int64_t, kBlockVoxels>> votes;
  std::array<std::array<double, 3>, kBlockVoxels> colorSum{};
  std::array<uint8_t, kBlockVoxels> colorCount{};
  std::vector<uint32_t> values;
};

}  // namespace

MipBlocksLevel reduceBlocks(const MipBlocksLevel& fine, MipOccupancy mode, unsigned threads) {
  static const CoarseMap coarseOf;
  const Dims fd = fine.header.dims;

  // Each fine block at origin o feeds the coarse block holding o / 2, as child
  // d (its x, y, z halves); group the children of each coarse block, d ascending.
  struct Child {
    uint64_t key;  // coarse origin / 8, 21 bits per axis (scenes lie in [0, 2^24))
    int d;
    const VoxelBlock* block;
  };
  std::vector<Child> children;
  children.reserve(fine.blocks.size());
  for (const auto& b : fine.blocks) {
    const auto& o = b->origin;
    const uint64_t key = uint64_t(uint32_t(o[0]) >> 4) << 42 | uint64_t(uint32_t(o[1]) >> 4) << 21 | uint64_t(uint32_t(o[2]) >> 4);
    children.push_back({key, ((o[0] >> 3) & 1) << 2 | ((o[1] >> 3) & 1) << 1 | ((o[2] >> 3) & 1), b.get()});
  }
  std::sort(children.begin(), children.end(),
            [](const Child& a, const Child& b) { return a.key != b.key ? a.key < b.key : a.d < b.d; });
  std::vector<size_t> groupStart;
  for (size_t i = 0; i < children.size(); ++i)
    if (i == 0 || children[i].key != children[i - 1].key) groupStart.push_back(i);
  const size_t groups = groupStart.size();
  groupStart.push_back(children.size());

  // One range of coarse blocks per thread; every block goes to its own slot.
  std::vector<std::unique_ptr<VoxelBlock>> out(groups);
  const unsigned pieces = std::max(1u, std::min<unsigned>(threads, unsigned(std::max<size_t>(1, groups))));
  parallelPieces(groups, pieces, pieces, [&](size_t begin, size_t end, size_t) {
    auto s = std::make_unique<Scratch>();
    s->slotOf.fill(-1);
    for (size_t g = begin; g < end; ++g) {
      const Child& first = children[groupStart[g]];
      const std::array<int32_t, 3> co{int32_t((first.key >> 42) << 3), int32_t(((first.key >> 21) & 0x1fffff) << 3),
                                      int32_t((first.key & 0x1fffff) << 3)};
      s->count.fill(0);
      s->surface.fill(0);
      s->colorCount.fill(0);
      for (uint8_t id : s->ids) s->slotOf[id] = -1;
      s->ids.clear();
      bool anyColor = false;
      for (size_t c = groupStart[g]; c < groupStart[g + 1]; ++c) {
        const VoxelBlock& b = *children[c].block;
        const auto& map = coarseOf.at[size_t(children[c].d)];
        for (int k = 0; k < kBlockWords; ++k)
          for (uint64_t bits = b.occupied[size_t(k)]; bits; bits &= bits - 1) {
            const int i = k * 64 + __builtin_ctzll(bits);
            const uint16_t to = map[size_t(i)];
            ++s->count[to];
            if ((b.surface[size_t(k)] >> (i & 63)) & 1) s->surface[to >> 6] |= uint64_t(1) << (to & 63);
          }
        for (const auto& cb : b.classes) {
          int16_t& slot = s->slotOf[cb->classId];
          if (slot < 0) {
            slot = int16_t(s->ids.size());
            s->ids.push_back(cb->classId);
            if (s->votes.size() < s->ids.size()) s->votes.emplace_back();
            s->votes[size_t(slot)].fill(0);
          }
          auto& sum = s->votes[size_t(slot)];
          cb->forEach([&](int i, uint32_t n) { sum[map[size_t(i)]] += n; });
        }
        if (!b.colors.empty()) {
          // Voxel order within the child, as reduceScene sums: the same doubles.
          forEachColor(b, b.occupied, [&](int i, const std::array<float, 3>& rgb) {
            const uint16_t to = map[size_t(i)];
            if (s->colorCount[to] == 0) s->colorSum[to] = {0, 0, 0};
            for (int a = 0; a < 3; ++a) s->colorSum[to][size_t(a)] += double(rgb[size_t(a)]);
            ++s->colorCount[to];
            anyColor = true;
          });
        }
      }
      auto block = std::make_unique<VoxelBlock>();
      block->origin = co;
      for (int off = 0; off < kBlockVoxels; ++off) {
        const uint32_t n = s->count[size_t(off)];
        if (n == 0) continue;
        if (mode == MipOccupancy::Majority) {
          // Children of coarse voxel X on an axis: 2X and 2X+1, the latter only inside the fine dims.
          const int64_t X = co[0] + int64_t(off >> 6), Y = co[1] + int64_t((off >> 3) & 7), Z = co[2] + int64_t(off & 7);
          auto inside = [](int64_t c, uint32_t dim) { return 2 * c + 1 < int64_t(dim) ? 2u : 1u; };
          const uint32_t kids = inside(X, fd.x) * inside(Y, fd.y) * inside(Z, fd.z);
          if (2 * n < kids) continue;
        }
        const uint64_t bit = uint64_t(1) << (off & 63);
        block->occupied[size_t(off >> 6)] |= bit;
        block->surface[size_t(off >> 6)] |= s->surface[size_t(off >> 6)] & bit;
        if (anyColor && s->colorCount[size_t(off)]) {
          const double k = 1.0 / s->colorCount[size_t(off)];
          const auto& sum = s->colorSum[size_t(off)];
          block->colors.push_back({float(sum[0] * k), float(sum[1] * k), float(sum[2] * k)});  // voxel order
          block->colored[size_t(off >> 6)] |= bit;
        }
      }
      bool any = false;
      for (uint64_t w : block->occupied) any = any || w;
      if (!any) continue;
      // Votes of the kept voxels, class by class in id order (a dropped voxel keeps none).
      std::vector<uint8_t> ids = s->ids;
      std::sort(ids.begin(), ids.end());
      for (uint8_t id : ids) {
        const auto& sum = s->votes[size_t(s->slotOf[id])];
        std::array<uint64_t, kBlockWords> voted{};
        s->values.clear();
        for (int k = 0; k < kBlockWords; ++k)
          for (uint64_t bits = block->occupied[size_t(k)]; bits; bits &= bits - 1) {
            const int i = k * 64 + __builtin_ctzll(bits);
            if (sum[size_t(i)] == 0) continue;
            voted[size_t(k)] |= uint64_t(1) << (i & 63);
            s->values.push_back(uint32_t(std::min<int64_t>(sum[size_t(i)], kMaxVotesPerClass)));
          }
        if (!s->values.empty()) block->classes.push_back(makeClassBlock(id, voted, s->values));
      }
      out[g] = std::move(block);
    }
  });

  MipBlocksLevel coarse;
  coarse.header = coarserMipHeader(fine.header);
  coarse.colorGrid = fine.colorGrid;
  for (auto& b : out)
    if (b) coarse.blocks.push_back(std::move(b));
  return coarse;
}

}  // namespace vox
