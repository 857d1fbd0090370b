#include "formats/pagefile/svo_layout.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <span>
#include <string>

#include "formats/pagefile/layout_io.h"
#include "libvox/core/bits.h"
#include "libvox/core/color.h"
#include "libvox/core/error.h"
#include "libvox/core/summary_bytes.h"

namespace vox::pagefile {

uint64_t svoPayloadBytes(uint64_t nodes, uint64_t bitmaps, uint64_t records, uint32_t flags) {
  uint64_t n = kSvoFixedBytes + 16 * nodes + 64 * bitmaps + 4 * records;
  if (flags & kFlagColor) n += 4 * records;
  if (flags & kFlagSurface) n += (records + 7) / 8;
  return n;
}

// ------------------------------------------------------------------ encoder

namespace {

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

// The chunk and its reductions: grids[d] has side C >> d, d = 0 .. depth.
std::vector<Grid> chunkPyramid(const ChunkVoxels& chunk, int depth) {
  std::vector<Grid> grids;
  grids.push_back(baseGrid(chunk));
  for (int d = 1; d <= depth; ++d) grids.push_back(reduce(grids.back()));
  return grids;
}

struct Node {
  uint32_t level = 0;                 // 0: leaf brick; the root has log2(C) - 3
  std::array<uint32_t, 3> origin{};   // in chunk-local level-0 voxels
  uint8_t childMask = 0, flags = 0;
  uint32_t childPtr = 0;
  std::array<uint64_t, 8> bitmap{};   // of its brick, bit bx + 8 * (by + 8 * bz)
  uint32_t count = 0;
};

// The brick of a node: the 8^3 block of its level's grid at origin >> level.
void fillBrick(const std::vector<Grid>& grids, Node& n) {
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
  n.flags = uint8_t((n.count == 512 ? kSvoNodeFull : 0) | (colored ? kSvoNodeColor : 0));
}

// The node pool, breadth first from the root: the children of a node are
// contiguous, in octant order; empty octants have no node.
std::vector<Node> buildNodeTree(const std::vector<Grid>& grids, int depth) {
  std::vector<Node> nodes;
  Node root;
  root.level = uint32_t(depth);
  fillBrick(grids, root);
  nodes.push_back(root);
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
      fillBrick(grids, c);
      nodes.push_back(c);
    }
  }
  return nodes;
}

// Counts, node pool, brick table, bitmaps and the records of every brick.
std::vector<uint8_t> writePayload(const std::vector<Node>& nodes, const std::vector<Grid>& grids, uint32_t flags) {
  const uint64_t B = nodes.size();
  uint64_t M = 0, T = 0;
  for (const Node& n : nodes) {
    M += n.count == 512 ? 0 : 1;
    T += n.count;
  }
  const bool color = flags & kFlagColor, surfaceCh = flags & kFlagSurface;
  std::vector<uint8_t> out(svoPayloadBytes(B, M, T, flags), 0);
  storeLE<uint32_t>(out.data() + svo_field::kNodeCount, uint32_t(B));
  storeLE<uint32_t>(out.data() + svo_field::kBitmapCount, uint32_t(M));
  storeLE<uint32_t>(out.data() + svo_field::kRecordCount, uint32_t(T));
  uint8_t* nodeP = out.data() + kSvoFixedBytes;
  uint8_t* brickP = nodeP + 8 * B;
  uint8_t* bitmapP = brickP + 8 * B;
  uint8_t* sumP = bitmapP + 64 * M;
  uint8_t* colP = sumP + 4 * T;
  uint8_t* surfP = colP + (color ? 4 * T : 0);
  uint32_t slot = 0, first = 0;
  for (size_t i = 0; i < nodes.size(); ++i) {
    const Node& n = nodes[i];
    storeLE<uint64_t>(nodeP + 8 * i, uint64_t(n.childMask) | uint64_t(n.flags) << 8 | uint64_t(n.level) << 24 |
                                         uint64_t(n.childPtr) << 32);
    const bool full = n.count == 512;
    storeLE<uint32_t>(brickP + 8 * i, first);
    storeLE<uint32_t>(brickP + 8 * i + 4, full ? kSvoNoBitmap : slot);
    if (!full) {
      for (int w = 0; w < 8; ++w) storeLE<uint64_t>(bitmapP + 64 * slot + 8 * w, n.bitmap[size_t(w)]);
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
        if (surfaceCh && g.surface[k]) setBit(surfP, first);
        ++first;
      }
  }
  return out;
}

}  // namespace

