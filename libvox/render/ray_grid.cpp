#include "libvox/render/ray_grid.h"

#include <algorithm>
#include <bit>
#include <climits>

#include "libvox/core/error.h"

namespace vox {

namespace {

uint64_t brickKey(uint32_t bx, uint32_t by, uint32_t bz) {
  return (uint64_t(bx) << 42) | (uint64_t(by) << 21) | uint64_t(bz);
}
void splitKey(uint64_t k, uint32_t& bx, uint32_t& by, uint32_t& bz) {
  bx = uint32_t(k >> 42);
  by = uint32_t((k >> 21) & 0x1fffff);
  bz = uint32_t(k & 0x1fffff);
}

}  // namespace

RayGrid::RayGrid(Dims dims) : dims_(dims) {
  if (dims.x == 0 || dims.y == 0 || dims.z == 0 || dims.maxAxis() > (1u << 20))
    throwUsage("ray grid: dims " + toString(dims) + " must be 1..2^20 per axis");
  topDims_ = {(dims.x + 511) / 512, (dims.y + 511) / 512, (dims.z + 511) / 512};
  const uint64_t topCount = uint64_t(topDims_[0]) * topDims_[1] * topDims_[2];
  if (topCount > (uint64_t(1) << 24))
    throwUsage("ray grid: a " + toString(dims) + " domain needs " + std::to_string(topCount) +
               " top-level cells (limit 2^24, i.e. about 131072 voxels per axis of a cube)");
  top_.assign(size_t(topCount), -1);
}

void RayGrid::addBrick(uint32_t bx, uint32_t by, uint32_t bz, const Mask512& mask) {
  if (finished_) throw Error(ErrorKind::Internal, "RayGrid::addBrick after finish()");
  if (uint64_t(bx) * 8 >= dims_.x || uint64_t(by) * 8 >= dims_.y || uint64_t(bz) * 8 >= dims_.z) return;
  pending_.emplace_back(brickKey(bx, by, bz), mask);
}

void RayGrid::addVoxel(uint32_t u, uint32_t v, uint32_t w) {
  if (finished_) throw Error(ErrorKind::Internal, "RayGrid::addVoxel after finish()");
  if (u >= dims_.x || v >= dims_.y || w >= dims_.z) return;
  const uint64_t key = brickKey(u >> 3, v >> 3, w >> 3);
  if (pending_.empty() || pending_.back().first != key) pending_.emplace_back(key, Mask512{});
  const int bit = bitOf(u & 7, v & 7, w & 7);
  pending_.back().second[bit >> 6] |= uint64_t(1) << (bit & 63);
}

// Grows the occupied box by the voxels of one brick. Within a mask, word x
// holds the voxels of slab x; byte y of a word the row y; bit z of a byte the
// voxel z: so OR-ing the words and then their bytes gives the y and z extents.
void RayGrid::includeInOccupiedBox(uint32_t bx, uint32_t by, uint32_t bz, const Mask512& mask) {
  uint64_t words = 0;
  int xlo = 8, xhi = -1;
  for (int x = 0; x < 8; ++x) {
    if (!mask[size_t(x)]) continue;
    words |= mask[size_t(x)];
    xlo = std::min(xlo, x);
    xhi = x;
  }
  if (xhi < 0) return;
  uint32_t bytes = 0;
  int ylo = 8, yhi = -1;
  for (int y = 0; y < 8; ++y) {
    const uint32_t row = uint32_t((words >> (8 * y)) & 0xff);
    if (!row) continue;
    bytes |= row;
    ylo = std::min(ylo, y);
    yhi = y;
  }
  const int zlo = std::countr_zero(bytes), zhi = 31 - std::countl_zero(bytes);
  const int64_t lo[3] = {int64_t(bx) * 8 + xlo, int64_t(by) * 8 + ylo, int64_t(bz) * 8 + zlo};
  const int64_t hi[3] = {int64_t(bx) * 8 + xhi + 1, int64_t(by) * 8 + yhi + 1, int64_t(bz) * 8 + zhi + 1};
  for (size_t a = 0; a < 3; ++a) {
    if (occupiedEnd_[a] == 0) {  // the first brick
      occupiedMin_[a] = lo[a];
      occupiedEnd_[a] = hi[a];
    } else {
      occupiedMin_[a] = std::min(occupiedMin_[a], lo[a]);
      occupiedEnd_[a] = std::max(occupiedEnd_[a], hi[a]);
    }
  }
}

void RayGrid::finish() {
  if (finished_) throw Error(ErrorKind::Internal, "RayGrid::finish called twice");
  finished_ = true;
  // Sort by (super in top order, region bit, brick bit) so children land in mask order.
  auto sortKey = [&](uint64_t key) {
    uint32_t bx, by, bz;
    splitKey(key, bx, by, bz);
    const uint64_t topIndex =
        (uint64_t(bx >> 6) * topDims_[1] + (by >> 6)) * topDims_[2] + (bz >> 6);
    const uint64_t regionBit = uint64_t(bitOf((bx >> 3) & 7, (by >> 3) & 7, (bz >> 3) & 7));
    const uint64_t brickBit = uint64_t(bitOf(bx & 7, by & 7, bz & 7));
    return (topIndex << 18) | (regionBit << 9) | brickBit;
  };
  std::vector<std::pair<uint64_t, size_t>> order(pending_.size());
  for (size_t i = 0; i < pending_.size(); ++i) order[i] = {sortKey(pending_[i].first), i};
  std::sort(order.begin(), order.end());

  std::vector<uint64_t> brickKeys;  // non-empty bricks, for the distance field
  int32_t curSuper = -1;
  uint64_t curTop = ~uint64_t(0), curRegionKey = ~uint64_t(0), curBrickKey = ~uint64_t(0);
  int32_t curRegion = -1;
  for (const auto& [skey, idx] : order) {
    uint32_t bx, by, bz;
    splitKey(pending_[idx].first, bx, by, bz);
    Mask512 mask = pending_[idx].second;
    // Drop bits outside the domain (partial bricks on the far faces only).
    const bool partial = (bx + 1) * 8 > dims_.x || (by + 1) * 8 > dims_.y || (bz + 1) * 8 > dims_.z;
    for (int b = 0; partial && b < 512; ++b) {
      if (!((mask[b >> 6] >> (b & 63)) & 1)) continue;
      const uint32_t u = bx * 8 + uint32_t(b >> 6), v = by * 8 + uint32_t((b >> 3) & 7), w = bz * 8 + uint32_t(b & 7);
      if (u >= dims_.x || v >= dims_.y || w >= dims_.z) mask[b >> 6] &= ~(uint64_t(1) << (b & 63));
    }
    bool any = false;
    for (uint64_t m : mask) any |= m != 0;
    if (!any) continue;
    includeInOccupiedBox(bx, by, bz, mask);
    if (skey == curBrickKey) {  // the same brick again: OR
      for (int i = 0; i < 8; ++i) bricks_.back()[i] |= mask[i];
      continue;
    }
    const uint64_t topIndex = skey >> 18;
    if (topIndex != curTop) {
      curTop = topIndex;
      curSuper = int32_t(supers_.size());
      supers_.emplace_back();
      supers_.back().base = uint32_t(regions_.size());
      top_[size_t(topIndex)] = curSuper;
      curRegionKey = ~uint64_t(0);
    }
    const uint64_t regionKey = skey >> 9;
    if (regionKey != curRegionKey) {
      curRegionKey = regionKey;
      const int rbit = int((skey >> 9) & 511);
      supers_[size_t(curSuper)].mask[rbit >> 6] |= uint64_t(1) << (rbit & 63);
      curRegion = int32_t(regions_.size());
      regions_.emplace_back();
      regions_.back().base = uint32_t(bricks_.size());
    }
    const int bbit = int(skey & 511);
    regions_[size_t(curRegion)].mask[bbit >> 6] |= uint64_t(1) << (bbit & 63);
    bricks_.push_back(mask);
    brickKeys.push_back(pending_[idx].first);
    curBrickKey = skey;
  }
  pending_.clear();
  pending_.shrink_to_fit();
  auto prefixes = [](std::vector<Node>& nodes) {
    for (Node& n : nodes) {
      uint32_t sum = 0;
      for (int i = 0; i < 8; ++i) {
        n.prefix[size_t(i)] = uint16_t(sum);
        sum += uint32_t(bitCount(n.mask[size_t(i)]));
      }
    }
  };
  prefixes(supers_);
  prefixes(regions_);
  buildDistanceField(brickKeys);
  buildBrickSlots();
  if (!brickKeys.empty()) {
    std::array<int64_t, 3> lo{INT64_MAX, INT64_MAX, INT64_MAX}, hi{-1, -1, -1};
    for (uint64_t key : brickKeys) {
      uint32_t b[3];
      splitKey(key, b[0], b[1], b[2]);
      for (int a = 0; a < 3; ++a) {
        lo[size_t(a)] = std::min<int64_t>(lo[size_t(a)], b[a]);
        hi[size_t(a)] = std::max<int64_t>(hi[size_t(a)], b[a]);
      }
    }
    const int64_t n[3] = {dims_.x, dims_.y, dims_.z};
    for (int a = 0; a < 3; ++a) {
      contentMin_[size_t(a)] = lo[size_t(a)] * 8;
      contentEnd_[size_t(a)] = std::min<int64_t>((hi[size_t(a)] + 1) * 8, n[a]);
    }
  }
  occupied_ = 0;
  for (const Mask512& b : bricks_)
    for (uint64_t m : b) occupied_ += uint64_t(bitCount(m));
}

void RayGrid::buildDistanceField(const std::vector<uint64_t>& brickKeys) {
  brickDims_ = {(dims_.x + 7) / 8, (dims_.y + 7) / 8, (dims_.z + 7) / 8};
  const size_t nx = brickDims_[0] + 2, ny = brickDims_[1] + 2, nz = brickDims_[2] + 2;
  if (uint64_t(brickDims_[0]) * brickDims_[1] * brickDims_[2] > (uint64_t(1) << 24)) return;
  // Chessboard distance by two raster passes over the 26-neighbourhood (each
  // pass takes the 13 neighbours already visited), exact for the L-infinity
  // metric; the padding ring stays 255 (far) so no bounds checks are needed.
  brickDist_.assign(nx * ny * nz, 255);
  for (uint64_t key : brickKeys) {
    uint32_t bx, by, bz;
    splitKey(key, bx, by, bz);
    brickDist_[(size_t(bx + 1) * ny + (by + 1)) * nz + (bz + 1)] = 0;
  }
  uint8_t* d = brickDist_.data();
  const ptrdiff_t sx = ptrdiff_t(ny * nz), sy = ptrdiff_t(nz);
  std::vector<ptrdiff_t> before;  // offsets of the 13 neighbours earlier in raster order, minus the z-1 one
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz) {
        const ptrdiff_t off = dx * sx + dy * sy + dz;
        if (off < 0 && off != -1) before.push_back(off);
      }
  // Per row: the 12 neighbours in other rows (already final in this pass) in
  // loops over z that compilers vectorise, then the z-1 (or z+1) neighbour in
  // a sequential scan.
  std::vector<uint8_t> m(nz);
  auto pass = [&](int dir) {
    for (size_t xi = 1; xi + 1 < nx; ++xi) {
      const size_t x = dir > 0 ? xi : nx - 1 - xi;
      for (size_t yi = 1; yi + 1 < ny; ++yi) {
        const size_t y = dir > 0 ? yi : ny - 1 - yi;
        uint8_t* row = d + x * size_t(sx) + y * size_t(sy);
        for (size_t z = 0; z < nz; ++z) m[z] = row[z];
        for (ptrdiff_t off : before) {
          const uint8_t* nb = row + dir * off;
          for (size_t z = 1; z + 1 < nz; ++z) {
            const uint8_t v = uint8_t(nb[z] + (nb[z] != 255));  // +1, saturating at 255
            m[z] = m[z] < v ? m[z] : v;
          }
        }
        for (size_t z = 1; z + 1 < nz; ++z) row[z] = m[z];
        if (dir > 0)
          for (size_t z = 1; z + 1 < nz; ++z) row[z] = uint8_t(std::min<int>(row[z], row[z - 1] + 1));
        else
          for (size_t z = nz - 2; z >= 1; --z) row[z] = uint8_t(std::min<int>(row[z], row[z + 1] + 1));
      }
    }
  };
  pass(+1);
  pass(-1);
  // The padding ring was a stand-in for "far": it holds no brick, and is read
  // by nobody (queries are for bricks inside the domain).
}

