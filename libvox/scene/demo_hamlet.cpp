#include "libvox/scene/demo_hamlet.h"

#include <algorithm>
#include <atomic>
#include <functional>
#include <cmath>
#include <vector>

#include "libvox/core/error.h"
#include "libvox/core/parallel.h"
#include "libvox/mesh/voxel_blocks.h"

namespace vox {

namespace {

enum Cls : uint8_t { kEmpty = 0, kGrass = 1, kDirt = 2, kStone = 3, kPlank = 4, kSnow = 5, kSand = 6, kWater = 7 };

constexpr double kGroundTop = 12, kGrassDepth = 2, kPathHalfWidth = 7, kPathBlend = 3;

struct Building {
  double x0, x1, z0, z1, height;
  Cls roof;
  int doorSide;  // 0: -x wall, 1: +x wall, 2: -z wall, 3: +z wall (faces the path)
};
// Footprints keep clear of the path (|x - z| < 7) and of each other.
constexpr Building kBuildings[4] = {
    {30, 80, 160, 210, 44, kPlank, 1},
    {150, 200, 30, 80, 52, kSnow, 0},
    {160, 220, 100, 140, 40, kPlank, 2},
    {20, 70, 100, 140, 36, kStone, 1},
};
constexpr double kWall = 3;

struct Tree {
  double x, z, trunkTop, canopyRadius;
};
constexpr Tree kTrees[8] = {{20, 60, 40, 13},  {100, 30, 44, 14}, {120, 200, 38, 12}, {220, 60, 46, 14},
                            {235, 180, 40, 12}, {160, 240, 42, 13}, {60, 240, 38, 12}, {100, 130, 44, 13}};
constexpr double kTrunkRadius = 3;

constexpr double kWellX = 140, kWellZ = 100, kWellInner = 5, kWellOuter = 9, kWellTop = 22, kWaterBottom = 5,
                 kWaterTop = 10;

/// Material at design point (x, y, z) in [0, 256)^3.
Cls material(double x, double y, double z) {
  // Well: ring of stone above ground, water in a shaft dug into the ground.
  const double wr = std::hypot(x - kWellX, z - kWellZ);
  if (wr < kWellOuter && y < kWellTop) {
    if (wr >= kWellInner) return y >= kWaterBottom - 1 ? kStone : (y < kGroundTop ? kDirt : kEmpty);
    if (y >= kWaterBottom && y < kWaterTop) return kWater;
    if (y < kWaterBottom) return kStone;  // the well's floor
    return kEmpty;
  }
  if (y < kGroundTop) {
    if (y < kGroundTop - kGrassDepth) return kDirt;
    return std::abs(x - z) < kPathHalfWidth ? kSand : kGrass;
  }
  for (const Building& b : kBuildings) {
    const double top = kGroundTop + b.height;
    if (x < b.x0 || x >= b.x1 || z < b.z0 || z >= b.z1 || y >= top) continue;
    if (y >= top - kWall) return b.roof;
    const bool inWall = x < b.x0 + kWall || x >= b.x1 - kWall || z < b.z0 + kWall || z >= b.z1 - kWall;
    if (!inWall) return y < kGroundTop + 1 ? kPlank : kEmpty;  // plank floor, hollow inside
    // Door: 10 wide, 20 high, in the middle of one wall.
    const double cx = (b.x0 + b.x1) / 2, cz = (b.z0 + b.z1) / 2;
    const bool doorWall = (b.doorSide == 0 && x < b.x0 + kWall) || (b.doorSide == 1 && x >= b.x1 - kWall) ||
                          (b.doorSide == 2 && z < b.z0 + kWall) || (b.doorSide == 3 && z >= b.z1 - kWall);
    const double along = b.doorSide < 2 ? z - cz : x - cx;
    if (doorWall && std::abs(along) < 5 && y < kGroundTop + 20) return kEmpty;
    // Windows: 6x6 openings high on the other walls.
    if (!doorWall && y >= kGroundTop + 22 && y < kGroundTop + 28) {
      const double t = (x < b.x0 + kWall || x >= b.x1 - kWall) ? z - cz : x - cx;
      if (std::abs(std::abs(t) - 12) < 3) return kEmpty;
    }
    return kStone;
  }
  for (const Tree& t : kTrees) {
    const double dx = x - t.x, dz = z - t.z;
    if (dx * dx + dz * dz < kTrunkRadius * kTrunkRadius && y < t.trunkTop) return kPlank;
    const double dy = y - (t.trunkTop + t.canopyRadius * 0.4);
    if (dx * dx + dy * dy * 1.4 + dz * dz < t.canopyRadius * t.canopyRadius) return kGrass;
  }
  return kEmpty;
}

uint32_t hash3(int32_t u, int32_t v, int32_t w) {
  uint32_t h = uint32_t(u) * 0x8da6b343u ^ uint32_t(v) * 0xd8163841u ^ uint32_t(w) * 0xcb1ab31fu;
  h ^= h >> 15;
  h *= 0x2c1b3c6du;
  h ^= h >> 12;
  h *= 0x297a2d39u;
  h ^= h >> 15;
  return h;
}

/// The class a confused observer mistakes `c` for.
Cls confusedWith(Cls c) {
  switch (c) {
    case kGrass: return kDirt;
    case kDirt: return kGrass;
    case kStone: return kPlank;
    case kPlank: return kStone;
    case kSnow: return kStone;
    case kSand: return kGrass;
    case kWater: return kStone;
    default: return kEmpty;
  }
}

struct Sampler {
  uint32_t res;
  double scale;  // design units per voxel
  Cls at(int32_t u, int32_t v, int32_t w) const {
    if (u < 0 || v < 0 || w < 0 || uint32_t(u) >= res || uint32_t(v) >= res || uint32_t(w) >= res) return kEmpty;
    return material((u + 0.5) * scale, (v + 0.5) * scale, (w + 0.5) * scale);
  }
};

/// Slices w0..w1-1 of the box [lo, hi] (inclusive u, v; the surface test reads
/// the neighbours through the sampler, so a box gives exactly the world's voxels
/// inside it).
void fillSlab(const Sampler& s, const int32_t lo[3], const int32_t hi[3], int32_t w0, int32_t w1, VoxelBlocks& out,
              const std::function<void()>& sliceDone) {
  // Nothing in the design reaches above y = 72, so rows above are skipped.
  const int32_t vMax = std::min<int32_t>(hi[1] + 1, int32_t(std::ceil(72.0 / s.scale)) + 1);
  for (int32_t w = w0; w < w1; ++w) {
    for (int32_t v = lo[1]; v < vMax; ++v)
      for (int32_t u = lo[0]; u <= hi[0]; ++u) {
        const Cls c = s.at(u, v, w);
        if (c == kEmpty) continue;
        const bool surface = s.at(u - 1, v, w) == kEmpty || s.at(u + 1, v, w) == kEmpty ||
                             s.at(u, v - 1, w) == kEmpty || s.at(u, v + 1, w) == kEmpty ||
                             s.at(u, v, w - 1) == kEmpty || s.at(u, v, w + 1) == kEmpty;
        const uint32_t h = hash3(u, v, w);
        const Coord3 at{u, v, w};
        // Observation count grows towards the path and with height (the "camera"
        // walked the path), from 1 to ~600 votes.
        const double x = (u + 0.5) * s.scale, y = (v + 0.5) * s.scale, z = (w + 0.5) * s.scale;
        const double nearPath = std::max(0.0, 1.0 - std::abs(x - z) / 128.0);
        const uint32_t main = 1 + (h % 97) + uint32_t(400 * nearPath * nearPath) + uint32_t(y * 2);
        out.addVotes(at, c, main, surface);
        // Path edges: sand and grass blend across a band.
        const double edge = std::abs(x - z) - kPathHalfWidth;
        if ((c == kGrass || c == kSand) && y >= kGroundTop - kGrassDepth && y < kGroundTop &&
            std::abs(edge) < kPathBlend) {
          const double t = 0.5 - edge / (2 * kPathBlend);  // 1 inside the path, 0 outside
          const Cls other = c == kSand ? kGrass : kSand;
          const double share = c == kSand ? 1 - t : t;
          out.addVotes(at, other, uint32_t(main * share), surface);
        }
        // A quarter of the voxels are contested by a plausible confusion; some of
        // those are exact ties (margin 0, lowest id wins).
        if (((h >> 8) & 3) == 0) {
          const uint32_t contest = ((h >> 10) & 7) == 0 ? main : uint32_t((h >> 16) % (main + 1));
          out.addVotes(at, confusedWith(c), contest, surface);
        }
        // A few stray votes for snow.
        if (((h >> 24) & 31) == 0 && c != kSnow) out.addVotes(at, kSnow, 1 + ((h >> 29) & 3), surface);
      }
    if (sliceDone) sliceDone();
  }
}

}  // namespace

VoxelBlocks buildHamletBlocks(const HamletOptions& options, SceneHeader& header) {
  if (options.resolution < 1) throwUsage("demo:hamlet: resolution must be >= 1");
  if (options.resolution > 4096) throwUsage("demo:hamlet: resolution must be <= 4096");
  header = SceneHeader{};
  const uint32_t r = options.resolution;
  header.dims = {r, r, r};
  header.voxelSize = 25.6 / r;
  header.origin = {-12.8, 0.0, -12.8};
  header.classes = blockPalette();
  header.sources.push_back({kHamletName, "demo", "", 0});
  const Sampler sampler{r, 256.0 / r};
  int32_t lo[3] = {0, 0, 0}, hi[3] = {int32_t(r) - 1, int32_t(r) - 1, int32_t(r) - 1};
  if (options.box) {
    const IndexBox& b = *options.box;
    const int32_t bl[3] = {b.min.u, b.min.v, b.min.w}, bh[3] = {b.max.u, b.max.v, b.max.w};
    for (int k = 0; k < 3; ++k) lo[k] = std::max(lo[k], bl[k]), hi[k] = std::min(hi[k], bh[k]);
  }
  if (lo[0] > hi[0] || lo[1] > hi[1] || lo[2] > hi[2]) return VoxelBlocks();

  // One slab of w-slices per thread, each into its own blocks.
  const uint32_t slices = uint32_t(hi[2] - lo[2] + 1);
  const unsigned slabs = std::max(1u, std::min<unsigned>(options.threads, slices));
  std::vector<VoxelBlocks> parts(slabs);
  std::atomic<uint32_t> slicesDone{0};
  std::function<void()> sliceDone;
  if (options.progress) sliceDone = [&] { options.progress(double(++slicesDone) / slices); };
  parallelPieces(slices, slabs, slabs, [&](size_t w0, size_t w1, size_t slab) {
    fillSlab(sampler, lo, hi, lo[2] + int32_t(w0), lo[2] + int32_t(w1), parts[slab], sliceDone);
  });
  // Votes add and surface flags OR, so the merged blocks do not depend on how
  // the slabs were split.
  for (unsigned t = 1; t < slabs; ++t) parts[0].merge(std::move(parts[t]));
  return std::move(parts[0]);
}

Scene buildHamlet(const HamletOptions& options) {
  SceneHeader header;
  VoxelBlocks blocks = buildHamletBlocks(options, header);
  return SceneBuilder(std::move(blocks), std::move(header)).build();
}

}  // namespace vox
