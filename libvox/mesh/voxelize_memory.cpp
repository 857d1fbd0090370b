#include "libvox/mesh/voxelize_memory.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <memory>
#include <optional>

#include "libvox/core/flat_map64.h"
#include "libvox/core/parallel.h"
#include "libvox/core/round_half_away.h"
#include "libvox/mesh/lattice_triangles.h"
#include "libvox/mesh/texture_sampling.h"
#include "libvox/mesh/voxel_blocks.h"

namespace vox {

namespace {

using P3 = std::array<double, 3>;

P3 sub(const P3& a, const P3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
P3 cross(const P3& a, const P3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double len(const P3& a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }
P3 mid(const P3& a, const P3& b) { return {(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2}; }

double len2(const P3& a) { return a[0] * a[0] + a[1] * a[1] + a[2] * a[2]; }

/// Halvings until the longest edge is at most `side` (squared lengths: no
/// square root per edge).
int splitDepth(const P3 t[3], double side) {
  const double l2 = std::max({len2(sub(t[1], t[0])), len2(sub(t[2], t[1])), len2(sub(t[0], t[2]))});
  int d = 0;
  for (double e2 = l2; e2 > side * side && d < 30; e2 /= 4) ++d;
  return d;
}

/// The voxels a bake works on, inclusive: the grid, or a region bake's box
/// (the voxelizer clips every triangle's candidates to it).
struct Domain {
  int64_t lo[3], hi[3];
};

Domain domainOf(const SceneHeader& header) {
  Domain d{{0, 0, 0}, {int64_t(header.dims.x) - 1, int64_t(header.dims.y) - 1, int64_t(header.dims.z) - 1}};
  if (header.region) {
    const IndexBox& b = header.region->box;
    const int64_t lo[3] = {b.min.u, b.min.v, b.min.w}, hi[3] = {b.max.u, b.max.v, b.max.w};
    for (int k = 0; k < 3; ++k) d.lo[k] = std::max(d.lo[k], lo[k]), d.hi[k] = std::min(d.hi[k], hi[k]);
  }
  return d;
}

/// The voxels along each axis that the closed bounding box of piece `t`
/// touches (a vertex on a voxel face touches both voxels), not clamped.
void voxelsOfPiece(const P3 t[3], int64_t lo[3], int64_t hi[3]) {
  for (int k = 0; k < 3; ++k) {
    const double mn = std::min({t[0][k], t[1][k], t[2][k]}), mx = std::max({t[0][k], t[1][k], t[2][k]});
    lo[k] = int64_t(std::ceil(mn)) - 1, hi[k] = int64_t(std::floor(mx));
  }
}

/// The cells of side `side` (voxels) that the closed bounding box of piece `t`
/// touches, clamped to the domain: [lo, hi] per axis; false when the box
/// misses it (cropped by --bounds, or outside a region). One rule for both
/// counts below.
bool cellsOfPiece(const P3 t[3], const Domain& domain, double side, int64_t lo[3], int64_t hi[3]) {
  int64_t a[3], b[3];
  voxelsOfPiece(t, a, b);
  for (int k = 0; k < 3; ++k) {
    a[k] = std::max(a[k], domain.lo[k]);
    b[k] = std::min(b[k], domain.hi[k]);
    if (a[k] > b[k]) return false;
    lo[k] = int64_t(double(a[k]) / side), hi[k] = int64_t(double(b[k]) / side);
  }
  return true;
}

/// Calls add(piece) for the 4^depth pieces of triangle `t` halved `depth`
/// times (edge midpoints), in a fixed order.
template <typename Add>
void forEachSplitPiece(const P3 t[3], int depth, Add&& add) {
  if (depth == 0) return add(t);
  const P3 m01 = mid(t[0], t[1]), m12 = mid(t[1], t[2]), m20 = mid(t[2], t[0]);
  const P3 a[3] = {t[0], m01, m20}, b[3] = {m01, t[1], m12}, c[3] = {m20, m12, t[2]}, e[3] = {m01, m12, m20};
  forEachSplitPiece(a, depth - 1, add);
  forEachSplitPiece(b, depth - 1, add);
  forEachSplitPiece(c, depth - 1, add);
  forEachSplitPiece(e, depth - 1, add);
}

/// What one cell of the count holds.
struct Cell {
  double areaL1 = 0;                // sum of area * |n|_1 of the pieces given to it
  std::array<uint8_t, 4> classes{};  // the first classes seen (enough to tell 1, 2, 3, 4+)
  uint8_t classCount = 0;

  void addClass(uint8_t cls) {
    for (int i = 0; i < std::min<int>(classCount, 4); ++i)
      if (classes[size_t(i)] == cls) return;
    if (classCount < 4) classes[classCount] = cls;
    if (classCount < 255) ++classCount;
  }
};

class CellCounter {
 public:
  /// `pieces`: how many pieces will be added; sizes the table (a small mesh
  /// does not pay for zeroing a large one).
  CellCounter(const Domain& domain, double side, uint64_t pieces) : side_(side), domain_(domain) {
    cells_.reserve(size_t(std::min<uint64_t>(pieces, 1 << 16)) / 8);
  }

  /// One piece: its bounding box's voxels (closed boxes: a vertex on a voxel
  /// face touches both voxels), clamped to the grid, as cells.
  void add(const P3 t[3], double areaL1, uint8_t cls) {
    int64_t lo[3], hi[3];
    if (!cellsOfPiece(t, domain_, side_, lo, hi)) return;
    const double n = double((hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1));
    for (int64_t x = lo[0]; x <= hi[0]; ++x)
      for (int64_t y = lo[1]; y <= hi[1]; ++y)
        for (int64_t z = lo[2]; z <= hi[2]; ++z) {
          Cell& c = cells_[uint64_t(x) << 42 | uint64_t(y) << 21 | uint64_t(z)];  // x, y, z < 2^21: never the empty key
          c.areaL1 += areaL1 / n;
          c.addClass(cls);
        }
  }

  /// Adds `other`'s cells (its classes beyond the four it names count as
  /// classes not seen here: an estimate of 4+).
  void merge(CellCounter&& other) {
    cells_.reserve(cells_.size() + other.cells_.size());
    other.cells_.forEach([&](uint64_t key, const Cell& theirs) {
      Cell& c = cells_[key];
      c.areaL1 += theirs.areaL1;
      for (int i = 0; i < std::min<int>(theirs.classCount, 4); ++i) c.addClass(theirs.classes[size_t(i)]);
      if (theirs.classCount > 4) c.classCount = uint8_t(std::min(255, c.classCount + theirs.classCount - 4));
    });
    other.cells_.clear();
  }

  void split(const P3 t[3], int depth, double areaL1PerPiece, uint8_t cls) {
    forEachSplitPiece(t, depth, [&](const P3 piece[3]) { add(piece, areaL1PerPiece, cls); });
  }

  /// (blocks, block-classes): a cell of 8 voxels is one block; a coarser cell
  /// holds about areaL1 / 64 blocks (a plane of area A and normal n crosses
  /// A |n|_1 / 64 cubes of side 8 on average over its offsets), at least one,
  /// at most all of them.
  std::pair<double, double> blocks() const {
    const double perSide = side_ / kBlockDim, most = perSide * perSide * perSide;
    double blocks = 0, classes = 0;
    cells_.forEach([&](uint64_t, const Cell& c) {
      const double b = perSide <= 1 ? 1.0 : std::clamp(c.areaL1 / (kBlockDim * kBlockDim) + 0.5, 1.0, most);
      blocks += b;
      // Blocks of a cell with several classes: about half of them hold the
      // second class, and so on (class borders run through cells).
      classes += b * (1 + 0.5 * std::max(0, int(c.classCount) - 1));
    });
    return {blocks, classes};
  }

 private:
  double side_;
  Domain domain_;
  FlatMap64<Cell> cells_;
};

/// The same count as CellCounter's at cells of one block, for a mesh of at
/// most four classes on a grid of at most 2^24 cells (every bake up to 2048^3):
/// a bit per cell and class, set with an atomic OR by the triangles' pieces,
/// where the table's hashing was most of the estimate (about 3 ms of a 60 ms
/// bake of a 70 k-triangle scan at 256^3). The result is CellCounter's exactly:
/// a cell of one block is one block whatever its area, and with at most four
/// classes a cell's class count is exact in both (its sums are multiples of
/// 1/2, exact in any order). nullopt where it does not apply.
std::optional<std::pair<double, double>> blocksByCellBits(const std::vector<P3>& g,
                                                          const std::vector<std::array<uint32_t, 3>>& triangles,
                                                          const std::vector<uint8_t>& triangleClass, const Dims& dims,
                                                          const Domain& domain,
                                                          const std::vector<int>& depth, size_t nPieces,
                                                          unsigned threads) {
  constexpr uint64_t kMaxCells = uint64_t(1) << 24;
  const uint64_t cx = (uint64_t(dims.x) + kBlockDim - 1) / kBlockDim, cy = (uint64_t(dims.y) + kBlockDim - 1) / kBlockDim,
                 cz = (uint64_t(dims.z) + kBlockDim - 1) / kBlockDim;
  if (cx * cy * cz > kMaxCells) return std::nullopt;
  std::array<int, 256> slotOf;
  slotOf.fill(-1);
  int classes = 0;
  const size_t nt = triangles.size();
  for (size_t i = 0; i < nt; ++i) {
    const uint8_t cls = i < triangleClass.size() ? triangleClass[i] : 0;
    if (slotOf[cls] >= 0) continue;
    if (classes == 4) return std::nullopt;
    slotOf[cls] = classes++;
  }
  const size_t words = size_t((cx * cy * cz + 63) / 64);
  std::vector<std::unique_ptr<std::atomic<uint64_t>[]>> bits(static_cast<size_t>(classes));
  for (auto& b : bits) {
    b = std::make_unique<std::atomic<uint64_t>[]>(words);
    for (size_t w = 0; w < words; ++w) b[w].store(0, std::memory_order_relaxed);
  }
  parallelPieces(nt, threads, nPieces, [&](size_t b, size_t e, size_t) {
    for (size_t i = b; i < e; ++i) {
      const auto& tri = triangles[i];
      const P3 t[3] = {g[tri[0]], g[tri[1]], g[tri[2]]};
      std::atomic<uint64_t>* set = bits[size_t(slotOf[i < triangleClass.size() ? triangleClass[i] : 0])].get();
      forEachSplitPiece(t, depth[i], [&](const P3 piece[3]) {
        int64_t lo[3], hi[3];
        if (!cellsOfPiece(piece, domain, double(kBlockDim), lo, hi)) return;
        for (int64_t x = lo[0]; x <= hi[0]; ++x)
          for (int64_t y = lo[1]; y <= hi[1]; ++y)
            for (int64_t z = lo[2]; z <= hi[2]; ++z) {
              const uint64_t cell = (uint64_t(x) * cy + uint64_t(y)) * cz + uint64_t(z);
              const uint64_t bit = uint64_t(1) << (cell & 63);
              std::atomic<uint64_t>& word = set[cell >> 6];
              if (!(word.load(std::memory_order_relaxed) & bit)) word.fetch_or(bit, std::memory_order_relaxed);
            }
      });
    }
  });
  // Cells touched (by any class) and the classes summed over them.
  uint64_t cells = 0, cellClasses = 0;
  for (size_t w = 0; w < words; ++w) {
    uint64_t any = 0;
    for (const auto& b : bits) {
      const uint64_t v = b[w].load(std::memory_order_relaxed);
      any |= v;
      cellClasses += uint64_t(bitCount(v));
    }
    cells += uint64_t(bitCount(any));
  }
  // A cell of c classes counts 1 + (c - 1) / 2 block-classes (CellCounter::blocks).
  return std::make_pair(double(cells), double(cells) + 0.5 * double(cellClasses - cells));
}

/// A region bake's share of the surface sums, from the split pieces (no
/// longer than a cell): each piece counts the share of its box's voxels
/// inside the domain, along all three axes for its area and surface voxels
/// (the voxelizer clips every triangle's voxels to the region) and across
/// the rays for its crossings (a region's rays keep every crossing of the
/// columns in its box, wherever along the ray). Replaces f's area,
/// crossings and surface voxels.
void regionSums(const std::vector<P3>& g, const std::vector<std::array<uint32_t, 3>>& triangles, const Dims& dims, const Domain& domain,
                const std::vector<int>& depth, size_t nPieces, unsigned threads, SurfaceFootprint& f) {
  const int64_t last[3] = {int64_t(dims.x) - 1, int64_t(dims.y) - 1, int64_t(dims.z) - 1};
  struct Sums {
    double area = 0, surface = 0, crossings[3] = {0, 0, 0};
  };
  std::vector<Sums> sums(nPieces);
  parallelPieces(triangles.size(), threads, nPieces, [&](size_t b, size_t e, size_t piece) {
    Sums& s = sums[piece];
    for (size_t i = b; i < e; ++i) {
      const auto& tri = triangles[i];
      const P3 t[3] = {g[tri[0]], g[tri[1]], g[tri[2]]};
      const P3 n = cross(sub(t[1], t[0]), sub(t[2], t[0]));
      const double share = 1.0 / double(uint64_t(1) << (2 * depth[i]));  // of the triangle, per piece
      const double area = len(n) / 2 * share, c[3] = {std::abs(n[0]) / 2 * share, std::abs(n[1]) / 2 * share,
                                                      std::abs(n[2]) / 2 * share};
      forEachSplitPiece(t, depth[i], [&](const P3 piece[3]) {
        // The piece's voxels in the grid (as the whole bake's sums count the
        // piece whole, the regions' shares add up to them), then the share
        // of those in the domain.
        int64_t lo[3], hi[3];
        voxelsOfPiece(piece, lo, hi);
        double in[3];
        for (int k = 0; k < 3; ++k) {
          lo[k] = std::max<int64_t>(lo[k], 0), hi[k] = std::min(hi[k], last[k]);
          in[k] = lo[k] > hi[k] ? 0.0
                                : double(std::max<int64_t>(0, std::min(hi[k], domain.hi[k]) -
                                                                  std::max(lo[k], domain.lo[k]) + 1)) /
                                      double(hi[k] - lo[k] + 1);
        }
        const double inside = in[0] * in[1] * in[2];
        s.area += area * inside;
        s.surface += (c[0] + c[1] + c[2]) * inside;
        for (int k = 0; k < 3; ++k) s.crossings[k] += c[k] * in[(k + 1) % 3] * in[(k + 2) % 3];
      });
    }
  });
  f.area = f.surfaceVoxels = 0;
  for (double& c : f.crossings) c = 0;
  for (const Sums& s : sums) {
    f.area += s.area, f.surfaceVoxels += s.surface;
    for (int k = 0; k < 3; ++k) f.crossings[k] += s.crossings[k];
  }
}

}  // namespace

SurfaceFootprint surfaceFootprint(const Mesh& mesh, const std::vector<uint8_t>& triangleClass, const SceneHeader& header,
                                  uint64_t maxPieces, unsigned threads) {
  SurfaceFootprint f;
  const Domain domain = domainOf(header);
  if (mesh.triangles.empty() || domain.lo[0] > domain.hi[0] || domain.lo[1] > domain.hi[1] ||
      domain.lo[2] > domain.hi[2])
    return f;
  // Grid space, g = (world - origin) / voxelSize, snapped to the voxelizer's
  // lattice (2^-kSubvoxelBits voxel): a face that the division puts a hair
  // beyond the grid's last voxel boundary still touches the last voxel.
  std::vector<P3> g(mesh.positions.size());
  const double lattice = double(int64_t(1) << kSubvoxelBits);
  parallelForEach((g.size() + 4095) / 4096, threads, 1, [&](size_t chunk) {
    for (size_t i = chunk * 4096; i < std::min(g.size(), (chunk + 1) * 4096); ++i)
      for (int k = 0; k < 3; ++k)
        g[i][k] = roundHalfAway((mesh.positions[i][k] - header.origin[k]) / header.voxelSize * lattice) / lattice;
  });
  // Triangles reaching past the lattice's range: the part of them the bake
  // keeps (libvox/mesh/lattice_triangles.h), a fan clipped near the grid, or
  // none (a ground plane 1e8 voxels wide would split into 2^48 pieces).
  const std::vector<std::array<uint32_t, 3>>* triangles = &mesh.triangles;
  const std::vector<uint8_t>* classes = &triangleClass;
  LatticeTriangles clipped;
  std::vector<uint8_t> clippedClasses;
  if (std::any_of(g.begin(), g.end(), [](const P3& p) {
        return !(std::abs(p[0]) <= kMaxLatticeDistance && std::abs(p[1]) <= kMaxLatticeDistance &&
                 std::abs(p[2]) <= kMaxLatticeDistance);
      })) {
    clipped = latticeTriangles(mesh, header, FarTriangles::Clip);
    g.resize(clipped.lattice.size());
    for (size_t i = 0; i < g.size(); ++i)
      for (int k = 0; k < 3; ++k) g[i][size_t(k)] = double(clipped.lattice[i][size_t(k)]) / lattice;
    clippedClasses.resize(clipped.triangles.size());
    for (size_t t = 0; t < clipped.triangles.size(); ++t)
      clippedClasses[t] = clipped.source[t] < triangleClass.size() ? triangleClass[clipped.source[t]] : 0;
    triangles = &clipped.triangles;
    classes = &clippedClasses;
    f.clippedTriangles = double(clipped.triangles.size());
    f.fanTriangles = double(clipped.triangles.size() - clipped.firstFan);
    f.clipVertices = double(clipped.lattice.size() - mesh.positions.size());
  }
  const size_t nt = triangles->size();
  if (nt == 0) return f;

  // The triangles in up to 4 fixed pieces (whatever --threads; at least 8192
  // triangles each), each summed and counted on its own and merged in piece
  // order, so the estimate does not depend on the thread count. Few pieces:
  // each keeps its own cells until the merge (about one table's worth when
  // the file's triangles are spatially coherent, at most 4).
  const size_t nPieces = std::min<size_t>(4, (nt + 8191) / 8192);
  auto tri = [&](size_t i, P3 t[3]) {
    for (int k = 0; k < 3; ++k) t[k] = g[(*triangles)[i][size_t(k)]];
  };

  // Sums, and every triangle's split depth at cells of one block (8 voxels).
  struct Sums {
    double area = 0, crossings[3] = {0, 0, 0}, volume6 = 0;
    P3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    uint64_t splitPieces = 0;
  };
  double side = kBlockDim;
  std::vector<int> depth(nt);
  std::vector<Sums> sums(nPieces);
  auto countPieces = [&](size_t b, size_t e, Sums& s) {
    s.splitPieces = 0;
    for (size_t i = b; i < e && s.splitPieces <= maxPieces; ++i) {
      P3 t[3];
      tri(i, t);
      depth[i] = splitDepth(t, side);
      s.splitPieces += depth[i] >= 31 ? maxPieces + 1 : uint64_t(1) << (2 * depth[i]);
    }
  };
  parallelPieces(nt, threads, nPieces, [&](size_t b, size_t e, size_t piece) {
    Sums& s = sums[piece];
    for (size_t i = b; i < e; ++i) {
      P3 t[3];
      tri(i, t);
      const P3 n = cross(sub(t[1], t[0]), sub(t[2], t[0]));  // |n| = 2 area
      s.area += len(n) / 2;
      for (int k = 0; k < 3; ++k) s.crossings[k] += std::abs(n[k]) / 2;
      s.volume6 += t[0][0] * (t[1][1] * t[2][2] - t[1][2] * t[2][1]) - t[0][1] * (t[1][0] * t[2][2] - t[1][2] * t[2][0]) +
                   t[0][2] * (t[1][0] * t[2][1] - t[1][1] * t[2][0]);
      for (const P3& p : t)
        for (int k = 0; k < 3; ++k) s.lo[k] = std::min(s.lo[k], p[k]), s.hi[k] = std::max(s.hi[k], p[k]);
    }
    countPieces(b, e, s);
  });
  P3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  double volume6 = 0;
  uint64_t pieces = 0;
  for (const Sums& s : sums) {
    f.area += s.area;
    for (int k = 0; k < 3; ++k) f.crossings[k] += s.crossings[k];
    volume6 += s.volume6;
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], s.lo[k]), hi[k] = std::max(hi[k], s.hi[k]);
    pieces = std::min(maxPieces + 1, pieces + s.splitPieces);
  }
  f.enclosedVoxels = std::abs(volume6) / 6;
  // The solid fill's box: the mesh's voxels, cut to the domain (a region
  // bake fills its part of the box only).
  f.boxVoxels = 1;
  f.boxColumns = 1;
  for (int k = 0; k < 3; ++k) {
    const double extent = std::max(0.0, std::min(double(domain.hi[k]), std::floor(hi[k])) -
                                            std::max(double(domain.lo[k]), std::ceil(lo[k]) - 1) + 1);
    f.boxVoxels *= extent;
    if (k < 2) f.boxColumns *= extent;
  }
  f.enclosedVoxels = std::min(f.enclosedVoxels, f.boxVoxels);
  f.surfaceVoxels = f.crossings[0] + f.crossings[1] + f.crossings[2];

  // The cell side: 8 voxels (one block) unless the pieces would be too many.
  while (pieces > maxPieces && side <= 1e9) {
    side *= 2;
    parallelPieces(nt, threads, nPieces, [&](size_t b, size_t e, size_t piece) { countPieces(b, e, sums[piece]); });
    pieces = 0;
    for (const Sums& s : sums) pieces = std::min(maxPieces + 1, pieces + s.splitPieces);
  }
  if (header.region) regionSums(g, *triangles, header.dims, domain, depth, nPieces, threads, f);
  if (side == kBlockDim)
    if (const auto counted = blocksByCellBits(g, *triangles, *classes, header.dims, domain, depth, nPieces, threads)) {
      std::tie(f.blocks, f.blockClasses) = *counted;
      return f;
    }
  // Each piece's cells, then merged into the first in piece order.
  std::vector<CellCounter> counters;
  counters.reserve(nPieces);
  for (size_t p = 0; p < nPieces; ++p) counters.emplace_back(domain, side, pieces / nPieces + 1);
  parallelPieces(nt, threads, nPieces, [&](size_t b, size_t e, size_t piece) {
    for (size_t i = b; i < e; ++i) {
      P3 t[3];
      tri(i, t);
      const P3 n = cross(sub(t[1], t[0]), sub(t[2], t[0]));
      const double areaL1 = (std::abs(n[0]) + std::abs(n[1]) + std::abs(n[2])) / 2;
      counters[piece].split(t, depth[i], areaL1 / double(uint64_t(1) << (2 * depth[i])),
                            i < classes->size() ? (*classes)[i] : 0);
    }
  });
  for (size_t p = 1; p < nPieces; ++p) counters[0].merge(std::move(counters[p]));
  std::tie(f.blocks, f.blockClasses) = counters[0].blocks();
  return f;
}

uint64_t distinctPositions(const Mesh& mesh) {
  // A 64-bit digest of each position's coordinates (+0 and -0 alike) in a
  // flat set: two distinct positions share a digest with a chance of about
  // P^2 / 2^65, which counts one position too few.
  FlatMap64<uint8_t> seen;
  for (const auto& p : mesh.positions) {
    uint64_t h = 0x9E3779B97F4A7C15ull;
    for (double c : p) {
      uint64_t bits;
      const double x = c == 0 ? 0.0 : c;
      std::memcpy(&bits, &x, sizeof bits);
      h = (h ^ bits) * 0xBF58476D1CE4E5B9ull;
      h ^= h >> 31;
    }
    seen[h == FlatMap64<uint8_t>::kEmptyKey ? 0 : h] = 1;
  }
  return seen.size();
}

MemoryEstimate estimateMeshBake(const SurfaceFootprint& f, const Mesh& mesh, const VoxelizeSettings& settings,
                                uint64_t weldedVertices, double besideBlocks) {
  MemoryEstimate e;
  // Heap blocks carry ~16 bytes of malloc header; the block map's entry is a
  // key and a pointer in a flat table 1/4 to 1/2 full (flat_map64.h). Blocks on the
  // border of two threads' triangles exist twice until merged: +10% (the
  // blocks' resident bytes at 2 threads were 4-10% over 1 thread's: cube,
  // bunny, fandisk at 1024). The scene writer's part is its own (the caller's:
  // formats/scene/scene_vdb_direct.h); it was in a +20% here, which its
  // grid-sized buffers outgrew (docs/reliability.md "Memory").
  constexpr double kMalloc = kMallocBlockBytes, kShared = 1.10;
  constexpr double kMapEntry = double(FlatMap64<std::unique_ptr<VoxelBlock>, PackedCoordHome>::slotBytesPerKey());
  e.add("surface blocks", f.blocks * (sizeof(VoxelBlock) + kMalloc + kMapEntry) * kShared);
  // A class block keeps a count per voted voxel (grown in doublings from 16:
  // about 1.4x the counts on average, and 16 at least).
  e.add("vote blocks", (f.blockClasses * (sizeof(ClassBlock) + 2 * kMalloc + sizeof(void*) + 16 * sizeof(uint32_t)) +
                        f.surfaceVoxels * 1.4 * sizeof(uint32_t)) * kShared);
  const bool texturesRead = settings.textureRows && !mesh.textures.empty();
  if (mesh.hasColor()) {
    // A tile's colour slot table (2 KB a block) lives while its geometry runs
    // and its colours are written, so `threads` tiles' tables at a time, two
    // on one thread (measured: box12 at 512 peaks alike at --threads 1 and 2),
    // times 1.5 for tiles of unequal size; its sums (32 bytes a coloured
    // voxel) as long (with textures read by rows they all wait for the
    // images: counted below). The colours (12 bytes a coloured voxel, one
    // allocation of the exact size per block) stay until the writer.
    const unsigned threads = std::max(2u, settings.threads);
    const double tablesAlive = std::min(1.0, 1.5 * threads / double(surfaceTileCount(threads, true)));
    const double slotTables = tablesAlive * f.blocks * (kBlockVoxels * sizeof(uint32_t) + kMalloc);
    const double sums = texturesRead ? 0.0 : tablesAlive * f.surfaceVoxels * double(sizeof(ColorSum));
    e.add("colour blocks",
          (slotTables + sums + f.blocks * kMalloc + f.surfaceVoxels * 3 * sizeof(float)) * kShared);
  }
  e.add("grid-space vertices", double(mesh.positions.size()) * 3 * sizeof(int64_t));
  // The surface pass's tiles list their triangles' indices: 4 bytes a
  // triangle in its slab's list, gathered from per-part lists grown by
  // doubling (their heap stays), and up to 8 more in the tiles' lists of a
  // slab cut along y, grown by doubling beside it. Uncounted, a square of
  // 500,000 or 1,000,000 triangles (3,500 voxels) came out 0.90 and 0.84x
  // its peak (docs/reliability.md "Memory").
  const double triangles = f.clippedTriangles > 0 && settings.fill == FillMode::Surface ? f.clippedTriangles
                                                                                        : double(mesh.triangles.size());
  e.add("tiles' triangle lists", triangles * 4 * sizeof(uint32_t));
  // A surface bake of triangles reaching past the lattice's range keeps its
  // clipped copy of the triangles for the whole bake (lattice_triangles.h):
  // corners and source (16 bytes) of every kept and fan triangle, a fan's
  // barycentric weights (72 bytes), the clip's vertices (24 bytes).
  if (settings.fill == FillMode::Surface && f.clippedTriangles > 0)
    e.add("clipped triangles", f.clippedTriangles * (3 * sizeof(uint32_t) + sizeof(uint32_t)) +
                                   f.fanTriangles * 9 * sizeof(double) + f.clipVertices * 3 * sizeof(int64_t));
  if (texturesRead) {
    // Textures read by rows after the geometry: every tile keeps its textured
    // pieces (32 bytes and an 8-byte reference to sort them by row; 1.7 per
    // surface voxel on the textured benchmark model) and colour sums (32
    // bytes a voxel, and its slot in voxel order once the tile's slot tables
    // are compacted: 4 bytes, and a 64-byte mask a block) until then. The
    // rows being read: the caller's.
    e.add("textured pieces kept until the textures are read",
          f.surfaceVoxels * (1.7 * double(sizeof(TexturedPiece) + 8) + double(sizeof(ColorSum)) + 4) +
              f.blocks * (kBlockWords * 8 + 2 * kMalloc));
  }
  if (settings.fill == FillMode::Solid) {
    const bool parity = settings.solidRule == SolidRule::Parity;
    // One bit per voxel of the mesh's box (the surface), three more for parity's rays.
    e.add("solid-fill bits", f.boxVoxels / 8 * (parity ? 4 : 1));
    // Crossings (16 bytes), collected per thread then concatenated and sorted.
    const double crossings = parity ? f.crossings[0] + f.crossings[1] + f.crossings[2] : f.crossings[2];
    e.add("ray crossings", crossings * 16 * 2);
    // Interior blocks keep their votes as runs (64-byte masks), not 2 KB vote
    // blocks; x1.3 for the map's growth and the threads' copies until merged
    // (fitted: the cube, bunny and fandisk filled at 256..1024, 1.05-1.3x
    // their peaks with the writer; the 1.8 before held the writer's buffers).
    e.add("interior blocks", f.enclosedVoxels / kBlockVoxels * (sizeof(VoxelBlock) + kMalloc + kMapEntry) * 1.3);
    if (!parity) {
      // The winding rule's weld and boundary tables (hash maps of positions,
      // cells and edges) live before the blocks exist and are freed before
      // the blocks grow: they count where they exceed the bake's own parts.
      // They hold the mesh's distinct positions, not its vertices (an STL's
      // three per triangle are about half a position per triangle once
      // equal positions are one), the edges between them (P + T for a
      // closed surface, by Euler's formula; 3 T at most), an index and a
      // moved copy per vertex, and for every boundary edge its walk and cap
      // (2 E - 3 T of them, about 2 P - T; a soup of separate triangles has
      // 3 T). Fitted on /usr/bin/time peaks above the resident start at
      // --res 16 and 128 (31 meshes: ../shared/data's, UV spheres, boxes, a
      // hemisphere, a tube, a height field, as OBJ and as STL soup, and a
      // soup of 30,000 separate triangles: every case at or over 1.05x its
      // peak, docs/reliability.md "Memory"); fitted on five meshes they were
      // 1.3-1.5x the peak of spheres, boxes and open meshes.
      constexpr double kFixed = 1.5e6, kPerVertex = 50, kPerPosition = 60, kPerEdge = 100, kPerBoundaryEdge = 2200;
      const double v = double(mesh.positions.size()), t = double(mesh.triangles.size());
      const double p = double(std::min<uint64_t>(weldedVertices, mesh.positions.size()));
      const double edges = std::min(3 * t, p + t), boundary = std::min(3 * t, std::max(0.0, 2 * p - t));
      // The capped copy of the mesh the interior pass reads (capMesh in
      // voxelize.cpp): every triangle (12 bytes) and class (1), every vertex's
      // lattice point (24), and a cap's three points, triangle and class (85;
      // at most one cap a boundary edge). It is made after the surface pass
      // and freed once the interior is merged, so it meets the blocks and the
      // crossings, not the tables. Uncounted, an 80,000-triangle STL sphere
      // and a 120,000-triangle STL box filled at 256 came out 1.02 and 1.03x
      // their peaks (docs/reliability.md "Memory").
      e.add("capped copy of the mesh", t * (3 * sizeof(uint32_t) + 1) + v * 3 * sizeof(int64_t) +
                                           boundary * (9 * sizeof(int64_t) + 3 * sizeof(uint32_t) + 1));
      // The caps' own +z crossings beside the mesh's (16 bytes, twice while
      // sorted), one per column a cap covers: a loop of length l spans at
      // most l^2 / 4pi (the boundary's B edges of the mean edge's length, in
      // voxels, from the area), and the caps cross a column of the box at
      // most twice (a tube's two ends). Uncounted, a 40,000-triangle STL
      // tube filled at 256 came out 1.02x its peak.
      const double edge = t > 0 ? std::sqrt(4 / std::sqrt(3.0) * f.area / t) : 0.0;
      const double capColumns = std::min(2 * f.boxColumns, boundary * edge * boundary * edge / (4 * M_PI));
      if (capColumns >= 1) e.add("caps' ray crossings", capColumns * 16 * 2);
      const double tables = kFixed + v * kPerVertex + p * kPerPosition + edges * kPerEdge + boundary * kPerBoundaryEdge;
      const double bake = double(e.bytes()) - v * 3 * sizeof(int64_t) + besideBlocks;
      if (tables > bake) e.add("winding boundary tables (before the blocks)", tables - bake);
    }
  }
  return e;
}

}  // namespace vox