int RayGrid::probe(int64_t u, int64_t v, int64_t w, const Mask512** brick) const {
  if (u < 0 || v < 0 || w < 0 || u >= int64_t(dims_.x) || v >= int64_t(dims_.y) || w >= int64_t(dims_.z)) return 3;
  const int32_t s = top_[(size_t(u >> 9) * topDims_[1] + size_t(v >> 9)) * topDims_[2] + size_t(w >> 9)];
  if (s < 0) return 3;
  const Node& sn = supers_[size_t(s)];
  const int rbit = bitOf(uint32_t(u >> 6) & 7, uint32_t(v >> 6) & 7, uint32_t(w >> 6) & 7);
  if (!sn.has(rbit)) return 2;
  const Node& rn = regions_[sn.child(rbit)];
  const int bbit = bitOf(uint32_t(u >> 3) & 7, uint32_t(v >> 3) & 7, uint32_t(w >> 3) & 7);
  if (!rn.has(bbit)) return 1;
  *brick = &bricks_[rn.child(bbit)];
  return 0;
}

bool RayGrid::occupied(int64_t u, int64_t v, int64_t w) const {
  const Mask512* b = nullptr;
  if (probe(u, v, w, &b) != 0) return false;
  const int bit = bitOf(uint32_t(u & 7), uint32_t(v & 7), uint32_t(w & 7));
  return ((*b)[size_t(bit >> 6)] >> (bit & 63)) & 1;
}