std::vector<uint8_t> encodeSvo(const ChunkVoxels& chunk, uint32_t flags, const ChunkPlace&) {
  if (!chunk.withVotes) throw Error(ErrorKind::Internal, "encodeSvo: the chunk has no votes");
  const int depth = std::countr_zero(chunk.side) - 3;  // level of the root
  const std::vector<Grid> grids = chunkPyramid(chunk, depth);
  const std::vector<Node> nodes = buildNodeTree(grids, depth);
  return writePayload(nodes, grids, flags);
}

std::vector<uint8_t> encodeSvoFromBricks(std::span<const SvoBrick> bricks, uint32_t side, uint32_t flags) {
  const int depth = std::countr_zero(side) - 3;
  // The chunk's own pyramid as the bricks show it: every brick voxel lands in
  // its level's grid; buildNodeTree and writePayload then work as for votes.
  std::vector<Grid> grids(size_t(depth) + 1);
  for (int d = 0; d <= depth; ++d) {
    Grid& g = grids[size_t(d)];
    g.side = side >> d;
    const size_t n = size_t(g.side) * g.side * g.side;
    g.occ.assign(n, 0);
    g.surface.assign(n, 0);
    g.summary.assign(n, {0, 0, 0, 0});
    g.color.assign(n, {0, 0, 0, 0});
  }
  for (const SvoBrick& b : bricks) {
    if (b.level > depth) throw Error(ErrorKind::Internal, "encodeSvoFromBricks: brick level past the root");
    Grid& g = grids[b.level];
    const uint32_t S = g.side, ox = b.origin[0] >> b.level, oy = b.origin[1] >> b.level, oz = b.origin[2] >> b.level;
    for (const DecodedVoxel& v : b.voxels) {
      const uint32_t k = (ox + (v.index & 7)) + S * ((oy + ((v.index >> 3) & 7)) + S * (oz + (v.index >> 6)));
      g.occ[k] = 1;
      g.surface[k] = v.surface ? 1 : 0;
      g.summary[k] = v.summary;
      g.color[k] = v.color;
    }
  }
  const std::vector<Node> nodes = buildNodeTree(grids, depth);
  return writePayload(nodes, grids, flags);
}

// ------------------------------------------------------------------ decoder

namespace {

// Where the parts of a payload start, from its counts.
struct Sections {
  uint64_t nodeCount = 0, bitmapCount = 0, recordCount = 0;  // B, M, T
  const uint8_t *nodes = nullptr, *bricks = nullptr, *bitmaps = nullptr;
  const uint8_t *summary = nullptr, *color = nullptr, *surface = nullptr;
  bool hasColor = false, hasSurface = false;
};

// One node as read and checked, with its brick's bitmap and records.
struct NodeRead {
  uint32_t level = 0;
  std::array<uint32_t, 3> origin{};
  uint8_t mask = 0, flags = 0;
  uint32_t ptr = 0, first = 0, count = 0;
  std::array<uint64_t, 8> bits{};

