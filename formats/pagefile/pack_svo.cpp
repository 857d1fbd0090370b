#include "formats/pagefile/pack_svo.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <deque>

#include "formats/pagefile/pagefile.h"
#include "libvox/core/atlas_content.h"
#include "libvox/core/error.h"
#include "libvox/core/summary_bytes.h"

namespace vox::packdetail {

namespace {

void putU32(uint8_t* p, uint32_t v) {
  for (int b = 0; b < 4; ++b) p[b] = uint8_t(v >> (8 * b));
}
void putU64(uint8_t* p, uint64_t v) {
  for (int b = 0; b < 8; ++b) p[b] = uint8_t(v >> (8 * b));
}

// One level of the chunk's own pyramid: level d has side C >> d; voxel (x, y, z)
// at x + S * (y + S * z).
struct Grid {
  uint32_t side = 0;
  std::vector<uint8_t> occ, surface;
  std::vector<std::array<uint8_t, 4>> summary, color;
  std::vector<std::array<float, 3>> linear;  // valid when color[k][3] == 255
  std::vector<uint32_t> voteBegin, voteEnd;
  std::vector<ClassVotes> votes;
};

Grid baseGrid(const ChunkVoxels& c) {
  Grid g;
  g.side = c.side;
  const uint32_t n = c.side * c.side * c.side;
  g.occ.resize(n);
  for (uint32_t k = 0; k < n; ++k) g.occ[k] = c.occupied(k) ? 1 : 0;
  g.surface = c.surface;
  g.summary = c.summary;
  g.color = c.color;
  g.linear = c.linear;
  g.voteBegin = c.voteBegin;
  g.voteEnd = c.voteEnd;
  g.votes = c.votes;
  return g;
}

// Level d + 1 from level d, exactly as libvox/scene/mip.cpp reduces with `any`: votes
// summed per class in 64 bits and saturated at kMaxVotesPerClass, colour the
// plain average (in double, children in x, y, z order with z fastest, times
// 1/count, stored as float) over the children that have one, surface OR.
Grid reduce(const Grid& f) {
  Grid g;
  g.side = f.side / 2;
  const uint32_t S = g.side, FS = f.side, n = S * S * S;
  g.occ.assign(n, 0);
  g.surface.assign(n, 0);
  g.summary.assign(n, {0, 0, 0, 0});
  g.color.assign(n, {0, 0, 0, 0});
  g.linear.assign(n, {0, 0, 0});
  g.voteBegin.assign(n, 0);
  g.voteEnd.assign(n, 0);
  std::array<uint64_t, 256> sums{};
  std::vector<uint8_t> touched;
  for (uint32_t z = 0; z < S; ++z)
    for (uint32_t y = 0; y < S; ++y)
      for (uint32_t x = 0; x < S; ++x) {
        const uint32_t k = x + S * (y + S * z);
        uint32_t count = 0, colorCount = 0;
        double cs[3] = {0, 0, 0};
        touched.clear();
        for (uint32_t dx = 0; dx < 2; ++dx)
          for (uint32_t dy = 0; dy < 2; ++dy)
            for (uint32_t dz = 0; dz < 2; ++dz) {
              const uint32_t fk = (2 * x + dx) + FS * ((2 * y + dy) + FS * (2 * z + dz));
              if (!f.occ[fk]) continue;
              ++count;
              if (f.surface[fk]) g.surface[k] = 1;
              for (uint32_t q = f.voteBegin[fk]; q < f.voteEnd[fk]; ++q) {
                const ClassVotes& cv = f.votes[q];
                if (cv.votes == 0) continue;
                if (sums[cv.classId] == 0) touched.push_back(cv.classId);
                sums[cv.classId] += cv.votes;
              }
              if (f.color[fk][3] == 255) {
                for (int a = 0; a < 3; ++a) cs[a] += double(f.linear[fk][size_t(a)]);
                ++colorCount;
              }
            }
        if (!count) continue;
        g.occ[k] = 1;
        std::sort(touched.begin(), touched.end());
        g.voteBegin[k] = uint32_t(g.votes.size());
        for (uint8_t c : touched) {
          if (sums[c]) g.votes.push_back({c, uint32_t(std::min<uint64_t>(sums[c], kMaxVotesPerClass))});
          sums[c] = 0;
        }
        g.voteEnd[k] = uint32_t(g.votes.size());
        const SummaryTexel t = summarize(std::span<const ClassVotes>(g.votes.data() + g.voteBegin[k], g.voteEnd[k] - g.voteBegin[k]));
        g.summary[k] = {t.cls, t.conf, t.obs, t.mrg};
        if (colorCount) {
          const double inv = 1.0 / colorCount;
          for (int a = 0; a < 3; ++a) g.linear[k][size_t(a)] = float(cs[a] * inv);
          g.color[k] = {linearToSrgb8(g.linear[k][0]), linearToSrgb8(g.linear[k][1]), linearToSrgb8(g.linear[k][2]), 255};
        }
      }
  return g;
}

struct Node {
  uint32_t level = 0;                 // 0: leaf brick; the root has log2(C) - 3
  std::array<uint32_t, 3> origin{};   // in chunk-local level-0 voxels
  uint8_t childMask = 0, flags = 0;
  uint32_t childPtr = 0;
  std::array<uint64_t, 8> bitmap{};   // of its brick, bit bx + 8 * (by + 8 * bz)
  uint32_t count = 0;
};

}  // namespace

std::vector<uint8_t> encodeSvo(const ChunkVoxels& chunk, uint32_t flags) {
  if (!chunk.withVotes) throw Error(ErrorKind::Internal, "encodeSvo: the chunk has no votes");
  const uint32_t C = chunk.side;
  const int depth = std::countr_zero(C) - 3;  // level of the root
  std::vector<Grid> grids;
  grids.push_back(baseGrid(chunk));
  for (int d = 1; d <= depth; ++d) grids.push_back(reduce(grids.back()));

  // The brick of a node: the 8^3 block of its level's grid at origin >> level.
  auto fillBrick = [&](Node& n) {
    const Grid& g = grids[n.level];
    const uint32_t S = g.side, ox = n.origin[0] >> n.level, oy = n.origin[1] >> n.level, oz = n.origin[2] >> n.level;
    n.bitmap.fill(0);
    n.count = 0;
    n.childMask = 0;
    bool colored = false;
    for (uint32_t bz = 0; bz < 8; ++bz)
      for (uint32_t by = 0; by < 8; ++by)
        for (uint32_t bx = 0; bx < 8; ++bx) {
          const uint32_t k = (ox + bx) + S * ((oy + by) + S * (oz + bz));
          if (!g.occ[k]) continue;
          const uint32_t b = bx + 8 * (by + 8 * bz);
          n.bitmap[b >> 6] |= uint64_t(1) << (b & 63);
          ++n.count;
          n.childMask |= uint8_t(1u << ((bx >> 2) | ((by >> 2) << 1) | ((bz >> 2) << 2)));
          if (g.color[k][3] == 255) colored = true;
        }
    n.flags = uint8_t((n.count == 512 ? pagefile::kSvoNodeFull : 0) | (colored ? pagefile::kSvoNodeColor : 0));
  };

  // Breadth first: the children of a node are contiguous, in octant order.
  std::vector<Node> nodes;
  {
    Node root;
    root.level = uint32_t(depth);
    fillBrick(root);
    nodes.push_back(root);
  }
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].level == 0) {
      nodes[i].childPtr = uint32_t(i);  // a leaf points at its brick (= its own index)
      continue;
    }
    nodes[i].childPtr = uint32_t(nodes.size());
    const uint32_t half = 8u << (nodes[i].level - 1);
    for (uint32_t oct = 0; oct < 8; ++oct) {
      if (!(nodes[i].childMask >> oct & 1)) continue;
      Node c;
      c.level = nodes[i].level - 1;
      c.origin = {nodes[i].origin[0] + half * (oct & 1), nodes[i].origin[1] + half * ((oct >> 1) & 1),
                  nodes[i].origin[2] + half * (oct >> 2)};
      fillBrick(c);
      nodes.push_back(c);
    }
  }

  const uint64_t B = nodes.size();
  uint64_t M = 0, T = 0;
  for (const Node& n : nodes) {
    M += n.count == 512 ? 0 : 1;
    T += n.count;
  }
  const bool color = flags & pagefile::kFlagColor, surfaceCh = flags & pagefile::kFlagSurface;
  std::vector<uint8_t> out(pagefile::svoPayloadBytes(B, M, T, flags), 0);
  putU32(out.data(), uint32_t(B));
  putU32(out.data() + 4, uint32_t(M));
  putU32(out.data() + 8, uint32_t(T));
  uint8_t* nodeP = out.data() + 16;
  uint8_t* brickP = nodeP + 8 * B;
  uint8_t* bitmapP = brickP + 8 * B;
  uint8_t* sumP = bitmapP + 64 * M;
  uint8_t* colP = sumP + 4 * T;
  uint8_t* surfP = colP + (color ? 4 * T : 0);
  uint32_t slot = 0, first = 0;
  for (size_t i = 0; i < nodes.size(); ++i) {
    const Node& n = nodes[i];
    putU64(nodeP + 8 * i, uint64_t(n.childMask) | uint64_t(n.flags) << 8 | uint64_t(n.level) << 24 |
                              uint64_t(n.childPtr) << 32);
    const bool full = n.count == 512;
    putU32(brickP + 8 * i, first);
    putU32(brickP + 8 * i + 4, full ? pagefile::kSvoNoBitmap : slot);
    if (!full) {
      for (int w = 0; w < 8; ++w) putU64(bitmapP + 64 * slot + 8 * w, n.bitmap[size_t(w)]);
      ++slot;
    }
    const Grid& g = grids[n.level];
    const uint32_t S = g.side, ox = n.origin[0] >> n.level, oy = n.origin[1] >> n.level, oz = n.origin[2] >> n.level;
    for (uint32_t w = 0; w < 8; ++w)
      for (uint64_t word = n.bitmap[w]; word; word &= word - 1) {
        const uint32_t b = w * 64 + uint32_t(std::countr_zero(word));
        const uint32_t k = (ox + (b & 7)) + S * ((oy + ((b >> 3) & 7)) + S * (oz + (b >> 6)));
        std::memcpy(sumP + 4ull * first, g.summary[k].data(), 4);
        if (color) std::memcpy(colP + 4ull * first, g.color[k].data(), 4);
        if (surfaceCh && g.surface[k]) surfP[first / 8] |= uint8_t(1u << (first % 8));
        ++first;
      }
  }
  return out;
}

}  // namespace vox::packdetail