size_t RayGrid::memoryBytes() const {
  return top_.size() * sizeof(int32_t) + (supers_.size() + regions_.size()) * sizeof(Node) +
         bricks_.size() * sizeof(Mask512) + brickDist_.size() + brickSlot_.size() * sizeof(int32_t);
}

void RayGrid::buildBrickSlots() {
  const uint64_t count = uint64_t(brickDims_[0]) * brickDims_[1] * brickDims_[2];
  if (count > kMaxBrickSlots) return;
  brickSlot_.assign(size_t(count), -3);
  // Fills the bricks of the box [lo, lo + n) (clipped to the domain) with `value`.
  auto fill = [&](const uint32_t lo[3], uint32_t n, int32_t value) {
    const uint32_t hx = std::min(lo[0] + n, brickDims_[0]), hy = std::min(lo[1] + n, brickDims_[1]),
                   hz = std::min(lo[2] + n, brickDims_[2]);
    for (uint32_t x = lo[0]; x < hx; ++x)
      for (uint32_t y = lo[1]; y < hy; ++y) {
        int32_t* row = brickSlot_.data() + (size_t(x) * brickDims_[1] + y) * brickDims_[2];
        std::fill(row + lo[2], row + hz, value);
      }
  };
  for (uint32_t tx = 0; tx < topDims_[0]; ++tx)
    for (uint32_t ty = 0; ty < topDims_[1]; ++ty)
      for (uint32_t tz = 0; tz < topDims_[2]; ++tz) {
        const int32_t s = top_[(size_t(tx) * topDims_[1] + ty) * topDims_[2] + tz];
        if (s < 0) continue;
        const uint32_t superLo[3] = {tx * 64, ty * 64, tz * 64};
        fill(superLo, 64, -2);
        const Node& sn = supers_[size_t(s)];
        for (int rb = 0; rb < 512; ++rb) {
          if (!sn.has(rb)) continue;
          const uint32_t regionLo[3] = {superLo[0] + uint32_t(rb >> 6) * 8, superLo[1] + uint32_t((rb >> 3) & 7) * 8,
                                        superLo[2] + uint32_t(rb & 7) * 8};
          fill(regionLo, 8, -1);
          const Node& rn = regions_[sn.child(rb)];
          for (int bb = 0; bb < 512; ++bb) {
            if (!rn.has(bb)) continue;
            const size_t x = regionLo[0] + uint32_t(bb >> 6), y = regionLo[1] + uint32_t((bb >> 3) & 7),
                         z = regionLo[2] + uint32_t(bb & 7);
            brickSlot_[(x * brickDims_[1] + y) * brickDims_[2] + z] = int32_t(rn.child(bb));
          }
        }
      }
}