  bool has(uint32_t b) const { return (bits[b >> 6] >> (b & 63)) & 1; }
  // The record of brick voxel b: first + the rank of b among the brick's bits.
  uint32_t recordOf(uint32_t b) const {
    uint32_t r = 0;
    for (uint32_t w = 0; w < b / 64; ++w) r += uint32_t(bitCount(bits[w]));
    return first + r + uint32_t(bitCount(bits[b / 64] & ((uint64_t(1) << (b % 64)) - 1)));
  }
};

// Running counts while the node pool is walked.
struct Walk {
  uint64_t nextChild = 1;  // node index the next child gets
  uint64_t bitmapSlot = 0, records = 0, leafVoxels = 0;
};

// Step 1: the counts in range, the size they give, the sections.
Sections readSections(const ChunkPayload& in) {
  const std::span<const uint8_t> bytes = in.bytes;
  const uint8_t* p = bytes.data();
  if (bytes.size() < kSvoFixedBytes) in.fail("field 'size': shorter than the svo payload's fixed part");
  const uint32_t depth = in.header.chunkLog2 - 3u;
  Sections s;
  const uint64_t B = loadLE<uint32_t>(p + svo_field::kNodeCount), M = loadLE<uint32_t>(p + svo_field::kBitmapCount),
                 T = loadLE<uint32_t>(p + svo_field::kRecordCount);
  uint64_t maxNodes = 0;
  for (uint32_t d = 0; d <= depth; ++d) maxNodes += uint64_t(1) << (3 * d);
  if (B < 1 || B > maxNodes)
    in.fail("svo field 'node_count': " + std::to_string(B) + ", expected 1.." + std::to_string(maxNodes));
  if (M > B) in.fail("svo field 'bitmap_count': " + std::to_string(M) + " > node_count " + std::to_string(B));
  if (T < B || T > 512 * B)
    in.fail("svo field 'record_count': " + std::to_string(T) + ", expected node_count.." + std::to_string(512 * B));
  if (loadLE<uint32_t>(p + svo_field::kReserved) != 0) in.fail("svo field 'reserved': must be 0");
  const uint64_t want = svoPayloadBytes(B, M, T, in.header.flags);
  if (bytes.size() != want)
    in.fail("field 'size': " + std::to_string(bytes.size()) + " bytes, the svo counts (node_count " + std::to_string(B) +
            ", bitmap_count " + std::to_string(M) + ", record_count " + std::to_string(T) + ") need " + std::to_string(want));
  s.nodeCount = B, s.bitmapCount = M, s.recordCount = T;
  s.hasColor = in.header.flags & kFlagColor;
  s.hasSurface = in.header.flags & kFlagSurface;
  s.nodes = p + kSvoFixedBytes;
  s.bricks = s.nodes + 8 * B;
  s.bitmaps = s.bricks + 8 * B;
  s.summary = s.bitmaps + 64 * M;
  s.color = s.summary + 4 * T;
  s.surface = s.color + (s.hasColor ? 4 * T : 0);
  return s;
}

// Step 2a: node n's word; places its children (breadth first, octant order).
void readNode(const ChunkPayload& in, const Sections& s, uint64_t n, std::vector<NodeRead>& nodes, Walk& walk) {
  NodeRead& nd = nodes[n];
  auto fail = [&](const std::string& what) { in.fail("svo node " + std::to_string(n) + ": field " + what); };
  if (n >= walk.nextChild) fail("'child_ptr': the node is not a child of any earlier node (unreachable)");
  const uint64_t raw = loadLE<uint64_t>(s.nodes + 8 * n);
  nd.mask = uint8_t(raw);
  nd.flags = uint8_t(raw >> 8);
  nd.ptr = uint32_t(raw >> 32);
  if (uint8_t(raw >> 16) != 0) fail("'reserved': must be 0");
  if (uint8_t(raw >> 24) != nd.level)
    fail("'level': " + std::to_string(uint8_t(raw >> 24)) + ", expected " + std::to_string(nd.level));
  if (nd.flags & ~(kSvoNodeFull | kSvoNodeColor)) fail("'flags': unknown bits");
  if (nd.level == 0) {
    if (nd.ptr != n) fail("'child_ptr': a leaf must point at its own brick " + std::to_string(n));
    return;
  }
  if (nd.ptr != walk.nextChild)
    fail("'child_ptr': " + std::to_string(nd.ptr) + ", expected " + std::to_string(walk.nextChild) +
         " (children follow breadth first)");
  const uint32_t half = 8u << (nd.level - 1);
  for (uint32_t oct = 0; oct < 8; ++oct) {
    if (!(nd.mask >> oct & 1)) continue;
    if (walk.nextChild >= s.nodeCount) fail("'child_mask': children past node_count " + std::to_string(s.nodeCount));
    NodeRead& c = nodes[walk.nextChild++];
    c.level = nd.level - 1;
    c.origin = {nd.origin[0] + half * (oct & 1), nd.origin[1] + half * ((oct >> 1) & 1), nd.origin[2] + half * (oct >> 2)};
  }
}

// Step 2b: brick n's table entry and bitmap.
void readBrickEntry(const ChunkPayload& in, const Sections& s, uint64_t n, NodeRead& nd, Walk& walk) {
  auto fail = [&](const std::string& what) { in.fail("svo brick " + std::to_string(n) + ": field " + what); };
  nd.first = loadLE<uint32_t>(s.bricks + 8 * n);
  const uint32_t slot = loadLE<uint32_t>(s.bricks + 8 * n + 4);
  if (nd.first != walk.records)
    fail("'first': " + std::to_string(nd.first) + ", expected " + std::to_string(walk.records));
  const bool full = nd.flags & kSvoNodeFull;
  if (full != (slot == kSvoNoBitmap)) fail("'bitmap': the node's full flag and the bitmap slot disagree");
  if (full) {
    nd.bits.fill(~uint64_t(0));
    return;
  }
  if (slot != walk.bitmapSlot || walk.bitmapSlot >= s.bitmapCount)
    fail("'bitmap': slot " + std::to_string(slot) + ", expected " + std::to_string(walk.bitmapSlot) +
         " (bitmaps are stored in brick order, bitmap_count " + std::to_string(s.bitmapCount) + ")");
  for (int w = 0; w < 8; ++w) nd.bits[size_t(w)] = loadLE<uint64_t>(s.bitmaps + 64 * walk.bitmapSlot + 8 * w);
  ++walk.bitmapSlot;
}

// Step 2c: the brick's voxels inside the level's domain, its child mask, its count.
void checkBrickVoxels(const ChunkPayload& in, const Sections& s, uint64_t n, NodeRead& nd,
                      const std::array<uint32_t, 3>& lim) {
  auto fail = [&](const std::string& what) { in.fail("svo brick " + std::to_string(n) + ": field " + what); };
  uint32_t count = 0;
  uint8_t octants = 0;
  const uint32_t step = 1u << nd.level;
  for (uint32_t w = 0; w < 8; ++w) {
    count += uint32_t(bitCount(nd.bits[w]));
    for (uint64_t word = nd.bits[w]; word; word &= word - 1) {
      const uint32_t b = w * 64 + uint32_t(std::countr_zero(word));
      const uint32_t bx = b & 7, by = (b >> 3) & 7, bz = b >> 6;
      octants |= uint8_t(1u << ((bx >> 2) | ((by >> 2) << 1) | ((bz >> 2) << 2)));
      if (nd.origin[0] + bx * step >= lim[0] || nd.origin[1] + by * step >= lim[1] || nd.origin[2] + bz * step >= lim[2])
        fail("'bitmap': voxel (" + std::to_string(bx) + ", " + std::to_string(by) + ", " + std::to_string(bz) +
             ") of the brick lies outside the level's dims");
    }
  }
  if (count == 0) fail("'bitmap': an empty brick");
  if (!(nd.flags & kSvoNodeFull) && count == 512) fail("'bitmap': all 512 bits set, but the node is not flagged full");
  if (nd.mask != octants)
    in.fail("svo node " + std::to_string(n) + ": field 'child_mask': " + std::to_string(nd.mask) +
            ", the brick's occupied octants are " + std::to_string(octants));
  nd.count = count;
  if (nd.first + uint64_t(count) > s.recordCount)
    fail("'bitmap': the bricks hold more voxels than record_count " + std::to_string(s.recordCount));
}

// Step 2d: the brick's records (classes, colours) and the node's colour flag.
void checkBrickRecords(const ChunkPayload& in, const Sections& s, uint64_t n, const NodeRead& nd) {
  bool anyColor = false;
  for (uint64_t r = nd.first; r < uint64_t(nd.first) + nd.count; ++r) {
    if (s.summary[4 * r] == 0)
      in.fail("field 'summary': record " + std::to_string(r) + " (svo brick " + std::to_string(n) + ") has class 0");
    if (s.hasColor) {
      const uint8_t* c = s.color + 4 * r;
      const std::array<uint8_t, 4> rgba{c[0], c[1], c[2], c[3]};
      if (const char* why = colorProblem(rgba)) in.fail(std::string("field 'color': record ") + std::to_string(r) + ": " + why);
      anyColor |= rgba[3] == 255;
    }
  }
  if (anyColor != bool(nd.flags & kSvoNodeColor))
    in.fail("svo node " + std::to_string(n) + ": field 'flags': the colour bit does not match the brick's colours");
}

// Step 2: every node reachable from the root, its brick and its records; then
// the totals against the counts and the index.
std::vector<NodeRead> readNodeTree(const ChunkPayload& in, const Sections& s) {
  const uint64_t B = s.nodeCount;
  std::vector<NodeRead> nodes(B);
  nodes[0].level = in.header.chunkLog2 - 3u;
  const auto lim = chunkLimits(in.header, in.entry);
  Walk walk;
  for (uint64_t n = 0; n < B; ++n) {
    readNode(in, s, n, nodes, walk);
    readBrickEntry(in, s, n, nodes[n], walk);
    checkBrickVoxels(in, s, n, nodes[n], lim);
    checkBrickRecords(in, s, n, nodes[n]);
    walk.records += nodes[n].count;
    if (nodes[n].level == 0) walk.leafVoxels += nodes[n].count;
  }
  if (walk.nextChild != B)
    in.fail("svo field 'node_count': " + std::to_string(B) + ", the tree has " + std::to_string(walk.nextChild) + " nodes");
  if (walk.bitmapSlot != s.bitmapCount)
    in.fail("svo field 'bitmap_count': " + std::to_string(s.bitmapCount) + ", the bricks store " +
            std::to_string(walk.bitmapSlot));
  if (walk.records != s.recordCount)
    in.fail("svo field 'record_count': " + std::to_string(s.recordCount) + ", the bricks hold " + std::to_string(walk.records));
  if (walk.leafVoxels != in.entry.occupied)
    in.fail("field 'occupied': the index says " + std::to_string(in.entry.occupied) + ", the leaf bricks hold " +
            std::to_string(walk.leafVoxels));
  const uint64_t T = s.recordCount;
  if (s.hasSurface && T % 8 && (s.surface[T / 8] >> (T % 8))) in.fail("field 'surface': padding bits must be 0");
  return nodes;
}

// Step 3: every mip voxel is occupied exactly when one of its 8 children is;
// its surface bit is their OR; it has a colour exactly when one of them has.
void checkMipBricks(const ChunkPayload& in, const Sections& s, const std::vector<NodeRead>& nodes) {
  for (uint64_t n = 0; n < nodes.size(); ++n) {
    const NodeRead& nd = nodes[n];
    if (nd.level == 0) continue;
    std::array<const NodeRead*, 8> kids{};
    for (uint32_t oct = 0, c = nd.ptr; oct < 8; ++oct)
      if (nd.mask >> oct & 1) kids[oct] = &nodes[c++];
    auto fail = [&](const char* field, uint32_t b, const char* why) {
      in.fail("svo brick " + std::to_string(n) + " (mip, level " + std::to_string(nd.level) + "): field " + field +
              ": voxel " + std::to_string(b) + " " + why);
    };
    for (uint32_t b = 0; b < 512; ++b) {
      const uint32_t bx = b & 7, by = (b >> 3) & 7, bz = b >> 6;
      const NodeRead* kid = kids[(bx >> 2) | ((by >> 2) << 1) | ((bz >> 2) << 2)];
      bool any = false, surf = false, col = false;
      if (kid)
        for (uint32_t d = 0; d < 8; ++d) {
          const uint32_t cb = (2 * (bx & 3) + (d & 1)) + 8 * ((2 * (by & 3) + ((d >> 1) & 1)) + 8 * (2 * (bz & 3) + (d >> 2)));
          if (!kid->has(cb)) continue;
          any = true;
          const uint32_t r = kid->recordOf(cb);
          if (s.hasSurface) surf |= bitOf(s.surface, r);
          if (s.hasColor) col |= s.color[4ull * r + 3] == 255;
        }
      if (nd.has(b) != any) fail("'bitmap'", b, "disagrees with the children's occupancy");
      if (!any) continue;
      const uint32_t r = nd.recordOf(b);
      if (s.hasSurface && bitOf(s.surface, r) != surf) fail("'surface'", b, "is not the OR of its children");
      if (s.hasColor && (s.color[4ull * r + 3] == 255) != col) fail("'color'", b, "has a colour exactly when a child has one");
    }
  }
}

// Step 4: the leaf voxels in ascending chunk-local index and, when asked, every
// brick with its voxels.
std::vector<DecodedVoxel> collectVoxels(const ChunkPayload& in, const Sections& s, const std::vector<NodeRead>& nodes,
                                        std::vector<SvoBrick>* bricksOut) {
  const uint32_t C = in.header.chunkSide();
  auto voxelOf = [&](uint32_t index, uint64_t r) {
    DecodedVoxel v;
    v.index = index;
    std::memcpy(v.summary.data(), s.summary + 4 * r, 4);
    if (s.hasColor) std::memcpy(v.color.data(), s.color + 4 * r, 4);
    v.surface = s.hasSurface ? bitOf(s.surface, r) : true;
    return v;
  };
  std::vector<DecodedVoxel> out;
  out.reserve(in.entry.occupied);
  if (bricksOut) bricksOut->clear();
  for (uint64_t n = 0; n < nodes.size(); ++n) {
    const NodeRead& nd = nodes[n];
    SvoBrick* sb = nullptr;
    if (bricksOut) {
      bricksOut->push_back({uint32_t(n), uint8_t(nd.level), nd.mask, nd.flags, nd.ptr, nd.origin, {}});
      sb = &bricksOut->back();
      sb->voxels.reserve(nd.count);
    }
    uint64_t r = nd.first;
    for (uint32_t w = 0; w < 8; ++w)
      for (uint64_t word = nd.bits[w]; word; word &= word - 1, ++r) {
        const uint32_t b = w * 64 + uint32_t(std::countr_zero(word));
        if (sb) sb->voxels.push_back(voxelOf(b, r));
        if (nd.level == 0) {
          const uint32_t x = nd.origin[0] + (b & 7), y = nd.origin[1] + ((b >> 3) & 7), z = nd.origin[2] + (b >> 6);
          out.push_back(voxelOf(x + C * (y + C * z), r));
        }
      }
  }
  std::sort(out.begin(), out.end(), [](const DecodedVoxel& a, const DecodedVoxel& b) { return a.index < b.index; });
  return out;
}

std::vector<DecodedVoxel> decodeSvoTree(const ChunkPayload& in, std::vector<SvoBrick>* bricksOut) {
  const Sections sections = readSections(in);
  const std::vector<NodeRead> nodes = readNodeTree(in, sections);
  checkMipBricks(in, sections, nodes);
  return collectVoxels(in, sections, nodes, bricksOut);
}

}  // namespace

std::vector<DecodedVoxel> decodeSvo(const ChunkPayload& payload) { return decodeSvoTree(payload, nullptr); }

std::vector<SvoBrick> svoBricks(const Reader& reader, size_t i) {
  if (reader.header().layout != Layout::Svo)
    throwBadInput(reader.name() + ": svoBricks: the file has the " + std::string(layoutName(reader.header().layout)) +
                  " layout, not svo");
  std::vector<SvoBrick> bricks;
  decodeSvoTree({reader, i, reader.header(), reader.entries().at(i), reader.payload(i)}, &bricks);
  return bricks;
}

}  // namespace vox::pagefile
