#include "libvox/mesh/voxel_blocks.h"

#include <algorithm>

#include "libvox/core/error.h"

namespace vox {

namespace {

ClassBlock& classOf(VoxelBlock& b, uint8_t classId) {
  return (!b.classes.empty() && b.classes.back()->classId == classId) ? *b.classes.back() : classBlock(b, classId);
}

}  // namespace

void ClassBlock::addFirst(int i, uint32_t votes) {
  if (votes == 0) return;
  if (!dense && counts.size() >= kCompactCounts) makeDense();
  voted[size_t(i >> 6)] |= uint64_t(1) << (i & 63);
  if (dense) {
    counts[size_t(i)] = std::min(votes, kMaxVotesPerClass);
    return;
  }
  if (counts.capacity() == counts.size()) counts.reserve(std::max<size_t>(16, counts.size() * 2));
  counts.insert(counts.begin() + ptrdiff_t(slot(i)), std::min(votes, kMaxVotesPerClass));
  for (int k = (i >> 6) + 1; k < kBlockWords; ++k) ++before[size_t(k)];
}

void ClassBlock::makeDense() {
  if (dense) return;
  std::vector<uint32_t> all(kBlockVoxels, 0);
  forEach([&](int i, uint32_t c) { all[size_t(i)] = c; });
  counts = std::move(all);
  dense = true;
}

void ClassBlock::addAll(const ClassBlock& other) {
  if (dense || other.dense || counts.size() + other.counts.size() > kCompactCounts) {
    makeDense();
    other.forEach([&](int i, uint32_t c) { counts[size_t(i)] = saturatingVotes(counts[size_t(i)], c); });
    for (int k = 0; k < kBlockWords; ++k) voted[size_t(k)] |= other.voted[size_t(k)];
    return;
  }
  // Both compact, in voxel order: one merge pass.
  std::vector<uint32_t> merged;
  merged.reserve(counts.size() + other.counts.size());
  size_t a = 0, b = 0;
  uint16_t seen = 0;
  for (int k = 0; k < kBlockWords; ++k) {
    before[size_t(k)] = seen;
    const uint64_t mine = voted[size_t(k)], theirs = other.voted[size_t(k)];
    for (uint64_t bits = mine | theirs; bits; bits &= bits - 1) {
      const uint64_t bit = bits & (~bits + 1);
      const uint32_t x = (mine & bit) ? counts[a++] : 0, y = (theirs & bit) ? other.counts[b++] : 0;
      merged.push_back(saturatingVotes(x, y));
      ++seen;
    }
    voted[size_t(k)] = mine | theirs;
  }
  counts = std::move(merged);
}

ClassBlock& classBlock(VoxelBlock& block, uint8_t classId) {
  auto at = std::lower_bound(block.classes.begin(), block.classes.end(), classId,
                             [](const std::unique_ptr<ClassBlock>& c, uint8_t id) { return c->classId < id; });
  if (at == block.classes.end() || (*at)->classId != classId) {
    auto cb = std::make_unique<ClassBlock>();
    cb->classId = classId;
    at = block.classes.insert(at, std::move(cb));
  }
  return **at;
}

const ClassBlock* findClassBlock(const VoxelBlock& block, uint8_t classId) {
  for (const auto& cb : block.classes)
    if (cb->classId == classId) return cb.get();
  return nullptr;
}

void materializeRuns(VoxelBlock& b) {
  if (!b.hasRuns()) return;
  ClassBlock& cb = classBlock(b, b.runClass);
  ClassBlock runs;
  runs.classId = b.runClass;
  uint16_t seen = 0;
  for (int k = 0; k < kBlockWords; ++k) {
    runs.before[size_t(k)] = seen;
    seen = uint16_t(seen + bitCount(b.runMask[size_t(k)]));
  }
  runs.voted = b.runMask;
  runs.counts.assign(seen, std::min(b.runVotes, kMaxVotesPerClass));
  if (b.runVotes) cb.addAll(runs);
  b.runMask = {};
  b.runClass = 0;
  b.runVotes = 0;
}

VoxelBlocks::VoxelBlocks() = default;
VoxelBlocks::VoxelBlocks(VoxelBlocks&&) noexcept = default;
VoxelBlocks& VoxelBlocks::operator=(VoxelBlocks&&) noexcept = default;
VoxelBlocks::~VoxelBlocks() = default;

VoxelBlock& VoxelBlocks::block(int32_t x, int32_t y, int32_t z) {
  const uint64_t key = blockKeyOf({x, y, z});  // callers checked representable()
  if (key == lastKey_) return *last_;
  auto& slot = blocks_[key];
  if (!slot) {
    slot = std::make_unique<VoxelBlock>();
    slot->origin = {x & ~(kBlockDim - 1), y & ~(kBlockDim - 1), z & ~(kBlockDim - 1)};
  }
  lastKey_ = key;
  last_ = slot.get();
  return *last_;
}

VoxelBlock* VoxelBlocks::blockAt(Coord3 c) {
  if (!representable(c)) {
    outOfRange_ = true;
    return nullptr;
  }
  return &block(c.u, c.v, c.w);
}

void VoxelBlocks::addVotesSlow(Coord3 c, uint8_t classId, uint32_t votes, bool surface) {
  if (!representable(c)) {
    outOfRange_ = true;
    return;
  }
  VoxelBlock& b = block(c.u, c.v, c.w);
  const int i = blockOffset(c.u, c.v, c.w);
  b.occupied[i >> 6] |= uint64_t(1) << (i & 63);
  if (surface) b.surface[i >> 6] |= uint64_t(1) << (i & 63);
  classOf(b, classId).add(i, votes);
}

void VoxelBlocks::addRun(Coord3 start, uint32_t length, uint8_t classId, uint32_t votes, bool surface) {
  if (votes == 0 || length == 0) return;
  const Coord3 last{start.u, start.v, int32_t(int64_t(start.w) + length - 1)};
  if (!representable(start) || !representable(last)) {
    outOfRange_ = true;
    return;
  }
  for (int32_t w = start.w; w <= last.w;) {
    // One block at a time: the run's part inside it shares the block.
    const int32_t blockEnd = std::min(last.w, (w | (kBlockDim - 1)));
    VoxelBlock& b = block(start.u, start.v, w);
    if (!surface) {
      // The voxels of one (x, y) in a block are 8 consecutive bits of one word.
      const int first = blockOffset(start.u, start.v, w), count = blockEnd - w + 1;
      const uint64_t bits = (count == 64 ? ~uint64_t(0) : ((uint64_t(1) << count) - 1)) << (first & 63);
      uint64_t& word = b.runMask[size_t(first >> 6)];
      const bool empty = !b.hasRuns();
      if (empty || (b.runClass == classId && b.runVotes == votes && !(word & bits))) {
        b.runClass = classId;
        b.runVotes = votes;
        word |= bits;
        b.occupied[size_t(first >> 6)] |= bits;
        w = blockEnd + 1;
        continue;
      }
      materializeRuns(b);  // another class or count, or votes that add up: plain form
    }
    ClassBlock& cb = classOf(b, classId);
    for (int32_t z = w; z <= blockEnd; ++z) {
      const int i = blockOffset(start.u, start.v, z);
      b.occupied[i >> 6] |= uint64_t(1) << (i & 63);
      if (surface) b.surface[i >> 6] |= uint64_t(1) << (i & 63);
      cb.add(i, votes);
    }
    w = blockEnd + 1;
  }
}

void VoxelBlocks::setColor(Coord3 c, RgbLinear color) {
  if (!representable(c)) {
    outOfRange_ = true;
    return;
  }
  setBlockColor(block(c.u, c.v, c.w), blockOffset(c.u, c.v, c.w), {color.r, color.g, color.b});
}

void setBlockColor(VoxelBlock& b, int i, const std::array<float, 3>& rgb) {
  const size_t rank = colorRank(b, i);
  uint64_t& word = b.colored[size_t(i >> 6)];
  const uint64_t bit = uint64_t(1) << (i & 63);
  if (word & bit) {
    b.colors[rank] = rgb;
    return;
  }
  b.colors.insert(b.colors.begin() + std::ptrdiff_t(rank), rgb);  // writers set them in voxel order: at the end
  word |= bit;
}

void VoxelBlocks::merge(VoxelBlocks&& other) {
  outOfRange_ = outOfRange_ || other.outOfRange_;
  blocks_.reserve(blocks_.size() + other.blocks_.size());
  other.blocks_.forEach([&](uint64_t key, std::unique_ptr<VoxelBlock>& theirs) {
    auto& slot = blocks_[key];
    if (!slot) {
      slot = std::move(theirs);
      return;
    }
    VoxelBlock& mine = *slot;
    if (theirs->hasRuns()) {
      // Their runs join ours when they match (same class and count, disjoint
      // voxels); otherwise they become plain votes, summed below.
      bool overlap = false;
      for (int k = 0; k < kBlockWords; ++k) overlap = overlap || (mine.runMask[size_t(k)] & theirs->runMask[size_t(k)]);
      if (!mine.hasRuns() || (mine.runClass == theirs->runClass && mine.runVotes == theirs->runVotes && !overlap)) {
        for (int k = 0; k < kBlockWords; ++k) mine.runMask[size_t(k)] |= theirs->runMask[size_t(k)];
        mine.runClass = theirs->runClass;
        mine.runVotes = theirs->runVotes;
      } else {
        materializeRuns(*theirs);
      }
    }
    for (int k = 0; k < kBlockWords; ++k) {
      mine.occupied[k] |= theirs->occupied[k];
      mine.surface[k] |= theirs->surface[k];
    }
    for (auto& cb : theirs->classes) {
      ClassBlock& dst = classBlock(mine, cb->classId);
      if (dst.empty())
        std::swap(dst, *cb);
      else
        dst.addAll(*cb);
    }

    if (!theirs->colors.empty()) {
      // The union of both in voxel order; where both have a colour, ours.
      std::array<uint64_t, kBlockWords> colored;
      size_t count = 0;
      for (int k = 0; k < kBlockWords; ++k) {
        colored[size_t(k)] = mine.colored[size_t(k)] | theirs->colored[size_t(k)];
        count += size_t(bitCount(colored[size_t(k)]));
      }
      std::vector<std::array<float, 3>> colors;
      colors.reserve(count);
      size_t m = 0, t = 0;
      for (int k = 0; k < kBlockWords; ++k)
        for (uint64_t bits = colored[size_t(k)]; bits; bits &= bits - 1) {
          const uint64_t bit = bits & (~bits + 1);
          const bool inMine = mine.colored[size_t(k)] & bit, inTheirs = theirs->colored[size_t(k)] & bit;
          colors.push_back(inMine ? mine.colors[m] : theirs->colors[t]);
          m += inMine, t += inTheirs;
        }
      mine.colored = colored;
      mine.colors = std::move(colors);
    }
  });
  other.blocks_.clear();
  other.lastKey_ = ~uint64_t(0);
  other.last_ = nullptr;
  lastKey_ = ~uint64_t(0);
  last_ = nullptr;
}

std::vector<VoxelBlock*> VoxelBlocks::sortedBlocks(BlockOrder less) {
  std::vector<VoxelBlock*> out;
  out.reserve(blocks_.size());
  blocks_.forEach([&](uint64_t, std::unique_ptr<VoxelBlock>& b) { out.push_back(b.get()); });
  if (!less) less = [](const VoxelBlock* a, const VoxelBlock* b) { return a->origin < b->origin; };
  std::sort(out.begin(), out.end(), less);
  return out;
}

void VoxelBlocks::validate(const Dims& d, const ClassTable& classes) {
  if (d.x == 0 || d.y == 0 || d.z == 0)
    throw Error(ErrorKind::Internal, "scene dims must be >= 1 on every axis, got " + toString(d));
  if (outOfRange_) throw Error(ErrorKind::Internal, "a voxel lies outside the scene domain " + toString(d));
  const uint32_t dim[3] = {d.x, d.y, d.z};
  blocks_.forEach([&](uint64_t, const std::unique_ptr<VoxelBlock>& b) {
    const auto& o = b->origin;
    for (int k = 0; k < 3; ++k)
      if (o[k] < 0 || uint32_t(o[k] + kBlockDim - 1) >= dim[k]) {
        // The block straddles or leaves the domain: check its voxels one by one.
        for (int i = 0; i < kBlockVoxels; ++i) {
          if (!((b->occupied[i >> 6] >> (i & 63)) & 1)) continue;
          const int32_t x = o[0] + (i >> 6), y = o[1] + ((i >> 3) & 7), z = o[2] + (i & 7);
          if (x < 0 || y < 0 || z < 0 || uint32_t(x) >= d.x || uint32_t(y) >= d.y || uint32_t(z) >= d.z)
            throw Error(ErrorKind::Internal,
                        "voxel " + toString(Coord3{x, y, z}) + " lies outside the scene domain " + toString(d));
        }
        break;
      }
    if (b->hasRuns() && !classes.find(b->runClass))
      throw Error(ErrorKind::Internal,
                  "class id " + std::to_string(b->runClass) + " has votes but is not in the class table");
    for (const auto& cb : b->classes)
      if (!classes.find(cb->classId))
        throw Error(ErrorKind::Internal,
                    "class id " + std::to_string(cb->classId) + " has votes but is not in the class table");
  });
}

void VoxelBlocks::release(VoxelBlock& block) {
  block.classes.clear();
  block.classes.shrink_to_fit();
  std::vector<std::array<float, 3>>().swap(block.colors);
}

}  // namespace vox