std::vector<Coord3> RayGrid::occupiedVoxels() const {
  std::vector<Coord3> voxels;
  voxels.reserve(size_t(occupied_));
  forEachOccupied([&](uint32_t u, uint32_t v, uint32_t w) { voxels.push_back({int32_t(u), int32_t(v), int32_t(w)}); });
  return voxels;
}

void RayGrid::forEachOccupied(const std::function<void(uint32_t, uint32_t, uint32_t)>& fn) const {
  for (uint32_t tx = 0; tx < topDims_[0]; ++tx)
    for (uint32_t ty = 0; ty < topDims_[1]; ++ty)
      for (uint32_t tz = 0; tz < topDims_[2]; ++tz) {
        const int32_t s = top_[(size_t(tx) * topDims_[1] + ty) * topDims_[2] + tz];
        if (s < 0) continue;
        const Node& sn = supers_[size_t(s)];
        for (int rb = 0; rb < 512; ++rb) {
          if (!sn.has(rb)) continue;
          const Node& rn = regions_[sn.child(rb)];
          for (int bb = 0; bb < 512; ++bb) {
            if (!rn.has(bb)) continue;
            const Mask512& m = bricks_[rn.child(bb)];
            const uint32_t bx = tx * 64 + uint32_t(rb >> 6) * 8 + uint32_t(bb >> 6);
            const uint32_t by = ty * 64 + uint32_t((rb >> 3) & 7) * 8 + uint32_t((bb >> 3) & 7);
            const uint32_t bz = tz * 64 + uint32_t(rb & 7) * 8 + uint32_t(bb & 7);
            for (int b = 0; b < 512; ++b)
              if ((m[size_t(b >> 6)] >> (b & 63)) & 1)
                fn(bx * 8 + uint32_t(b >> 6), by * 8 + uint32_t((b >> 3) & 7), bz * 8 + uint32_t(b & 7));
          }
        }
      }
}

}  // namespace vox
