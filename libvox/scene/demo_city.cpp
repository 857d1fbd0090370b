#include "libvox/scene/demo_city.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "libvox/core/error.h"
#include "libvox/core/parallel.h"

namespace vox {

namespace {

enum Cls : uint8_t { kEmpty = 0, kGrass = 1, kDirt = 2, kStone = 3, kPlank = 4, kSnow = 5, kSand = 6, kWater = 7 };

// Every length is in voxels (kCityVoxelSize = 0.5 m each).
constexpr int32_t kGroundTop = 8;  // the ground slab is v in [0, 8): Dirt, then the surface layer at v = 7
constexpr int32_t kPitch = 192;    // street grid period along x and z (96 m)
constexpr int32_t kStreet = 32;    // street corridor at local [0, 32): sidewalk 6, road 20, sidewalk 6
constexpr int32_t kSidewalk = 6;
constexpr int32_t kRoadCentre = 16;
constexpr int32_t kStorey = 6;   // 3 m
constexpr int32_t kParapet = 2;  // walls stand 1 m above the roof slab
constexpr int32_t kWindowLo = 2, kWindowHi = 5;  // window rows within a storey (1.5 m high)
// Rivers run along z, one every kRiverSpacing voxels of x (the first at
// kRiverFirst), meandering by up to kRiverMeander between control points
// kRiverStep apart; water where |u - centre(w)| < kRiverHalfWidth.
constexpr int32_t kRiverSpacing = 4096, kRiverFirst = 640, kRiverStep = 256, kRiverMeander = 96,
                  kRiverHalfWidth = 24;
constexpr int32_t kRiverBed = 2, kRiverWaterTop = 6;  // sand [0, 2), water [2, 6), air above; bridge decks at v = 7
constexpr int32_t kPondBed = 3, kPondWaterTop = 7;
constexpr int32_t kTreeCell = 20;  // one tree at most per 20 x 20 cell of a park
constexpr int32_t kParkPathHalf = 3;

enum Salt : uint32_t { kSaltVoxel = 1, kSaltRiver, kSaltBlock, kSaltCut, kSaltLot, kSaltPark, kSaltTree };

uint32_t hashOf(int64_t a, int64_t b, int64_t c, uint32_t salt) {
  uint64_t x = uint64_t(a) * 0x9e3779b97f4a7c15ull ^ uint64_t(b) * 0xc2b2ae3d27d4eb4full ^
               uint64_t(c) * 0x165667b19e3779f9ull ^ (uint64_t(salt) + 1) * 0xd6e8feb86659fd93ull;
  x ^= x >> 32;
  x *= 0xd6e8feb86659fd93ull;
  x ^= x >> 32;
  x *= 0xd6e8feb86659fd93ull;
  x ^= x >> 32;
  return uint32_t(x);
}

int64_t floorDiv(int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

// ---------------------------------------------------------------- rivers

int32_t riverOffset(int64_t river, int64_t step) {
  return int32_t(hashOf(river, step, 0, kSaltRiver) % uint32_t(2 * kRiverMeander + 1)) - kRiverMeander;
}

/// x of river `river`'s centre line at z = w: piecewise linear between hashed control points.
int32_t riverCentre(int64_t river, int32_t w) {
  const int64_t j = floorDiv(w, kRiverStep), t = w - j * kRiverStep;
  const int64_t mix = (int64_t(riverOffset(river, j)) * (kRiverStep - t) + int64_t(riverOffset(river, j + 1)) * t);
  return int32_t(kRiverFirst + river * kRiverSpacing + floorDiv(mix, kRiverStep));
}

int64_t nearestRiver(int64_t u) { return floorDiv(u - kRiverFirst + kRiverSpacing / 2, kRiverSpacing); }

bool inRiver(int32_t u, int32_t w) {
  return std::abs(u - riverCentre(nearestRiver(u), w)) < kRiverHalfWidth;
}

/// True when the columns [u0, u1) x [w0, w1) come within `margin` of a river's water.
bool nearRiver(int32_t u0, int32_t u1, int32_t w0, int32_t w1, int32_t margin) {
  for (int64_t k = nearestRiver((int64_t(u0) + u1) / 2) - 1, kEnd = k + 3; k < kEnd; ++k) {
    // The centre line is linear between control points: its range over [w0, w1)
    // is spanned by the ends and the control points inside.
    int32_t lo = std::min(riverCentre(k, w0), riverCentre(k, w1 - 1)), hi = std::max(riverCentre(k, w0), riverCentre(k, w1 - 1));
    for (int64_t j = floorDiv(w0, kRiverStep) + 1; j * kRiverStep < w1; ++j) {
      const int32_t c = riverCentre(k, int32_t(j * kRiverStep));
      lo = std::min(lo, c), hi = std::max(hi, c);
    }
    // Water columns: centre - (halfWidth - 1) .. centre + (halfWidth - 1).
    if (int64_t(u0) - margin <= int64_t(hi) + kRiverHalfWidth - 1 &&
        int64_t(u1) - 1 + margin >= int64_t(lo) - kRiverHalfWidth + 1)
      return true;
  }
  return false;
}

// ---------------------------------------------------------------- one column

enum Upper : uint8_t { kNoUpper, kWall, kInterior, kTree };

/// Everything about the column (u, w) that its voxels need, computed from the
/// integer coordinates alone.
struct Column {
  int32_t top = 0;  // v >= top is empty (already clipped to the domain's height)
  // The ground: up to four layers from v = 0 up, layer i ending below
  // layerTop[i] (a kEmpty layer is the air under a bridge's deck).
  uint8_t layers = 0;
  int32_t layerTop[4]{};
  Cls layerCls[4]{};
  Cls groundTop = kGrass;  // what the ground's Dirt is confused with
  // Above the ground: a building's wall or interior, or a tree.
  Upper upper = kNoUpper;
  Cls cls = kEmpty, cls2 = kEmpty;  // wall | floor + roof | trunk + canopy
  bool windows = false;             // wall: this column has a window in every storey
  int32_t roofV = 0;                // building: the roof slab's v
  int32_t stride = kStorey;         // interior: floor slabs every `stride` from kGroundTop
  int32_t trunkTop = 0, canopyLo = 0, canopyHi = -1;  // tree: trunk [kGroundTop, trunkTop), canopy [lo, hi]
  int32_t streetDistance = 0;       // to the nearest street centre line (observation counts)

  void addLayer(int32_t v1, Cls c) {
    layerTop[layers] = v1;
    layerCls[layers] = c;
    ++layers;
  }
};

/// The class at height v (kEmpty when empty).
inline Cls classAt(const Column& c, int32_t v) {
  if (v < 0 || v >= c.top) return kEmpty;
  for (int i = 0; i < c.layers; ++i)
    if (v < c.layerTop[i]) return c.layerCls[i];
  if (v < kGroundTop) return kEmpty;  // a river's or pond's air
  switch (c.upper) {
    case kWall:
      if (c.windows && v < c.roofV) {
        const int32_t r = (v - kGroundTop) % kStorey;
        if (r >= kWindowLo && r < kWindowHi) return kEmpty;
      }
      return c.cls;
    case kInterior:
      if (v == c.roofV) return c.cls2;
      return v < c.roofV && (v - kGroundTop) % c.stride == 0 ? c.cls : kEmpty;
    case kTree:
      if (v < c.trunkTop) return c.cls;
      return v >= c.canopyLo && v <= c.canopyHi ? c.cls2 : kEmpty;
    default: return kEmpty;
  }
}

constexpr int32_t kNone = std::numeric_limits<int32_t>::max();

/// The smallest occupied v' >= v of the column, or kNone: jumps over air and
/// hollow interiors in constant time.
inline int32_t nextOccupied(const Column& c, int32_t v) {
  v = std::max(v, 0);
  if (v >= c.top) return kNone;
  for (int i = 0; i < c.layers; ++i)
    if (v < c.layerTop[i]) {
      if (c.layerCls[i] != kEmpty) return v;
      v = c.layerTop[i];
    }
  if (v >= c.top) return kNone;
  v = std::max(v, kGroundTop);
  if (v >= c.top) return kNone;
  switch (c.upper) {
    case kWall:
      if (c.windows && v < c.roofV) {
        const int32_t r = (v - kGroundTop) % kStorey;
        if (r >= kWindowLo && r < kWindowHi) v += kWindowHi - r;
      }
      return v < c.top ? v : kNone;
    case kInterior: {
      if (v >= c.roofV) return v == c.roofV ? v : kNone;
      const int32_t k = (v - kGroundTop + c.stride - 1) / c.stride;
      return std::min(kGroundTop + k * c.stride, c.roofV);
    }
    case kTree:
      if (v < c.trunkTop) return v;
      v = std::max(v, c.canopyLo);
      return v <= c.canopyHi && v < c.top ? v : kNone;
    default: return kNone;
  }
}

/// The fixed facts of one city (from its extent).
struct World {
  int32_t X, Y, Z;
  int32_t maxStoreys;  // the tallest building that fits under Y (roof, parapet)
};

int32_t isqrt(int64_t n) {
  int64_t r = int64_t(std::sqrt(double(n)));
  while (r * r > n) --r;
  while ((r + 1) * (r + 1) <= n) ++r;
  return int32_t(r);
}

/// Building parameters of lot (i, j) of street block (bx, bz): a pure function
/// of those integers (and of the world's height cap).
struct Lot {
  int32_t x0, x1, z0, z1;  // lot bounds (world columns)
  bool building = false;
  int32_t fx0, fx1, fz0, fz1;  // footprint
  int32_t storeys = 0, roofV = 0, top = 0, stride = kStorey;
  Cls wall = kStone, floor = kPlank, roof = kStone, yard = kGrass;
  int32_t windowPeriod = 5, windowWidth = 2;
};

/// Lot cuts of a street block along one axis: 1..3 lots, boundaries jittered.
int32_t lotCount(int64_t bx, int64_t bz, int axis) { return 1 + int32_t(hashOf(bx, bz, axis, kSaltCut) % 3); }
int32_t lotCut(int64_t bx, int64_t bz, int axis, int32_t i, int32_t n) {
  if (i <= 0) return kStreet;
  if (i >= n) return kPitch;
  const int32_t jitter = int32_t(hashOf(bx, bz, axis * 8 + i, kSaltCut) % 25) - 12;
  return kStreet + (kPitch - kStreet) * i / n + jitter;
}

uint32_t lotHash(int64_t bx, int64_t bz, int32_t i, int32_t j) { return hashOf(bx, bz, i * 4 + j, kSaltLot); }

/// Storeys of a lot's building from the lot's hash: mostly low houses, some
/// mid-rise blocks, a few towers (kMaxStoreys at most); capped by the height.
constexpr int32_t kMaxStoreys = 60;
int32_t lotStoreys(const World& world, uint32_t h) {
  const uint32_t r = (h >> 5) % 1000;
  const int32_t storeys = r < 600 ? 2 + int32_t(r % 5) : r < 920 ? 7 + int32_t(r % 14) : 21 + int32_t(r % 40);
  return std::min(storeys, world.maxStoreys);
}

Lot lotAt(const World& world, int64_t bx, int64_t bz, int32_t lx, int32_t lz) {
  const int32_t nx = lotCount(bx, bz, 0), nz = lotCount(bx, bz, 1);
  int32_t i = 0, j = 0;
  while (i + 1 < nx && lx >= lotCut(bx, bz, 0, i + 1, nx)) ++i;
  while (j + 1 < nz && lz >= lotCut(bx, bz, 1, j + 1, nz)) ++j;
  Lot lot;
  const int32_t baseX = int32_t(bx * kPitch), baseZ = int32_t(bz * kPitch);
  lot.x0 = baseX + lotCut(bx, bz, 0, i, nx);
  lot.x1 = baseX + lotCut(bx, bz, 0, i + 1, nx);
  lot.z0 = baseZ + lotCut(bx, bz, 1, j, nz);
  lot.z1 = baseZ + lotCut(bx, bz, 1, j + 1, nz);
  const uint32_t h = lotHash(bx, bz, i, j), h2 = hashOf(bx, bz, i * 4 + j, kSaltLot + 100);
  lot.yard = h % 3 == 2 ? kSand : kGrass;
  const int32_t setback = 2 + int32_t((h >> 2) % 4);
  lot.fx0 = lot.x0 + setback, lot.fx1 = lot.x1 - setback, lot.fz0 = lot.z0 + setback, lot.fz1 = lot.z1 - setback;
  const int32_t storeys = lotStoreys(world, h);
  lot.building = storeys >= 1 && lot.fx1 - lot.fx0 >= 10 && lot.fz1 - lot.fz0 >= 10 &&
                 !nearRiver(lot.fx0, lot.fx1, lot.fz0, lot.fz1, 3);
  if (!lot.building) return lot;
  lot.storeys = storeys;
  lot.roofV = kGroundTop + storeys * kStorey;
  lot.top = lot.roofV + 1 + kParapet;
  lot.stride = kStorey * (1 + int32_t(h2 % 3));  // a floor slab every 1, 2 or 3 storeys
  const uint32_t m = (h2 >> 2) % 5;
  lot.wall = m == 0 && storeys <= 6 ? kPlank : m == 1 ? kSand : kStone;  // wooden houses, sandstone, concrete
  lot.floor = storeys <= 6 ? kPlank : kStone;
  const uint32_t roof = (h2 >> 5) % 20;
  lot.roof = roof < 8 ? kStone : roof < 12 ? kSnow : roof < 16 ? kGrass : kPlank;
  lot.windowPeriod = 4 + int32_t((h2 >> 10) % 5);
  lot.windowWidth = std::min(lot.windowPeriod - 1, 2 + int32_t((h2 >> 13) % 2));
  return lot;
}

/// A park's pond: an ellipse around the block's middle, in some parks.
struct Pond {
  bool present = false;
  int32_t cx = 0, cz = 0, ra = 1, rb = 1;  // world columns
  bool contains(int32_t u, int32_t w) const {
    const int64_t dx = u - cx, dz = w - cz;
    return present && dx * dx * rb * rb + dz * dz * ra * ra < int64_t(ra) * ra * rb * rb;
  }
};

Pond pondOf(int64_t bx, int64_t bz) {
  Pond p;
  const uint32_t h = hashOf(bx, bz, 1, kSaltPark);
  p.ra = 22 + int32_t((h >> 4) % 16);
  p.rb = 14 + int32_t((h >> 8) % 14);
  p.cx = int32_t(bx * kPitch) + (kStreet + kPitch) / 2 + int32_t((h >> 12) % 21) - 10;
  p.cz = int32_t(bz * kPitch) + (kStreet + kPitch) / 2 + int32_t((h >> 17) % 21) - 10;
  p.present = h % 3 == 0 && !nearRiver(p.cx - p.ra, p.cx + p.ra + 1, p.cz - p.rb, p.cz + p.rb + 1, 2);
  return p;
}

bool onParkPath(int64_t bx, int64_t bz, int32_t u, int32_t w) {
  const int32_t mid = (kStreet + kPitch) / 2;
  return std::abs(u - int32_t(bx * kPitch) - mid) < kParkPathHalf || std::abs(w - int32_t(bz * kPitch) - mid) < kParkPathHalf;
}

/// The tree of one park cell, if any.
struct Tree {
  bool present = false;
  int32_t cx = 0, cz = 0, radius = 0, trunkTop = 0, canopyCentre = 0;
};

// The tallest tree: trunk 6 + 7 above the ground, canopy radius 7 around
// trunkTop + radius - 2.
constexpr int32_t kTreeTopBound = kGroundTop + 6 + 7 + 7 - 2 + 7 + 1;

Tree treeOf(int64_t bx, int64_t bz, int32_t ci, int32_t cj, const Pond& pond) {
  Tree t;
  const uint32_t h = hashOf(bx * 16 + ci, bz * 16 + cj, 0, kSaltTree);
  if (h % 100 >= 62) return t;
  t.cx = int32_t(bx * kPitch) + kStreet + ci * kTreeCell + 8 + int32_t((h >> 7) % 4);
  t.cz = int32_t(bz * kPitch) + kStreet + cj * kTreeCell + 8 + int32_t((h >> 9) % 4);
  t.radius = 4 + int32_t((h >> 11) % 4);
  t.trunkTop = kGroundTop + 6 + int32_t((h >> 13) % 8);
  t.canopyCentre = t.trunkTop + t.radius - 2;
  const int32_t r = t.radius, mid = (kStreet + kPitch) / 2;
  const int32_t lx = t.cx - int32_t(bx * kPitch), lz = t.cz - int32_t(bz * kPitch);
  const bool onPath = std::abs(lx - mid) < r + kParkPathHalf + 1 || std::abs(lz - mid) < r + kParkPathHalf + 1;
  const bool inPond = pond.present && t.cx + r >= pond.cx - pond.ra - 1 && t.cx - r <= pond.cx + pond.ra + 1 &&
                      t.cz + r >= pond.cz - pond.rb - 1 && t.cz - r <= pond.cz + pond.rb + 1;
  t.present = !onPath && !inPond && !nearRiver(t.cx - r, t.cx + r + 1, t.cz - r, t.cz + r + 1, 2);
  return t;
}

Column columnAt(const World& world, int32_t u, int32_t w) {
  Column c;
  if (u < 0 || w < 0 || u >= world.X || w >= world.Z) return c;  // outside: empty
  const int64_t bx = floorDiv(u, kPitch), bz = floorDiv(w, kPitch);
  const int32_t lx = int32_t(u - bx * kPitch), lz = int32_t(w - bz * kPitch);
  {
    const int32_t dx = std::abs(lx - kRoadCentre), dz = std::abs(lz - kRoadCentre);
    c.streetDistance = std::min(std::min(dx, kPitch - dx), std::min(dz, kPitch - dz));
  }
  const bool streetX = lz < kStreet, streetZ = lx < kStreet;  // streets running along x / along z
  auto clip = [&](int32_t top) { c.top = std::min(top, world.Y); };

  // Streets: road (Stone, dashed Snow centre lines) between sidewalks (Sand).
  Cls street = kEmpty;
  if (streetX || streetZ) {
    const bool roadZ = streetZ && lx >= kSidewalk && lx < kStreet - kSidewalk;
    const bool roadX = streetX && lz >= kSidewalk && lz < kStreet - kSidewalk;
    street = roadX || roadZ ? kStone : kSand;
    const bool lineZ = streetZ && !streetX && (lx == kRoadCentre - 1 || lx == kRoadCentre) && (w / 8) % 2 == 0;
    const bool lineX = streetX && !streetZ && (lz == kRoadCentre - 1 || lz == kRoadCentre) && (u / 8) % 2 == 0;
    if (lineZ || lineX) street = kSnow;
  }

  // Rivers cut through everything; streets along x cross them on bridges.
  if (inRiver(u, w)) {
    c.addLayer(kRiverBed, kSand);
    c.addLayer(kRiverWaterTop, kWater);
    c.groundTop = kSand;
    if (streetX) {  // a bridge: the deck at v = kGroundTop - 1 over an air gap
      c.addLayer(kGroundTop - 1, kEmpty);
      c.addLayer(kGroundTop, street);
      clip(kGroundTop);
    } else {
      clip(kRiverWaterTop);
    }
    return c;
  }

  const auto groundWith = [&](Cls top) {
    c.addLayer(kGroundTop - 1, kDirt);
    c.addLayer(kGroundTop, top);
    c.groundTop = top;
    clip(kGroundTop);
  };
  if (street != kEmpty) {
    groundWith(street);
    return c;
  }

  const bool park = hashOf(bx, bz, 0, kSaltBlock) % 100 < 14;
  if (park) {
    const Pond pond = pondOf(bx, bz);
    if (pond.contains(u, w)) {
      c.addLayer(kPondBed, kSand);
      c.addLayer(kPondWaterTop, kWater);
      c.groundTop = kSand;
      clip(kPondWaterTop);
      return c;
    }
    groundWith(onParkPath(bx, bz, u, w) ? kSand : kGrass);
    const int32_t ci = (lx - kStreet) / kTreeCell, cj = (lz - kStreet) / kTreeCell;
    const Tree t = treeOf(bx, bz, ci, cj, pond);
    if (!t.present) return c;
    const int32_t dx = u - t.cx, dz = w - t.cz;
    const bool trunk = (dx == 0 || dx == -1) && (dz == 0 || dz == -1);
    const int64_t rem = int64_t(t.radius) * t.radius - int64_t(dx) * dx - int64_t(dz) * dz;
    if (!trunk && rem < 0) return c;
    c.upper = kTree;
    c.cls = kPlank;
    c.cls2 = kGrass;
    c.trunkTop = trunk ? t.canopyCentre : kGroundTop;
    if (rem >= 0) {
      const int32_t half = isqrt(rem);
      c.canopyLo = t.canopyCentre - half;
      c.canopyHi = t.canopyCentre + half;
    }
    clip(std::max(c.trunkTop, c.canopyHi + 1));
    return c;
  }

  const Lot lot = lotAt(world, bx, bz, lx, lz);
  const bool inFootprint = lot.building && u >= lot.fx0 && u < lot.fx1 && w >= lot.fz0 && w < lot.fz1;
  groundWith(lot.yard);
  if (!inFootprint) return c;
  c.roofV = lot.roofV;
  const bool faceX = u == lot.fx0 || u == lot.fx1 - 1, faceZ = w == lot.fz0 || w == lot.fz1 - 1;
  if (faceX || faceZ) {
    c.upper = kWall;
    c.cls = lot.wall;
    if (faceX != faceZ) {  // corners stay solid
      const int32_t along = faceX ? w - lot.fz0 : u - lot.fx0, length = faceX ? lot.fz1 - lot.fz0 : lot.fx1 - lot.fx0;
      c.windows = along >= 2 && along < length - 2 && (along - 2) % lot.windowPeriod < lot.windowWidth;
    }
    clip(lot.top);
  } else {
    c.upper = kInterior;
    c.cls = lot.floor;
    c.cls2 = lot.roof;
    c.stride = lot.stride;
    clip(lot.roofV + 1);
  }
  return c;
}

// ---------------------------------------------------------------- votes

/// The class a confused observer mistakes `c` at height v for. In the ground
/// the confusions stay among the ground's own classes (Dirt with the surface
/// layer above it, a road's Stone with Dirt), which also keeps a ground block
/// to two or three vote blocks.
Cls confusedWith(Cls c, int32_t v, const Column& col) {
  switch (c) {
    case kGrass: return kDirt;
    case kDirt: return col.groundTop == kDirt ? kGrass : col.groundTop;
    case kStone: return v < kGroundTop ? kDirt : kPlank;
    case kPlank: return kStone;
    case kSnow: return kStone;
    case kSand: return kDirt;
    case kWater: return kSand;
    default: return kEmpty;
  }
}

inline void emitVoxel(int32_t u, int32_t v, int32_t w, Cls c, const Column& col, bool surface, VoxelBlocks& out) {
  const uint32_t h = hashOf(u, v, w, kSaltVoxel);
  // Observation counts: the "camera" drove the streets, and saw higher voxels
  // more often (fewer occluders), from 1 to ~600.
  const int32_t near = kPitch / 2 - col.streetDistance;
  const uint32_t main = 1 + h % 97 + uint32_t(300 * near * near / ((kPitch / 2) * (kPitch / 2))) +
                        uint32_t(std::min(v, 600) / 3);
  const Coord3 at{u, v, w};
  out.addVotes(at, c, main, surface);
  // A quarter of the voxels are contested by a plausible confusion; an eighth
  // of those are exact ties (margin 0, lowest id wins).
  if (((h >> 8) & 3) == 0) {
    const uint32_t contest = ((h >> 10) & 7) == 0 ? main : (h >> 16) % (main + 1);
    out.addVotes(at, confusedWith(c, v, col), contest, surface);
  }
}

// ---------------------------------------------------------------- tiles

constexpr int32_t kTile = kBlockDim;  // a tile is one 8^3 block column: no block is shared by two tiles

/// The box clipped to the domain (may be empty).
IndexBox clipToDomain(const IndexBox& box, const World& world) {
  IndexBox b = box;
  b.min = {std::max(b.min.u, 0), std::max(b.min.v, 0), std::max(b.min.w, 0)};
  b.max = {std::min(b.max.u, world.X - 1), std::min(b.max.v, world.Y - 1), std::min(b.max.w, world.Z - 1)};
  return b;
}

/// An upper bound of the occupied heights in street block (bx, bz): its
/// tallest lot's building (rivers only take buildings away) or its tallest
/// possible tree; computed from the block's hashes, not its columns.
int32_t streetBlockTop(const World& world, int64_t bx, int64_t bz) {
  int32_t top = kGroundTop;
  if (hashOf(bx, bz, 0, kSaltBlock) % 100 < 14) {
    top = kTreeTopBound;
  } else {
    int32_t storeys = 0;
    for (int32_t i = 0, nx = lotCount(bx, bz, 0); i < nx; ++i)
      for (int32_t j = 0, nz = lotCount(bx, bz, 1); j < nz; ++j)
        storeys = std::max(storeys, lotStoreys(world, lotHash(bx, bz, i, j)));
    if (storeys >= 1) top = kGroundTop + storeys * kStorey + 1 + kParapet;
  }
  return std::min(top, world.Y);
}

/// streetBlockTop() of the last few street blocks asked for (consecutive
/// tiles share them: a street block holds 24 x 24 tiles).
class StreetBlockTops {
 public:
  explicit StreetBlockTops(const World& world) : world_(world) {}
  int32_t operator()(int64_t bx, int64_t bz) {
    Entry& e = entries_[size_t(uint64_t(bx * 31 + bz) & (kEntries - 1))];
    if (!e.valid || e.bx != bx || e.bz != bz) e = {true, bx, bz, streetBlockTop(world_, bx, bz)};
    return e.top;
  }

 private:
  struct Entry {
    bool valid = false;
    int64_t bx = 0, bz = 0;
    int32_t top = 0;
  };
  static constexpr size_t kEntries = 64;
  const World& world_;
  Entry entries_[kEntries];
};

/// The voxels of tile (tx, tz) inside `box` (clipped, not empty) into `out`;
/// returns the number produced.
uint64_t fillTile(const World& world, int32_t tx, int32_t tz, const IndexBox& box, VoxelBlocks& out,
                  StreetBlockTops& tops) {
  // Boxes above everything the tile's street blocks hold cost no column.
  int32_t bound = 0;
  for (int64_t bx = floorDiv(tx * kTile, kPitch); bx <= floorDiv(tx * kTile + kTile - 1, kPitch); ++bx)
    for (int64_t bz = floorDiv(tz * kTile, kPitch); bz <= floorDiv(tz * kTile + kTile - 1, kPitch); ++bz)
      bound = std::max(bound, tops(bx, bz));
  if (box.min.v >= bound) return 0;
  const int32_t u0 = std::max(tx * kTile, box.min.u), u1 = std::min(tx * kTile + kTile - 1, box.max.u);
  const int32_t w0 = std::max(tz * kTile, box.min.w), w1 = std::min(tz * kTile + kTile - 1, box.max.w);
  const int32_t nu = u1 - u0 + 3, nw = w1 - w0 + 3;  // with a ring of neighbours
  Column cols[(kTile + 2) * (kTile + 2)];
  int32_t tileTop = 0;
  for (int32_t i = 0; i < nu; ++i)
    for (int32_t j = 0; j < nw; ++j) {
      Column& c = cols[i * nw + j];
      c = columnAt(world, u0 - 1 + i, w0 - 1 + j);
      if (i > 0 && j > 0 && i < nu - 1 && j < nw - 1) tileTop = std::max(tileTop, c.top);
    }
  const int32_t vEnd = std::min(box.max.v + 1, tileTop);
  uint64_t produced = 0;
  // Block layer by block layer, so that consecutive voxels share a block.
  for (int32_t layer = box.min.v & ~(kBlockDim - 1); layer < vEnd; layer += kBlockDim) {
    const int32_t lo = std::max(layer, box.min.v), hi = std::min(layer + kBlockDim, vEnd);
    for (int32_t i = 1; i < nu - 1; ++i)
      for (int32_t j = 1; j < nw - 1; ++j) {
        const Column& c = cols[i * nw + j];
        if (c.top <= lo) continue;
        const Column &xm = cols[(i - 1) * nw + j], &xp = cols[(i + 1) * nw + j];
        const Column &zm = cols[i * nw + j - 1], &zp = cols[i * nw + j + 1];
        const int32_t u = u0 - 1 + i, w = w0 - 1 + j;
        for (int32_t v = nextOccupied(c, lo); v < hi; v = nextOccupied(c, v + 1)) {
          const Cls cls = classAt(c, v);
          const bool surface = classAt(c, v - 1) == kEmpty || classAt(c, v + 1) == kEmpty ||
                               classAt(xm, v) == kEmpty || classAt(xp, v) == kEmpty ||
                               classAt(zm, v) == kEmpty || classAt(zp, v) == kEmpty;
          emitVoxel(u, v, w, cls, c, surface, out);
          ++produced;
        }
      }
  }
  return produced;
}

World worldOf(const std::array<uint32_t, 3>& extent) {
  const std::string problem = cityExtentProblem(extent);
  if (!problem.empty()) throwUsage(std::string(kCityName) + ": " + problem);
  World w{int32_t(extent[0]), int32_t(extent[1]), int32_t(extent[2]), 0};
  w.maxStoreys = std::max(0, (w.Y - kGroundTop - 1 - kParapet) / kStorey);
  return w;
}

/// The tiles of a clipped box, numbered z-row by z-row.
struct TileRange {
  int32_t tx0 = 0, tz0 = 0, ntx = 0, ntz = 0;
  uint64_t count() const { return uint64_t(ntx) * uint64_t(ntz); }
  void at(uint64_t i, int32_t& tx, int32_t& tz) const {
    tz = tz0 + int32_t(i / uint64_t(ntx));
    tx = tx0 + int32_t(i % uint64_t(ntx));
  }
};

TileRange tilesOf(const IndexBox& box) {
  TileRange r;
  if (box.empty()) return r;
  r.tx0 = box.min.u / kTile, r.tz0 = box.min.w / kTile;
  r.ntx = box.max.u / kTile - r.tx0 + 1, r.ntz = box.max.w / kTile - r.tz0 + 1;
  return r;
}

}  // namespace

SceneHeader cityHeader(const std::array<uint32_t, 3>& extent) {
  worldOf(extent);  // validates
  SceneHeader header;
  header.dims = {extent[0], extent[1], extent[2]};
  header.voxelSize = kCityVoxelSize;
  header.origin = {-0.5 * extent[0] * kCityVoxelSize, 0.0, -0.5 * extent[2] * kCityVoxelSize};
  header.classes = blockPalette();
  header.sources.push_back({kCityName, "demo", "", 0});
  return header;
}

VoxelBlocks buildCityBlocks(const CityOptions& options) {
  const World world = worldOf(options.extent);
  const IndexBox box = clipToDomain(options.box, world);
  VoxelBlocks result;
  // A box above the tallest building (or tree) any city of this height holds is empty.
  const int32_t worldTop = std::min(world.Y, std::max(kTreeTopBound, kGroundTop + std::min(kMaxStoreys, world.maxStoreys) *
                                                                                       kStorey + 1 + kParapet));
  const TileRange tiles = tilesOf(box.min.v < worldTop ? box : IndexBox{});
  const uint64_t n = tiles.count();
  if (n == 0) return result;
  // Fixed-size pieces of consecutive tiles, each into its own blocks: tiles
  // own whole 8^3 blocks, so the merge is a union and the result does not
  // depend on the split or the thread count.
  const unsigned workers = workerCount(options.threads);
  const size_t pieces = size_t(std::min<uint64_t>(n, uint64_t(workers) * 16));
  std::vector<VoxelBlocks> parts(pieces);
  std::atomic<uint64_t> done{0};
  parallelPieces(size_t(n), options.threads, pieces, [&](size_t b, size_t e, size_t p) {
    StreetBlockTops tops(world);
    for (size_t i = b; i < e; ++i) {
      int32_t tx, tz;
      tiles.at(i, tx, tz);
      fillTile(world, tx, tz, box, parts[p], tops);
      if (options.progress && (i - b) % 256 == 255) options.progress(double(done += 256) / double(n));
    }
  });
  for (VoxelBlocks& part : parts) {
    result.merge(std::move(part));
    part = VoxelBlocks();
  }
  if (options.progress) options.progress(1.0);
  return result;
}

Scene buildCity(const CityOptions& options) {
  SceneHeader header = cityHeader(options.extent);
  VoxelBlocks blocks = buildCityBlocks(options);
  return SceneBuilder(std::move(blocks), std::move(header)).build();
}

CityFootprint estimateCityFootprint(const CityOptions& options, uint64_t maxSampledTiles) {
  const World world = worldOf(options.extent);
  const IndexBox box = clipToDomain(options.box, world);
  const TileRange tiles = tilesOf(box);
  CityFootprint f;
  f.tiles = tiles.count();
  if (f.tiles == 0) return f;
  const uint64_t samples = std::max<uint64_t>(1, std::min(f.tiles, maxSampledTiles));
  f.sampledTiles = samples;
  struct Counts {
    uint64_t blocks = 0, classBlocks = 0, classBytes = 0, occupied = 0;
  };
  std::vector<Counts> counts(samples);
  parallelForEach(size_t(samples), options.threads, 16, [&](size_t k) {
    // Every tile when they all fit, else tiles spread by a hash (a lattice
    // would alias with the street grid's period).
    const uint64_t i = samples == f.tiles ? k : (uint64_t(hashOf(int64_t(k), 7, 11, kSaltVoxel)) << 32 |
                                                 hashOf(int64_t(k), 13, 17, kSaltVoxel)) % f.tiles;
    int32_t tx, tz;
    tiles.at(i, tx, tz);
    VoxelBlocks scratch;
    StreetBlockTops tops(world);
    counts[k].occupied = fillTile(world, tx, tz, box, scratch, tops);
    for (const VoxelBlock* b : scratch.sortedBlocks()) {
      ++counts[k].blocks;
      counts[k].classBlocks += b->classes.size();
      for (const auto& c : b->classes) counts[k].classBytes += classBlockHeapBytes(*c);
    }
  });
  Counts sum;
  for (const Counts& c : counts)
    sum.blocks += c.blocks, sum.classBlocks += c.classBlocks, sum.classBytes += c.classBytes, sum.occupied += c.occupied;
  const double scale = double(f.tiles) / double(samples);
  f.blocks = double(sum.blocks) * scale;
  f.classBlocks = double(sum.classBlocks) * scale;
  f.classBytes = double(sum.classBytes) * scale;
  f.occupied = double(sum.occupied) * scale;
  return f;
}

MemoryEstimate cityBakeMemory(const CityFootprint& f) {
  MemoryEstimate e;
  e.add("voxel blocks", f.blocks * 420.0);
  e.add("class vote blocks", f.classBytes);
  // The direct writer's per-leaf tables and buffers: fitted to the peaks
  // measured once vote blocks were compact (docs/city.md "Memory guard").
  e.add("writer", f.blocks * 400.0 + f.classBlocks * 24.0);
  return e;
}

}  // namespace vox
