// The exact voxelizer (contract in voxelize.h). Spaces, where they meet here
// (libvox/core/types.h lists the project's):
//   world    mesh positions (Mesh::positions);
//   grid     g = (world - origin) / voxelSize, voxel (u, v, w) covers [u, u+1]^3;
//   index    the integer voxel (u, v, w) itself;
//   lattice  grid x 2^kSubvoxelBits, integers: the snapped vertices every exact
//            decision is made on (names say `lattice`);
//   box      the solid fill's working box (VoxelBox): box-local voxel and ray
//            numbers, so its bit sets and crossing lists stay small.
// voxelizeMeshBlocks reads as its steps: snap (lattice_triangles.h: a surface
// fill clips the triangles reaching past the lattice's range), surface pass, then for a solid
// fill the rays' crossings, the inside flags per axis, and the interior.
#include "libvox/mesh/voxelize.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <optional>

#include "libvox/core/color.h"
#include "libvox/core/error.h"
#include "libvox/core/floor_int.h"
#include "libvox/core/flat_map64.h"
#include "libvox/core/memory_budget.h"
#include "libvox/core/parallel.h"
#include "libvox/mesh/lattice_triangles.h"
#include "libvox/mesh/texture_sampling.h"
#include "libvox/mesh/voxel_blocks.h"
#include "libvox/mesh/winding_number.h"

namespace vox {

namespace {

using i64 = int64_t;
using i128 = __int128;
using Vec3i = std::array<i64, 3>;

constexpr i64 kS = i64(1) << kSubvoxelBits;  // lattice steps per voxel

i128 abs128(i128 x) { return x < 0 ? -x : x; }

// ---------------------------------------------------------------- exact SAT

// Exact separating-axis test of a triangle and a closed box, on integers:
// coordinates doubled and relative to the box centre, the box
// [-h[0], h[0]] x [-h[1], h[1]] x [-h[2], h[2]].
// Magnitudes (lattice within 2^37 of the origin, doubled 2^39): normals 2^81,
// their products with points 2^122, within int128.
bool satDoubledBox(const Vec3i p[3], const i64 h[3]) {
  for (int i = 0; i < 3; ++i) {
    const i64 mn = std::min({p[0][i], p[1][i], p[2][i]}), mx = std::max({p[0][i], p[1][i], p[2][i]});
    if (mn > h[i] || mx < -h[i]) return false;
  }
  const i128 e[3][3] = {{i128(p[1][0]) - p[0][0], i128(p[1][1]) - p[0][1], i128(p[1][2]) - p[0][2]},
                        {i128(p[2][0]) - p[1][0], i128(p[2][1]) - p[1][1], i128(p[2][2]) - p[1][2]},
                        {i128(p[0][0]) - p[2][0], i128(p[0][1]) - p[2][1], i128(p[0][2]) - p[2][2]}};
  const i128 n[3] = {e[0][1] * e[2][2] - e[0][2] * e[2][1], e[0][2] * e[2][0] - e[0][0] * e[2][2],
                     e[0][0] * e[2][1] - e[0][1] * e[2][0]};
  {
    const i128 d = n[0] * p[0][0] + n[1] * p[0][1] + n[2] * p[0][2];
    const i128 r = h[0] * abs128(n[0]) + h[1] * abs128(n[1]) + h[2] * abs128(n[2]);
    if (abs128(d) > r) return false;
  }
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
      const i128 a1 = e[j][i2], a2 = -e[j][i1];
      i128 mn = 0, mx = 0;
      for (int k = 0; k < 3; ++k) {
        const i128 proj = a1 * p[k][i1] + a2 * p[k][i2];
        if (k == 0 || proj < mn) mn = proj;
        if (k == 0 || proj > mx) mx = proj;
      }
      const i128 r = h[i1] * abs128(a1) + h[i2] * abs128(a2);
      if (mn > r || mx < -r) return false;
    }
  return true;
}

// A voxel: the box is [-kS, kS]^3 (the exact test behind satFiltered).
bool satDoubled(const Vec3i p[3]) {
  const i64 h[3] = {kS, kS, kS};
  return satDoubledBox(p, h);
}

// ---------------------------------------------------------------- clipping (double)

struct Poly {
  int n = 0;
  double p[12][3];  // a triangle clipped by 6 planes has at most 9 vertices
};

/// One side of a slab: the part of `src` with x[Axis] >= bound (KeepAbove) or
/// <= bound, vertices in order from vertex 0, crossings interpolated along the
/// edges. Every vote's area comes from this clipping, so any change to its
/// arithmetic changes scenes; the templates only fix the axis and side.
template <int Axis, bool KeepAbove>
void clipSide(const Poly& src, Poly& dst, double bound) {
  // Each vertex's signed distance once, carried from edge to edge; the last
  // edge (back to vertex 0) peeled off the loop. The same arithmetic as ever,
  // in fewer instructions: this is a third of the surface pass (callgrind).
  auto distance = [bound](const double* v) { return KeepAbove ? v[Axis] - bound : bound - v[Axis]; };
  auto edge = [&](const double* a, const double* b, double da, double db, int& m) {
    if (da >= 0) std::memcpy(dst.p[m++], a, sizeof(double[3]));
    if ((da >= 0) != (db >= 0)) {
      const double t = da / (da - db);
      double* q = dst.p[m++];
      for (int k = 0; k < 3; ++k) q[k] = a[k] + (b[k] - a[k]) * t;
      q[Axis] = bound;
    }
  };
  const int n = src.n;
  int m = 0;
  if (n > 0) {
    const double d0 = distance(src.p[0]);
    double da = d0;
    for (int i = 0; i + 1 < n; ++i) {
      const double db = distance(src.p[i + 1]);
      edge(src.p[i], src.p[i + 1], da, db, m);
      da = db;
    }
    edge(src.p[n - 1], src.p[0], da, d0, m);
  }
  dst.n = m;
}

/// The extent [mn, mx] of `P` along `axis` (P not empty).
void polyRange(const Poly& P, int axis, double& lo, double& hi) {
  lo = hi = P.p[0][axis];
  for (int i = 1; i < P.n; ++i) lo = std::min(lo, P.p[i][axis]), hi = std::max(hi, P.p[i][axis]);
}

/// `in` clipped to [lo, hi] along Axis (against lo, then hi), its extent along
/// the axis being [mn, mx]: `in` itself when it lies inside (clipping would
/// copy it vertex for vertex; most triangle pieces at the usual resolutions
/// sit inside one slab), an empty `out` when it lies outside, else the
/// clipped polygon in `out`, skipping a side that `in` does not cross (it
/// would copy every vertex unchanged).
template <int Axis>
const Poly& clipRange(const Poly& in, Poly& out, double lo, double hi, double mn, double mx) {
  if (in.n == 0 || mn > hi || mx < lo) {
    out.n = 0;
    return out;
  }
  if (mn >= lo && mx <= hi) return in;
  if (mn >= lo) {
    clipSide<Axis, false>(in, out, hi);
  } else if (mx <= hi) {
    clipSide<Axis, true>(in, out, lo);
  } else {
    Poly tmp;
    clipSide<Axis, true>(in, tmp, lo);
    clipSide<Axis, false>(tmp, out, hi);
  }
  return out;
}

double polyArea(const Poly& P) {
  if (P.n < 3) return 0;
  // The fan from vertex 0: each triangle's second edge is the next one's
  // first, so it is computed once (the same values, fewer instructions).
  const double* a = P.p[0];
  double s[3] = {0, 0, 0};
  double u[3] = {P.p[1][0] - a[0], P.p[1][1] - a[1], P.p[1][2] - a[2]};
  for (int i = 1; i + 1 < P.n; ++i) {
    const double* c = P.p[i + 1];
    const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    s[0] += u[1] * v[2] - u[2] * v[1];
    s[1] += u[2] * v[0] - u[0] * v[2];
    s[2] += u[0] * v[1] - u[1] * v[0];
    u[0] = v[0], u[1] = v[1], u[2] = v[2];
  }
  return 0.5 * std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
}

// ---------------------------------------------------------------- helpers

i64 floorDiv(i128 a, i128 b) {  // b > 0
  i128 q = a / b;
  if ((a % b != 0) && (a < 0)) --q;
  return i64(q);
}

uint64_t voxelKey(int32_t u, int32_t v, int32_t w) {
  return (uint64_t(uint32_t(u)) << 42) | (uint64_t(uint32_t(v)) << 21) | uint64_t(uint32_t(w));
}

/// The voxels in [0, dim) whose closed interval [k, k+1] touches the lattice
/// interval [latticeLo, latticeHi]: [first, last], empty when first > last.
/// Inlined: called per triangle and axis by the surface pass, out of line it
/// cost the bunny at 256 0.6% more instructions (callgrind).
/// Lattice values are within 2^20 voxels of the grid (kMaxLatticeDistance), so
/// |lattice| < 2^37 and int64 holds every product below; S is a power of two,
/// so floor division by it is an arithmetic shift (C++20), not the 128-bit
/// division (a library call) it was.
[[gnu::always_inline]] inline void voxelsTouching(i64 latticeLo, i64 latticeHi, int32_t dim, int32_t& first, int32_t& last) {
  static_assert(kS == (i64(1) << kSubvoxelBits));
  // Voxel k touches iff k*S <= latticeHi and (k+1)*S >= latticeLo.
  const i64 f = (latticeLo - 1) >> kSubvoxelBits;  // floor((lo-1)/S); largest k with (k+1)*S < lo is one less
  first = int32_t(std::max<i64>(0, f));
  if ((i64(first) + 1) * kS < latticeLo) ++first;
  last = int32_t(std::min<i64>(dim - 1, latticeHi >> kSubvoxelBits));
}

// The same separating-axis test in double precision, used as a filter: it
// answers only when every axis is decided by a margin far above the rounding
// error (1e-9 of the magnitudes involved, against ~1e-15 actual), and returns
// -1 otherwise so the exact test decides. Inputs are exact (integers < 2^40).
int satFiltered(const Vec3i p[3]) {
  const double h = double(kS);
  double q[3][3];
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i) q[k][i] = double(p[k][i]);
  const double e[3][3] = {{q[1][0] - q[0][0], q[1][1] - q[0][1], q[1][2] - q[0][2]},
                          {q[2][0] - q[1][0], q[2][1] - q[1][1], q[2][2] - q[1][2]},
                          {q[0][0] - q[2][0], q[0][1] - q[2][1], q[0][2] - q[2][2]}};
  bool ambiguous = false;
  const double n[3] = {e[0][1] * e[2][2] - e[0][2] * e[2][1], e[0][2] * e[2][0] - e[0][0] * e[2][2],
                       e[0][0] * e[2][1] - e[0][1] * e[2][0]};
  {
    const double d = n[0] * q[0][0] + n[1] * q[0][1] + n[2] * q[0][2];
    const double r = h * (std::abs(n[0]) + std::abs(n[1]) + std::abs(n[2]));
    const double mag = (std::abs(e[0][1] * e[2][2]) + std::abs(e[0][2] * e[2][1])) * std::abs(q[0][0]) +
                       (std::abs(e[0][2] * e[2][0]) + std::abs(e[0][0] * e[2][2])) * std::abs(q[0][1]) +
                       (std::abs(e[0][0] * e[2][1]) + std::abs(e[0][1] * e[2][0])) * std::abs(q[0][2]) + r;
    const double err = 1e-9 * mag;
    if (std::abs(d) - r > err) return 0;
    if (std::abs(d) - r > -err) ambiguous = true;
  }
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
      const double a1 = e[j][i2], a2 = -e[j][i1];
      double mn = 0, mx = 0, mag = 0;
      for (int k = 0; k < 3; ++k) {
        const double proj = a1 * q[k][i1] + a2 * q[k][i2];
        mag = std::max(mag, std::abs(a1 * q[k][i1]) + std::abs(a2 * q[k][i2]));
        if (k == 0 || proj < mn) mn = proj;
        if (k == 0 || proj > mx) mx = proj;
      }
      const double r = h * (std::abs(a1) + std::abs(a2));
      const double err = 1e-9 * (mag + r);
      if (mn - r > err || -r - mx > err) return 0;
      if (mn - r > -err || -r - mx > -err) ambiguous = true;
    }
  return ambiguous ? -1 : 1;
}

}  // namespace

bool triangleTouchesVoxel(const std::array<int64_t, 3> tri[3], int32_t u, int32_t v, int32_t w) {
  const i64 c[3] = {(2 * i64(u) + 1) * kS, (2 * i64(v) + 1) * kS, (2 * i64(w) + 1) * kS};
  Vec3i p[3];
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i) p[k][i] = 2 * tri[k][i] - c[i];
  // Box axes first: exact, cheap, and they reject most candidates.
  for (int i = 0; i < 3; ++i) {
    const i64 mn = std::min({p[0][i], p[1][i], p[2][i]}), mx = std::max({p[0][i], p[1][i], p[2][i]});
    if (mn > kS || mx < -kS) return false;
  }
  const int quick = satFiltered(p);
  return quick >= 0 ? quick == 1 : satDoubled(p);
}

namespace {

// ---------------------------------------------------------------- the solid fill's box

/// The solid fill's working box: the voxels of the mesh's bounding box,
/// clamped to the domain (inclusive index-space voxel coordinates), and the
/// box-local numbers of its voxels (x-major, z fastest) and of its rays.
struct VoxelBox {
  int32_t lo[3], hi[3];
  int32_t ext[3];  // hi - lo + 1, kept: the hot loops index with it
  // Where the rays start along each axis: lo, or (a region bake's box) the
  // whole bake's box: crossings below lo keep their own start, so their order
  // along the ray (which decides the enclosing class) is the whole bake's.
  int32_t rayFrom[3];
  VoxelBox(const int32_t l[3], const int32_t h[3]) {
    for (int i = 0; i < 3; ++i) lo[i] = l[i], hi[i] = h[i], ext[i] = h[i] - l[i] + 1, rayFrom[i] = l[i];
  }
  uint64_t extent(int axis) const { return uint64_t(ext[axis]); }
  /// Box-local number of voxel (x, y, z): x-major, z fastest.
  uint64_t localIndex(int32_t x, int32_t y, int32_t z) const {
    return (uint64_t(x - lo[0]) * extent(1) + uint64_t(y - lo[1])) * extent(2) + uint64_t(z - lo[2]);
  }
  /// Box-local number of the ray along `axis` through voxels (.., vb, vc) on the
  /// axes b = axis + 1 and c = axis + 2 (mod 3).
  uint64_t columnIndex(int axis, int32_t vb, int32_t vc) const {
    const int b = (axis + 1) % 3, c = (axis + 2) % 3;
    return uint64_t(vb - lo[b]) * extent(c) + uint64_t(vc - lo[c]);
  }
};

/// A bit per voxel of a VoxelBox (at its localIndex), shared by the threads of
/// the surface pass (atomic words: triangles of several threads touch the same word).
struct BoxBits {
  VoxelBox box;
  std::vector<std::atomic<uint64_t>> words;
  explicit BoxBits(const VoxelBox& b) : box(b) {
    const uint64_t n = b.extent(0) * b.extent(1) * b.extent(2);
    words = std::vector<std::atomic<uint64_t>>((n + 63) / 64 + 1);  // +1: get64 reads one word ahead
  }
  void set(uint64_t i) { words[i >> 6].fetch_or(uint64_t(1) << (i & 63), std::memory_order_relaxed); }
  /// Bits i .. i+63 (bit 0 = i).
  uint64_t get64(uint64_t i) const {
    const uint64_t k = i >> 6, sh = i & 63;
    const uint64_t a = words[k].load(std::memory_order_relaxed) >> sh;
    return sh ? a | (words[k + 1].load(std::memory_order_relaxed) << (64 - sh)) : a;
  }
};

// The inside flags of one axis's rays, in BoxBits' layout (z fastest), written
// by one thread: plain words, and runs along z set a word at a time. (Setting
// one atomic bit per voxel was a third of a solid voxelization.)
struct PlainBits {
  std::vector<uint64_t> words;
  explicit PlainBits(const VoxelBox& b) {
    const uint64_t n = b.extent(0) * b.extent(1) * b.extent(2);
    words.assign((n + 63) / 64 + 1, 0);
  }
  void set(uint64_t i) { words[i >> 6] |= uint64_t(1) << (i & 63); }
  void setRange(uint64_t from, uint64_t to) {  // bits [from, to)
    while (from < to) {
      const uint64_t bit = from & 63, n = std::min<uint64_t>(64 - bit, to - from);
      words[from >> 6] |= (n == 64 ? ~uint64_t(0) : ((uint64_t(1) << n) - 1)) << bit;
      from += n;
    }
  }
  uint64_t get64(uint64_t i) const {
    const uint64_t k = i >> 6, sh = i & 63;
    return sh ? (words[k] >> sh) | (words[k + 1] << (64 - sh)) : words[k];
  }
};

// ---------------------------------------------------------------- snapping and the box

/// The solid fill's box: the voxels the mesh's triangles touch, clamped to
/// the domain; nullopt when that is empty.
std::optional<VoxelBox> solidFillBox(const Mesh& mesh, const std::vector<Vec3i>& lattice, Dims dims) {
  const int32_t dimv[3] = {int32_t(dims.x), int32_t(dims.y), int32_t(dims.z)};
  int32_t lo[3], hi[3];
  for (int i = 0; i < 3; ++i) {
    i64 mn = lattice[mesh.triangles[0][0]][i], mx = mn;
    for (const auto& tri : mesh.triangles)
      for (uint32_t vi : tri) mn = std::min(mn, lattice[vi][i]), mx = std::max(mx, lattice[vi][i]);
    voxelsTouching(mn, mx, dimv[i], lo[i], hi[i]);
    if (lo[i] > hi[i]) return std::nullopt;
  }
  return VoxelBox(lo, hi);
}

/// The solid fill's bit sets (one for the winding rule, four for parity) are
/// checked against the process's memory limit (libvox/core/memory_budget.h)
/// before they are allocated; the CLI has already checked the whole bake, this
/// catches library callers (mip --source).
void checkSolidFillMemory(const VoxelBox& box, SolidRule rule) {
  const uint64_t volume = box.extent(0) * box.extent(1) * box.extent(2);
  MemoryEstimate bits;
  bits.add("resident", residentBytesNow());
  bits.add("solid-fill bits", double(volume) / 8 * (rule == SolidRule::Parity ? 4 : 1));
  checkProcessMemory(bits, "a solid fill of a " + std::to_string(volume) + "-voxel box",
                     "fill only the surface, or use fewer, larger voxels");
}

/// `box` cut to the region (inclusive), its rays starting where box's do;
/// nullopt when they do not meet.
std::optional<VoxelBox> cutToRegion(const VoxelBox& box, const IndexBox& region) {
  const int32_t rlo[3] = {region.min.u, region.min.v, region.min.w}, rhi[3] = {region.max.u, region.max.v, region.max.w};
  int32_t lo[3], hi[3];
  for (int i = 0; i < 3; ++i) {
    lo[i] = std::max(box.lo[i], rlo[i]), hi[i] = std::min(box.hi[i], rhi[i]);
    if (lo[i] > hi[i]) return std::nullopt;
  }
  VoxelBox cut(lo, hi);
  for (int i = 0; i < 3; ++i) cut.rayFrom[i] = box.rayFrom[i];
  return cut;
}

/// Progress of one voxelization: fractions clamped to 1, from any worker.
struct Progress {
  const ProgressFn& fn;
  void operator()(double fraction) const {
    if (fn) fn(std::min(1.0, fraction));
  }
};

// ---------------------------------------------------------------- surface pass

struct SurfaceWork {
  const Mesh& mesh;
  const std::vector<uint8_t>& triClass;  // per mesh triangle
  const LatticeTriangles& triangles;     // the triangles on the lattice (clipped where they reach too far)
  Dims dims;
  bool color;
  const IndexBox* region;  // a region bake's box (inclusive), or null: the whole domain
  BoxBits* surfaceBits;  // solid fill: marks surface voxels inside the box
  const RowSampling* sampling;  // how each texture is sampled
  TextureRowSource* textureRows;  // VoxelizeSettings::textureRows, or null
};

/// The colour sums of one tile's surface voxels, per 8^3 block: a slot per
/// voxel (0: no sum yet, else 1 + the sum's index), the sums themselves in
/// chunks that never move. A voxel's sum is found with the block lookup the
/// votes already make (the last block is kept), where a hash map of voxels
/// cost a node allocation per coloured voxel and most of a coloured bake.
/// Memory: 2 KB per block plus 32 bytes per coloured voxel, about what the
/// map's nodes took.
class ColorSums {
 public:
  /// The slot of voxel (u, v, w)'s sum in sums(), made (zero) if new.
  uint32_t slotAt(int32_t u, int32_t v, int32_t w) {
    const uint64_t key = voxelKey(u >> kBlockLog2, v >> kBlockLog2, w >> kBlockLog2);
    if (key != lastKey_) {
      uint32_t& at = index_[key];  // grid voxels: u, v, w >= 0, so key < 2^63, never the empty key
      if (at == 0) {
        blocks_.push_back({{u & ~(kBlockDim - 1), v & ~(kBlockDim - 1), w & ~(kBlockDim - 1)},
                           std::make_unique<std::array<uint32_t, kBlockVoxels>>(), {}, {}});
        at = uint32_t(blocks_.size());
      }
      lastKey_ = key, last_ = &blocks_[at - 1];
    }
    uint32_t& slot = (*last_->slots)[size_t(blockOffset(u, v, w))];
    if (slot == 0) slot = sums_.add() + 1;  // add() stops below 2^32 - 1
    return slot - 1;
  }
  ColorSumStore& sums() { return sums_; }

  /// Gives every voxel with a sum its vote-weighted colour in `blocks` (which
  /// holds the tile's votes, so every such block exists), then frees the sums.
  void writeColors(VoxelBlocks& blocks) {
    for (const Block& cb : blocks_) {
      VoxelBlock* block = blocks.blockAt({cb.origin[0], cb.origin[1], cb.origin[2]});
      if (!block) continue;  // beyond +-2^23: blocks.outOfRange() says so, as for its votes
      VoxelBlock& b = *block;
      // In voxel order into one allocation of the exact size (the tile's
      // blocks have no colour yet; setBlockColor keeps any that would).
      std::array<std::array<float, 3>, kBlockVoxels> colors;
      std::array<uint64_t, kBlockWords> colored{};
      size_t n = 0;
      auto add = [&](int i, uint32_t slot) {
        const ColorSum& c = sums_[slot - 1];
        if (c.w == 0) return;
        const double d = double(c.w) * 65535.0;
        colors[n++] = {float(double(c.r) / d), float(double(c.g) / d), float(double(c.b) / d)};
        colored[size_t(i >> 6)] |= uint64_t(1) << (i & 63);
      };
      if (cb.slots) {
        for (int i = 0; i < kBlockVoxels; ++i)
          if (const uint32_t slot = (*cb.slots)[size_t(i)]) add(i, slot);
      } else {
        size_t next = 0;
        for (int k = 0; k < kBlockWords; ++k)
          for (uint64_t bits = cb.withSum[size_t(k)]; bits; bits &= bits - 1)
            add(k * 64 + std::countr_zero(bits), cb.compact[next++]);
      }
      if (b.colors.empty()) {
        b.colors.assign(colors.begin(), colors.begin() + std::ptrdiff_t(n));
        b.colored = colored;
      } else {
        size_t next = 0;
        for (int k = 0; k < kBlockWords; ++k)
          for (uint64_t bits = colored[size_t(k)]; bits; bits &= bits - 1)
            setBlockColor(b, k * 64 + std::countr_zero(bits), colors[next++]);
      }
    }
    *this = ColorSums();
  }

  /// Once the tile's geometry is done and its sums wait for the textures read
  /// by rows (after every tile's geometry): each block's slot table (2 KB)
  /// becomes the slots of its voxels with a sum, in voxel order (4 bytes
  /// each), and the block index goes. slotAt may not be called after it.
  void compactSlots() {
    for (Block& cb : blocks_) {
      if (!cb.slots) continue;
      size_t n = 0;
      for (int i = 0; i < kBlockVoxels; ++i)
        if ((*cb.slots)[size_t(i)]) {
          cb.withSum[size_t(i >> 6)] |= uint64_t(1) << (i & 63);
          ++n;
        }
      cb.compact.reserve(n);
      for (int i = 0; i < kBlockVoxels; ++i)
        if (const uint32_t slot = (*cb.slots)[size_t(i)]) cb.compact.push_back(slot);
      cb.slots.reset();
    }
    index_ = FlatMap64<uint32_t, PackedCoordHome>();
    lastKey_ = ~uint64_t(0), last_ = nullptr;
  }

 private:
  struct Block {
    std::array<int32_t, 3> origin;
    std::unique_ptr<std::array<uint32_t, kBlockVoxels>> slots;  // 1 + the sum's slot per voxel, 0: none
    // After compactSlots: the voxels with a sum and their slots (1 + slot) in voxel order.
    std::array<uint64_t, kBlockWords> withSum{};
    std::vector<uint32_t> compact;
  };
  FlatMap64<uint32_t, PackedCoordHome> index_;  // block key -> 1 + its index in blocks_
  std::vector<Block> blocks_;
  ColorSumStore sums_;
  uint64_t lastKey_ = ~uint64_t(0);
  Block* last_ = nullptr;
};

/// One tile's surface voxels: its votes, the colour sums that become its
/// colours, and the textured pieces still to add to them: those of textures
/// with pixels (added once the tile's geometry is done) and those of images
/// read by rows after every tile's geometry (libvox/mesh/texture_sampling.h).
struct SurfaceOut {
  VoxelBlocks blocks;
  ColorSums colors;
  TexturedPieces textured;
  RowPieces byRows;
};

/// Linear colour of triangle t at barycentric (l0, l1, l2) before its
/// texture: base colour factor x vertex colour, interpolated at that point.
/// When the triangle is textured, `texture` is its texture (else -1) and
/// (s, tt) the texture coordinates there.
std::array<float, 4> baseColor(const Mesh& m, size_t t, double l0, double l1, double l2, int& texture, double& s,
                               double& tt) {
  std::array<float, 4> c{1, 1, 1, 1};
  const MeshMaterial* mat = nullptr;
  if (!m.triangleMaterial.empty() && m.triangleMaterial[t] < m.materials.size()) mat = &m.materials[m.triangleMaterial[t]];
  if (mat) c = mat->baseColorFactor;
  const auto& tri = m.triangles[t];
  if (!m.colors.empty())
    for (int k = 0; k < 4; ++k)
      c[k] *= float(l0 * m.colors[tri[0]][k] + l1 * m.colors[tri[1]][k] + l2 * m.colors[tri[2]][k]);
  texture = -1;
  if (mat && mat->texture >= 0 && size_t(mat->texture) < m.textures.size()) {
    const auto& uv = mat->texCoordSet == 1 ? m.uv1 : m.uv0;
    if (!uv.empty()) {
      texture = mat->texture;
      s = l0 * uv[tri[0]][0] + l1 * uv[tri[1]][0] + l2 * uv[tri[2]][0];
      tt = l0 * uv[tri[0]][1] + l1 * uv[tri[1]][1] + l2 * uv[tri[2]][1];
      if (mat->placesTexture()) {
        const std::array<double, 6>& T = mat->uvTransform;
        const double s0 = s;
        s = T[0] * s0 + T[1] * tt + T[2];
        tt = T[3] * s0 + T[4] * tt + T[5];
      }
      // A coordinate that is not a number (a NaN or infinite UV in the file)
      // has no texel: the piece takes the base colour alone, the same on every
      // machine (casting it to a texel index would be undefined behaviour).
      if (!std::isfinite(s) || !std::isfinite(tt)) texture = -1;
    }
  }
  return c;
}

/// Barycentric coordinates of the vertex average of polygon `P` in triangle (a, b, c).
void barycentric(const Poly& P, const double a[3], const double b[3], const double c[3], double& l0, double& l1,
                 double& l2) {
  double p[3] = {0, 0, 0};
  for (int i = 0; i < P.n; ++i)
    for (int k = 0; k < 3; ++k) p[k] += P.p[i][k] / P.n;
  const double v0[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v1[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]},
               v2[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
  auto dot = [](const double* x, const double* y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; };
  const double d00 = dot(v0, v0), d01 = dot(v0, v1), d11 = dot(v1, v1), d20 = dot(v2, v0), d21 = dot(v2, v1);
  const double den = d00 * d11 - d01 * d01;
  if (!(std::abs(den) > 0)) {  // degenerate triangle: use its centroid
    l0 = l1 = l2 = 1.0 / 3.0;
    return;
  }
  l1 = std::clamp((d11 * d20 - d01 * d21) / den, 0.0, 1.0);
  l2 = std::clamp((d00 * d21 - d01 * d20) / den, 0.0, 1.0 - l1);
  l0 = 1.0 - l1 - l2;
}

/// Votes for an area of `units` 2^-16 voxel faces (>= 0): rounded to the
/// nearest (halves up, as std::round), at least 1, at most 2e9. Truncation and
/// an exact fraction instead of std::round, which is a libm call here.
uint32_t areaVotes(double units) {
  if (!(units < 2e9)) return 2000000000u;
  const int64_t whole = int64_t(units);  // units >= 0: truncation is floor
  const int64_t rounded = whole + (units - double(whole) >= 0.5 ? 1 : 0);  // the fraction is exact
  return rounded < 1 ? 1u : uint32_t(rounded);
}

/// Triangle t's voxels with x in [from[0], to[0]] and y in [from[1], to[1]]
/// (a tile): the votes (area) and colour sums of each voxel its closed box
/// touches, into `out`. P and the pieces below are in grid space (doubles), q
/// in lattice units.
void surfaceTriangle(const SurfaceWork& W, size_t t, const int32_t from[2], const int32_t to[2], SurfaceOut& out) {
  const auto& tri = W.triangles.corners(W.mesh, t);
  const uint32_t source = W.triangles.sourceOf(t);  // the mesh triangle: class, material, vertex colours, UVs
  std::array<int64_t, 3> q[3];
  for (int k = 0; k < 3; ++k) q[k] = W.triangles.lattice[tri[k]];
  i64 latticeLo[3], latticeHi[3];
  for (int i = 0; i < 3; ++i) {
    latticeLo[i] = std::min({q[0][i], q[1][i], q[2][i]});
    latticeHi[i] = std::max({q[0][i], q[1][i], q[2][i]});
  }
  int32_t first[3], last[3];
  const int32_t dimv[3] = {int32_t(W.dims.x), int32_t(W.dims.y), int32_t(W.dims.z)};
  for (int i = 0; i < 3; ++i) {
    voxelsTouching(latticeLo[i], latticeHi[i], dimv[i], first[i], last[i]);
    if (W.region) {  // the pieces below depend on the voxel only, so the box's voxels come out as in the whole bake
      const int32_t rlo[3] = {W.region->min.u, W.region->min.v, W.region->min.w};
      const int32_t rhi[3] = {W.region->max.u, W.region->max.v, W.region->max.w};
      first[i] = std::max(first[i], rlo[i]), last[i] = std::min(last[i], rhi[i]);
    }
    if (i < 2) first[i] = std::max(first[i], from[i]), last[i] = std::min(last[i], to[i]);
    if (first[i] > last[i]) return;
  }
  const uint8_t cls = W.triClass[source];

  Poly P;
  P.n = 3;
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i) P.p[k][i] = double(q[k][i]) / double(kS);
  const double eps = 1e-6;  // candidate search margin; exact SAT decides

  // Puv's extent along z, [zMin, zMax], measured once per column. Inlined
  // into both row loops: as a call it cost 3% of the pass's instructions.
  auto emit = [&](int32_t u, int32_t v, int32_t w, const Poly& Puv, double zMin,
                  double zMax) __attribute__((always_inline)) {
    Poly pieceStorage;
    const Poly& piece = clipRange<2>(Puv, pieceStorage, w, w + 1.0, zMin, zMax);  // the part inside the voxel
    const double area = polyArea(piece);
    // A piece of clearly positive area proves the intersection (double rounding
    // cannot make 1e-9 voxel^2 out of nothing); touching or missing voxels, where
    // the area is ~0, are decided by the exact test.
    if (!(area > 1e-9) && !triangleTouchesVoxel(q, u, v, w)) return;
    const uint32_t votes = areaVotes(area * double(kS));
    out.blocks.addVotes({u, v, w}, cls, votes, true);
    if (W.surfaceBits) W.surfaceBits->set(W.surfaceBits->box.localIndex(u, v, w));
    if (W.color) {
      // Colour at the piece's centre (the triangle's centroid if clipping lost it).
      double l0 = 1.0 / 3, l1 = 1.0 / 3, l2 = 1.0 / 3;
      if (piece.n > 0) barycentric(piece, P.p[0], P.p[1], P.p[2], l0, l1, l2);
      W.triangles.toSource(t, l0, l1, l2);  // a clipped triangle's point in its source triangle
      int texture;
      double s, tt;
      const std::array<float, 4> rgba = baseColor(W.mesh, source, l0, l1, l2, texture, s, tt);
      const uint32_t slot = out.colors.slotAt(u, v, w);
      ColorSum& sum = out.colors.sums()[slot];
      sum.w += votes;
      if (texture >= 0) {  // its texel later (texture_sampling.h); the sums are integers, so order does not matter
        const TextureSampling& sampling = W.sampling->sampling(uint32_t(texture));
        const TexelSpot spot = sampling.width > 0 && sampling.height > 0 ? texelSpot(sampling, s, tt) : TexelSpot{};
        const PieceLook look{{rgba[0], rgba[1], rgba[2]}, uint32_t(texture)};
        // A texture read by rows whose header did not read has no size: its
        // image fails to open, which ends the bake; the piece stays white meanwhile.
        if (W.sampling->imageOf(look.texture) >= 0 && sampling.height > 0)
          out.byRows.push(slot, votes, look, spot, W.sampling->band(look.texture, spot.y0), W.sampling->bands());
        else
          out.textured.push(slot, votes, look, spot);
      } else {
        sum.r += votes * q16(rgba[0]);
        sum.g += votes * q16(rgba[1]);
        sum.b += votes * q16(rgba[2]);
      }
    }
  };

  double xMin, xMax;
  polyRange(P, 0, xMin, xMax);
  // Candidate rows and voxels come from the exact pieces themselves (Pu, Puv)
  // when every decision of the y clip is certain: no vertex of Pu within
  // kCertain of a row boundary. Pu's vertices are then within `err` of the
  // true ones (the x clip decides on exact distances: lattice / kS), Puv's
  // vertices correspond one to one to the true polygon's, each off by at most
  // 2 err + |dz| (err / kCertain + 4 ulp) along z, and `zMargin` covers that
  // with a factor 4 to spare. So the candidates still hold every voxel the
  // exact test or a piece's area admits, and the scene is the same as with
  // the margin-clipped polygons, which a slab not certain still uses
  // (rowsWithMargin): the same votes, fewer clips.
  constexpr double kCertain = 1e-6;
  double zMinT, zMaxT, maxAbs = 0;
  polyRange(P, 2, zMinT, zMaxT);
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i) maxAbs = std::max(maxAbs, std::abs(P.p[k][i]));
  const double err = 16 * std::numeric_limits<double>::epsilon() * (maxAbs + 1);
  const double zMargin = 4 * (2 * err + (zMaxT - zMinT) * (err / kCertain + 4 * std::numeric_limits<double>::epsilon()));

  // Rows of slab u from the polygons clipped with margin eps (the reference
  // way: every candidate from a polygon a little larger than the slab).
  auto rowsWithMargin = [&](int32_t u, const Poly& Pu, double puYMin, double puYMax) {
    Poly PueStorage;
    const Poly& Pue = clipRange<0>(P, PueStorage, u - eps, u + 1 + eps, xMin, xMax);
    if (Pue.n == 0) return;
    double ylo, yhi;
    polyRange(Pue, 1, ylo, yhi);
    // Voxel k touches [lo, hi] iff k + 1 >= lo and k <= hi: from ceil(lo) - 1
    // (a piece starting inside a voxel does not touch the one below).
    const int32_t v0 = std::max(first[1], int32_t(ceilToInt(ylo - eps)) - 1);
    const int32_t v1 = std::min(last[1], int32_t(floorToInt(yhi + eps)));
    for (int32_t v = v0; v <= v1; ++v) {
      Poly PuveStorage, PuvStorage;
      const Poly& Puve = clipRange<1>(Pue, PuveStorage, v - eps, v + 1 + eps, ylo, yhi);
      if (Puve.n == 0) continue;
      const Poly& Puv = clipRange<1>(Pu, PuvStorage, v, v + 1.0, puYMin, puYMax);
      double zlo, zhi, puvZMin = 0, puvZMax = 0;
      polyRange(Puve, 2, zlo, zhi);
      if (Puv.n > 0) polyRange(Puv, 2, puvZMin, puvZMax);
      const int32_t w0 = std::max(first[2], int32_t(ceilToInt(zlo - eps)) - 1);
      const int32_t w1 = std::min(last[2], int32_t(floorToInt(zhi + eps)));
      for (int32_t w = w0; w <= w1; ++w) emit(u, v, w, Puv, puvZMin, puvZMax);
    }
  };

  for (int32_t u = first[0]; u <= last[0]; ++u) {
    Poly PuStorage;
    const Poly& Pu = clipRange<0>(P, PuStorage, u, u + 1.0, xMin, xMax);
    // Empty decides exactly: the triangle misses the closed slab, so neither a
    // piece nor the exact test admits any voxel of it.
    if (Pu.n == 0) continue;
    double puYMin = Pu.p[0][1], puYMax = puYMin;
    bool certain = true;
    for (int i = 0; i < Pu.n; ++i) {
      const double y = Pu.p[i][1];
      puYMin = std::min(puYMin, y), puYMax = std::max(puYMax, y);
      const double f = std::abs(y - double(int64_t(y)));  // distance to the integer toward 0, exact
      certain &= f > kCertain && f < 1 - kCertain;
    }
    if (!certain) {
      rowsWithMargin(u, Pu, puYMin, puYMax);
      continue;
    }
    const int32_t v0 = std::max(first[1], int32_t(ceilToInt(puYMin)) - 1);
    const int32_t v1 = std::min(last[1], int32_t(floorToInt(puYMax)));
    for (int32_t v = v0; v <= v1; ++v) {
      Poly PuvStorage;
      const Poly& Puv = clipRange<1>(Pu, PuvStorage, v, v + 1.0, puYMin, puYMax);
      if (Puv.n == 0) continue;  // certain: the triangle misses the row
      double puvZMin, puvZMax;
      polyRange(Puv, 2, puvZMin, puvZMax);
      const int32_t w0 = std::max(first[2], int32_t(ceilToInt(puvZMin - zMargin)) - 1);
      const int32_t w1 = std::min(last[2], int32_t(floorToInt(puvZMax + zMargin)));
      for (int32_t w = w0; w <= w1; ++w) emit(u, v, w, Puv, puvZMin, puvZMax);
    }
  }
}


/// Tiles of the surface pass: x ranges [from[0], to[0]] and y ranges
/// [from[1], to[1]] of whole 8^3 blocks, so the tiles' blocks are disjoint (no
/// block is built twice and merged), each with the triangles whose candidate
/// voxels reach into it.
struct Tile {
  int32_t from[2], to[2];
  std::vector<uint32_t> triangles;
};

/// The voxels a triangle's candidates span along x, y and z (clamped to the
/// domain and the region); empty (some first > last) when it touches neither.
struct CandidateBox {
  int32_t first[3], last[3];
  bool empty() const { return first[0] > last[0] || first[1] > last[1] || first[2] > last[2]; }
};

CandidateBox candidateBox(const SurfaceWork& W, size_t t) {
  const auto& tri = W.triangles.corners(W.mesh, t);
  const int32_t dimv[3] = {int32_t(W.dims.x), int32_t(W.dims.y), int32_t(W.dims.z)};
  CandidateBox c;
  for (int i = 0; i < 3; ++i) {
    const auto& L = W.triangles.lattice;
    const i64 a = L[tri[0]][i], b = L[tri[1]][i], d = L[tri[2]][i];
    voxelsTouching(std::min({a, b, d}), std::max({a, b, d}), dimv[i], c.first[i], c.last[i]);
    if (W.region) {
      const int32_t rlo[3] = {W.region->min.u, W.region->min.v, W.region->min.w};
      const int32_t rhi[3] = {W.region->max.u, W.region->max.v, W.region->max.w};
      c.first[i] = std::max(c.first[i], rlo[i]), c.last[i] = std::min(c.last[i], rhi[i]);
    }
  }
  return c;
}

/// Adds `perVoxel` x (the voxels of [first, last] in each block along the
/// axis) to `work`, one entry per block.
void addPerBlock(std::vector<double>& work, int32_t first, int32_t last, double perVoxel) {
  for (int32_t u = first; u <= last;) {
    const int32_t end = std::min(last, u | (kBlockDim - 1));
    work[size_t(u >> kBlockLog2)] += perVoxel * double(end - u + 1);
    u = end + 1;
  }
}

/// Cuts the blocks [firstBlock, lastBlock] along one axis into up to `pieces`
/// ranges of whole blocks with similar work (`work` per block, indexed from
/// firstBlock), as voxel ranges [from, to] ending at `lastVoxel`. Blocks
/// without work before or after the rest join the first or last range (no
/// empty tiles).
std::vector<std::array<int32_t, 2>> cutByWork(const std::vector<double>& work, int32_t firstBlock, int32_t lastVoxel,
                                              size_t pieces) {
  double total = 0;
  for (double w : work) total += w;
  std::vector<std::array<int32_t, 2>> ranges;
  double acc = 0;
  int32_t from = firstBlock * kBlockDim;
  const int32_t n = int32_t(work.size());
  for (int32_t b = 0; b < n; ++b) {
    acc += work[size_t(b)];
    const bool lastBlock = b + 1 == n;
    if (lastBlock || (acc >= total * double(ranges.size() + 1) / double(pieces) && acc < total)) {
      ranges.push_back({from, lastBlock ? lastVoxel : (firstBlock + b + 1) * kBlockDim - 1});
      from = (firstBlock + b + 1) * kBlockDim;
    }
  }
  return ranges;
}

/// About `pieces` tiles of the domain with similar work, by area rather than
/// by triangle count: every triangle counts its candidate voxels (rows along
/// z in each x column and y row it spans, plus a little per column for the
/// clipping). The domain is cut along x into slabs of whole blocks; a slab
/// holding more than its share (a large triangle facing x, whose voxels all
/// lie in one block column) is cut along y too, so both threads have work
/// when a few large triangles are most of the surface. Where the tiles end
/// does not change the result (a voxel's pieces do not depend on who clips
/// them), only the balance.
std::vector<Tile> surfaceTiles(const SurfaceWork& W, size_t pieces, unsigned threads) {
  const int32_t dimx = int32_t(W.dims.x), dimy = int32_t(W.dims.y);
  const size_t nTri = W.triangles.size(W.mesh);
  // The triangles in fixed parts (whatever the thread count), each measured
  // and listed on its own and merged in part order: the tiles, and so the
  // scene, do not depend on --threads (nor would they on the tiles anyway).
  const size_t parts = std::max<size_t>(1, std::min<size_t>(8, (nTri + 8191) / 8192));
  // Candidate boxes are recomputed in each pass rather than kept (24 bytes a
  // triangle would outweigh the index lists for a large scan).
  const size_t columns = size_t((dimx + kBlockDim - 1) / kBlockDim);
  std::vector<std::vector<double>> partWork(parts, std::vector<double>(columns, 0.0));  // per block column
  parallelPieces(nTri, threads, parts, [&](size_t b, size_t e, size_t part) {
    for (size_t t = b; t < e; ++t) {
      const CandidateBox c = candidateBox(W, t);
      if (c.empty()) continue;
      addPerBlock(partWork[part], c.first[0], c.last[0],
                  double(c.last[1] - c.first[1] + 1) * double(c.last[2] - c.first[2] + 1) + 4);
    }
  });
  std::vector<double> work(columns, 0.0);
  for (const std::vector<double>& w : partWork)
    for (size_t k = 0; k < columns; ++k) work[k] += w[k];
  double total = 0;
  for (double w : work) total += w;
  const std::vector<std::array<int32_t, 2>> slabs = cutByWork(work, 0, dimx - 1, pieces);

  // Each slab's triangles, then its cuts along y when it holds more than its share.
  std::vector<std::vector<std::vector<uint32_t>>> partSlabs(parts, std::vector<std::vector<uint32_t>>(slabs.size()));
  parallelPieces(nTri, threads, parts, [&](size_t b, size_t e, size_t part) {
    for (size_t t = b; t < e; ++t) {
      const CandidateBox c = candidateBox(W, t);
      if (c.empty()) continue;
      // The first slab ending at or after first[0], then on while they start at or before last[0].
      auto s = std::lower_bound(slabs.begin(), slabs.end(), c.first[0],
                                [](const std::array<int32_t, 2>& x, int32_t v) { return x[1] < v; });
      for (; s != slabs.end() && (*s)[0] <= c.last[0]; ++s)
        partSlabs[part][size_t(s - slabs.begin())].push_back(uint32_t(t));
    }
  });
  std::vector<std::vector<uint32_t>> slabTriangles(slabs.size());
  for (size_t k = 0; k < slabs.size(); ++k) {
    size_t n = 0;
    for (size_t part = 0; part < parts; ++part) n += partSlabs[part][k].size();
    slabTriangles[k].reserve(n);
    for (size_t part = 0; part < parts; ++part) {
      slabTriangles[k].insert(slabTriangles[k].end(), partSlabs[part][k].begin(), partSlabs[part][k].end());
      partSlabs[part][k] = std::vector<uint32_t>();
    }
  }
  std::vector<Tile> tiles;
  const int32_t blocksY = (dimy + kBlockDim - 1) / kBlockDim;
  for (size_t s = 0; s < slabs.size(); ++s) {
    const auto [x0, x1] = slabs[s];
    double slabWork = 0;
    for (int32_t b = x0 >> kBlockLog2; b <= x1 >> kBlockLog2; ++b) slabWork += work[size_t(b)];
    const size_t cuts = size_t(std::min(double(blocksY), std::floor(slabWork * double(pieces) / std::max(total, 1.0))));
    if (cuts < 2) {
      tiles.push_back({{x0, 0}, {x1, dimy - 1}, std::move(slabTriangles[s])});
      continue;
    }
    std::vector<double> rows(size_t(blocksY), 0.0);  // the slab's work per block row along y
    for (uint32_t t : slabTriangles[s]) {
      const CandidateBox c = candidateBox(W, t);
      const double columns = double(std::min(x1, c.last[0]) - std::max(x0, c.first[0]) + 1);
      addPerBlock(rows, c.first[1], c.last[1], columns * double(c.last[2] - c.first[2] + 1));
    }
    const size_t firstTile = tiles.size();
    for (const auto& [y0, y1] : cutByWork(rows, 0, dimy - 1, cuts)) tiles.push_back({{x0, y0}, {x1, y1}, {}});
    for (uint32_t t : slabTriangles[s]) {
      const CandidateBox c = candidateBox(W, t);
      for (size_t k = firstTile; k < tiles.size(); ++k)
        if (tiles[k].from[1] <= c.last[1] && tiles[k].to[1] >= c.first[1]) tiles[k].triangles.push_back(t);
    }
  }
  return tiles;
}

/// The surface pass: every triangle's voxels, the domain cut into tiles of
/// whole blocks, each tile's blocks its own, so merging them only moves
/// blocks; colours are the vote-weighted averages of the integer sums.
VoxelBlocks voxelizeSurface(const SurfaceWork& work, unsigned threads, const Progress& progress, double share) {
  const size_t nTri = work.triangles.size(work.mesh);
  const size_t pieces = surfaceTileCount(threads, work.color);
  std::vector<Tile> tiles;
  if (pieces > 1) {
    tiles = surfaceTiles(work, pieces, threads);
  } else {  // one tile: the whole domain, every triangle
    tiles.push_back({{INT32_MIN, INT32_MIN}, {INT32_MAX, INT32_MAX}, std::vector<uint32_t>(nTri)});
    for (size_t t = 0; t < nTri; ++t) tiles[0].triangles[t] = uint32_t(t);
  }
  std::vector<std::unique_ptr<SurfaceOut>> parts(tiles.size());
  for (auto& p : parts) p = std::make_unique<SurfaceOut>();
  std::atomic<size_t> done{0};
  size_t steps = 0;
  for (const Tile& s : tiles) steps += s.triangles.size();
  // The tile's voxels are its own: their colours are final once its textured
  // pieces are added, on its thread: at once for textures with pixels, after
  // every tile's geometry for those read by rows.
  auto finishColors = [&](size_t s) { parts[s]->colors.writeColors(parts[s]->blocks); };
  parallelPieces(tiles.size(), threads, tiles.size(), [&](size_t b, size_t e, size_t) {
    for (size_t s = b; s < e; ++s) {
      const Tile& tile = tiles[s];
      for (size_t i = 0; i < tile.triangles.size(); ++i) {
        surfaceTriangle(work, tile.triangles[i], tile.from, tile.to, *parts[s]);
        if (i % 4096 == 4095) progress(share * double(done += 4096) / double(std::max<size_t>(1, steps)));
      }
      addTexturedPieces(work.mesh, parts[s]->textured, parts[s]->colors.sums());
      parts[s]->textured.clear();
      if (parts[s]->byRows.pieces.empty()) finishColors(s);
      else parts[s]->colors.compactSlots();  // the sums wait for the images; their voxels need 2 KB a block less
    }
  });
  if (work.textureRows) {
    // Every image read once, band by band (also those no piece samples: an
    // undecodable image ends the bake whatever it needs).
    std::vector<RowPieces*> byRows(parts.size());
    for (size_t s = 0; s < parts.size(); ++s) byRows[s] = &parts[s]->byRows;
    sampleFromRows(*work.sampling, byRows, *work.textureRows, threads);
    parallelForEach(tiles.size(), threads, 1, [&](size_t s) {
      if (parts[s]->byRows.pieces.empty()) return;
      addSampledPieces(parts[s]->byRows.pieces, parts[s]->colors.sums());
      parts[s]->byRows = RowPieces();
      finishColors(s);
    });
  }
  for (size_t t = 1; t < parts.size(); ++t) parts[0]->blocks.merge(std::move(parts[t]->blocks));
  return std::move(parts[0]->blocks);
}

// ---------------------------------------------------------------- solid pass

struct Crossing {
  uint64_t column;  // the ray: VoxelBox::columnIndex
  int32_t start;    // first voxel along the ray whose centre lies beyond the crossing
  int8_t delta;     // +1 entering (normal against the ray), -1 leaving
  uint8_t cls;
  bool operator<(const Crossing& o) const {
    return std::tie(column, start, delta, cls) < std::tie(o.column, o.start, o.delta, o.cls);
  }
};

/// Does the edge a->b own the points on it (top-left rule for CCW triangles)?
bool ownsEdge(i64 ax, i64 ay, i64 bx, i64 by) {
  const i64 dx = bx - ax, dy = by - ay;
  return dy > 0 || (dy == 0 && dx < 0);
}

i64 ceilDiv(i128 a, i128 b) { return -floorDiv(-a, b); }

/// Crossings of rays along `axis` (through voxel centres, in the +axis
/// direction) with one triangle (q in lattice units), for the rays of `box`.
/// Out of line on purpose: inlined into the triangle loop it ran ~15% more
/// instructions (register pressure in the 128-bit loop; callgrind, bunny 256 solid).
[[gnu::noinline]] void crossTriangle(const Vec3i q[3], int axis, uint8_t cls, const VoxelBox& box,
                                     std::vector<Crossing>& out) {
  // Local copies: the crossings pushed below cannot alias them, so they stay in registers.
  const int32_t lo[3] = {box.lo[0], box.lo[1], box.lo[2]}, hi[3] = {box.hi[0], box.hi[1], box.hi[2]};
  const int a = axis, b = (axis + 1) % 3, c = (axis + 2) % 3;
  // Doubled coordinates: voxel centres sit at odd multiples of kS.
  i64 P[3][3];
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i) P[k][i] = 2 * q[k][i];
  i128 area2 = i128(P[1][b] - P[0][b]) * (P[2][c] - P[0][c]) - i128(P[1][c] - P[0][c]) * (P[2][b] - P[0][b]);
  if (area2 == 0) return;  // contains the ray direction: no crossing
  // (b, c, a) is right-handed, so area2 has the sign of the normal's component
  // along +a: positive means the ray leaves the solid there (outward normals).
  const int8_t delta = area2 > 0 ? -1 : +1;
  int idx[3] = {0, 1, 2};
  if (area2 < 0) std::swap(idx[1], idx[2]), area2 = -area2;
  const i64* V[3] = {P[idx[0]], P[idx[1]], P[idx[2]]};
  const i64 bmin = std::min({V[0][b], V[1][b], V[2][b]}), bmax = std::max({V[0][b], V[1][b], V[2][b]});
  const i64 cmin = std::min({V[0][c], V[1][c], V[2][c]}), cmax = std::max({V[0][c], V[1][c], V[2][c]});
  // Voxel k's centre along an axis is (2k + 1) kS.
  const i64 kb0 = std::max<i64>(lo[b], ceilDiv(i128(bmin) - kS, 2 * kS));
  const i64 kb1 = std::min<i64>(hi[b], floorDiv(i128(bmax) - kS, 2 * kS));
  const i64 kc0 = std::max<i64>(lo[c], ceilDiv(i128(cmin) - kS, 2 * kS));
  const i64 kc1 = std::min<i64>(hi[c], floorDiv(i128(cmax) - kS, 2 * kS));
  const bool own[3] = {ownsEdge(V[0][b], V[0][c], V[1][b], V[1][c]), ownsEdge(V[1][b], V[1][c], V[2][b], V[2][c]),
                       ownsEdge(V[2][b], V[2][c], V[0][b], V[0][c])};
  const i64 extentC = i64(hi[c]) - lo[c] + 1;
  for (i64 kb = kb0; kb <= kb1; ++kb)
    for (i64 kc = kc0; kc <= kc1; ++kc) {
      const i64 Qb = (2 * kb + 1) * kS, Qc = (2 * kc + 1) * kS;
      i128 E[3];
      bool inside = true;
      for (int e = 0; e < 3 && inside; ++e) {
        const i64* A = V[e];
        const i64* B = V[(e + 1) % 3];
        E[e] = i128(B[b] - A[b]) * (Qc - A[c]) - i128(B[c] - A[c]) * (Qb - A[b]);
        inside = E[e] > 0 || (E[e] == 0 && own[e]);
      }
      if (!inside) continue;
      // Height along a at Q, as num / area2 (barycentric weights E / area2).
      const i128 num = E[1] * V[0][a] + E[2] * V[1][a] + E[0] * V[2][a];
      i64 start = floorDiv(num - i128(kS) * area2, i128(2 * kS) * area2) + 1;
      start = std::clamp<i64>(start, box.rayFrom[a], i64(hi[a]) + 1);
      out.push_back({uint64_t((kb - lo[b]) * extentC + (kc - lo[c])), int32_t(start), delta, cls});
    }
}

/// A bit per voxel of the mesh's bounding box [lo, hi], x-major, z fastest.

/// Does a crossing that changes the winding number from `before` by `delta`
/// enter a part? It does when it raises |winding|, so that parts with inverted
/// winding (whose rays see -1 on entry) are entered too.
bool enters(int before, int delta) { return std::abs(before + delta) > std::abs(before); }

/// The class of the part enclosing voxel `k` of a column: the last crossing at
/// or before it that enters a part; nullopt when the column has none.
std::optional<uint8_t> enclosingClass(const std::vector<Crossing>& sorted, uint64_t column, int32_t k) {
  auto it = std::lower_bound(sorted.begin(), sorted.end(), Crossing{column, INT32_MIN, -128, 0});
  std::optional<uint8_t> cls;
  int winding = 0;
  for (; it != sorted.end() && it->column == column && it->start <= k; ++it) {
    if (enters(winding, it->delta)) cls = it->cls;
    winding += it->delta;
  }
  return cls;
}

/// The rays of the solid fill, per axis: their crossings with the triangles
/// (sorted: a total order, the same for any split) and the voxels whose centre
/// they see inside (non-zero winding number).
struct SolidRays {
  std::vector<Crossing> crossings[3];
  std::unique_ptr<PlainBits> inside[3];
};

/// The crossings of every triangle with the rays along `axis`, triangles split
/// into `threads` pieces and concatenated in piece order.
std::vector<Crossing> collectCrossings(const std::vector<std::array<uint32_t, 3>>& triangles,
                                       const std::vector<uint8_t>& triangleClass, const std::vector<Vec3i>& lattice,
                                       const VoxelBox& box, int axis, unsigned threads) {
  std::vector<std::vector<Crossing>> perPiece(threads);
  parallelPieces(triangles.size(), threads, threads, [&](size_t b, size_t e, size_t piece) {
    for (size_t i = b; i < e; ++i) {
      const auto& tri = triangles[i];
      const Vec3i q[3] = {lattice[tri[0]], lattice[tri[1]], lattice[tri[2]]};
      crossTriangle(q, axis, triangleClass[i], box, perPiece[piece]);
    }
  });
  std::vector<Crossing> all;
  for (auto& v : perPiece) all.insert(all.end(), v.begin(), v.end());
  return all;
}

/// The voxels of `box` that the rays along `axis` see inside: from each
/// crossing up to the next one on its ray, where the winding number is not 0.
/// `all` must be sorted. Out of line on purpose, like crossTriangle (inlined: ~4%
/// more instructions).
[[gnu::noinline]] std::unique_ptr<PlainBits> insideAlong(const std::vector<Crossing>& all, const VoxelBox& box,
                                                         int axis) {
  const int32_t* lo = box.lo;
  const int32_t* hi = box.hi;
  auto bits = std::make_unique<PlainBits>(box);
  const int a = axis, b = (axis + 1) % 3, c = (axis + 2) % 3;
  const uint64_t extentC = box.extent(c);
  for (size_t i = 0; i < all.size();) {
    const uint64_t column = all[i].column;
    int32_t xyz[3];
    xyz[b] = int32_t(column / extentC) + lo[b];
    xyz[c] = int32_t(column % extentC) + lo[c];
    int winding = 0;
    for (; i < all.size() && all[i].column == column; ++i) {
      winding += all[i].delta;
      const int32_t to = (i + 1 < all.size() && all[i + 1].column == column) ? all[i + 1].start : hi[a] + 1;
      if (winding == 0) continue;
      const int32_t from = std::max(all[i].start, lo[a]);  // a region's rays start below its box
      if (a == 2) {  // contiguous along z
        if (to > from) {
          xyz[2] = from;
          const uint64_t first = box.localIndex(xyz[0], xyz[1], xyz[2]);
          bits->setRange(first, first + uint64_t(to - from));
        }
        continue;
      }
      for (int32_t k = from; k < to; ++k) {
        xyz[a] = k;
        bits->set(box.localIndex(xyz[0], xyz[1], xyz[2]));
      }
    }
  }
  return bits;
}

/// Casts the rays of `box` along +x, +y and +z: crossings triangle-parallel per
/// axis, then the three axes sorted and filled side by side (each writes only
/// its own bits).
SolidRays castRays(const Mesh& mesh, const std::vector<uint8_t>& triangleClass, const std::vector<Vec3i>& lattice,
                   const VoxelBox& box, unsigned threads) {
  SolidRays rays;
  for (int axis = 0; axis < 3; ++axis)
    rays.crossings[axis] = collectCrossings(mesh.triangles, triangleClass, lattice, box, axis, threads);
  parallelPieces(3, threads, threads, [&](size_t axisBegin, size_t axisEnd, size_t) {
    for (size_t axis = axisBegin; axis < axisEnd; ++axis) {
      std::sort(rays.crossings[axis].begin(), rays.crossings[axis].end());
      rays.inside[axis] = insideAlong(rays.crossings[axis], box, int(axis));
    }
  });
  return rays;
}

/// The class of the part enclosing voxel `at` by the +x, then the +y rays
/// (for voxels with no entering crossing below them along +z); `fallback` when
/// neither has one.
uint8_t enclosingClassAlongXOrY(const SolidRays& rays, const VoxelBox& box, const int32_t at[3], uint8_t fallback) {
  std::optional<uint8_t> cls;
  for (int axis : {0, 1}) {
    if (cls) break;
    const int b = (axis + 1) % 3, c = (axis + 2) % 3;
    cls = enclosingClass(rays.crossings[axis], box.columnIndex(axis, at[b], at[c]), at[axis]);
  }
  return cls ? *cls : fallback;
}

/// The interior voxels of the +z column (x, y) of `box`: inside for at least 2
/// of the 3 rays and not on the surface. Walks the column's +z crossings
/// alongside z (the class of the last entering crossing at or below a voxel is
/// the enclosing part's), 64 voxels at a time; each run of interior voxels up
/// to the next +z crossing (where the enclosing class may change) is one addRun.
void interiorColumn(int32_t x, int32_t y, const SolidRays& rays, const BoxBits& surfaceBits, const VoxelBox& box,
                    uint8_t fallbackClass, VoxelBlocks& out) {
  const std::vector<Crossing>& zCross = rays.crossings[2];
  const uint64_t column = box.columnIndex(2, x, y);
  auto cur = std::lower_bound(zCross.begin(), zCross.end(), Crossing{column, INT32_MIN, -128, 0});
  std::optional<uint8_t> columnClass;
  int columnWinding = 0;
  const uint64_t base = box.localIndex(x, y, box.lo[2]);
  const int32_t n = box.hi[2] - box.lo[2] + 1;
  for (int32_t z0 = 0; z0 < n; z0 += 64) {
    const int32_t m = std::min(64, n - z0);
    const uint64_t w0 = rays.inside[0]->get64(base + uint64_t(z0)), w1 = rays.inside[1]->get64(base + uint64_t(z0)),
                   w2 = rays.inside[2]->get64(base + uint64_t(z0));
    uint64_t todo = ((w0 & w1) | (w0 & w2) | (w1 & w2)) & ~surfaceBits.get64(base + uint64_t(z0)) &
                    (m == 64 ? ~uint64_t(0) : (uint64_t(1) << m) - 1);
    while (todo) {
      const int bit = std::countr_zero(todo);
      const int32_t z = box.lo[2] + z0 + bit;
      while (cur != zCross.end() && cur->column == column && cur->start <= z) {
        if (enters(columnWinding, cur->delta)) columnClass = cur->cls;
        columnWinding += cur->delta;
        ++cur;
      }
      const int ones = std::countr_one(todo >> bit);
      int32_t end = z + ones;
      if (cur != zCross.end() && cur->column == column) end = std::min(end, cur->start);
      if (columnClass) {
        out.addRun({x, y, z}, uint32_t(end - z), *columnClass, kInteriorVotes, false);
      } else {  // rare: no entering crossing below along +z
        for (int32_t zz = z; zz < end; ++zz) {
          const int32_t at[3] = {x, y, zz};
          out.addRun({x, y, zz}, 1, enclosingClassAlongXOrY(rays, box, at, fallbackClass), kInteriorVotes, false);
        }
      }
      const int len = end - z;
      todo &= len >= 64 ? 0 : ~(((uint64_t(1) << len) - 1) << bit);
    }
  }
}

/// The interior of a solid fill into `blocks`: x slabs of the box split into
/// `threads` pieces, merged in piece order.
void addInterior(VoxelBlocks& blocks, const SolidRays& rays, const BoxBits& surfaceBits, const VoxelBox& box,
                 uint8_t fallbackClass, unsigned threads) {
  std::vector<std::unique_ptr<VoxelBlocks>> interior(threads);
  for (auto& b : interior) b = std::make_unique<VoxelBlocks>();
  parallelPieces(box.extent(0), threads, threads, [&](size_t xb, size_t xe, size_t piece) {
    for (int32_t x = box.lo[0] + int32_t(xb); x < box.lo[0] + int32_t(xe); ++x)
      for (int32_t y = box.lo[1]; y <= box.hi[1]; ++y)
        interiorColumn(x, y, rays, surfaceBits, box, fallbackClass, *interior[piece]);
  });
  for (auto& b : interior) blocks.merge(std::move(*b));
}

// ---------------------------------------------------------------- winding-number solid pass

/// The mesh closed by caps over its boundary loops (libvox/mesh/winding_number.h):
/// its triangles and lattice points (the mesh's, then the caps'), classes (a cap
/// takes the class of the triangle owning its boundary edge).
struct CappedMesh {
  std::vector<std::array<uint32_t, 3>> triangles;
  std::vector<Vec3i> lattice;
  std::vector<uint8_t> classes;
};

CappedMesh capMesh(const Mesh& mesh, const std::vector<uint8_t>& triangleClass, const std::vector<Vec3i>& lattice,
                   const std::vector<CapTriangle>& caps) {
  CappedMesh out;
  // At their final size: grown from the mesh's own by push_back, an open
  // mesh's copy doubled (48 bytes a vertex held through the interior pass).
  out.triangles.reserve(mesh.triangles.size() + caps.size());
  out.lattice.reserve(lattice.size() + 3 * caps.size());
  out.classes.reserve(triangleClass.size() + caps.size());
  out.triangles.assign(mesh.triangles.begin(), mesh.triangles.end());
  out.lattice.assign(lattice.begin(), lattice.end());
  out.classes.assign(triangleClass.begin(), triangleClass.end());
  for (const CapTriangle& c : caps) {
    const uint32_t first = uint32_t(out.lattice.size());
    for (int k = 0; k < 3; ++k) out.lattice.push_back(c.v[k]);
    out.triangles.push_back({first, first + 1, first + 2});
    out.classes.push_back(triangleClass[c.sourceTriangle]);
  }
  return out;
}

// Voxels per side of a top-level block of the winding rule: far from the holes'
// rims the caps' field varies little (CapField::ballField), so large blocks
// decide most of the box with one exact evaluation each. A small box is cut
// into tiles down to kMinTile per side, so that every worker gets several
// (windingTileEdge): the result does not depend on the tiles, since a block's
// bound decides a voxel only where the exact value would decide it the same.
constexpr int32_t kTile = 32;
constexpr int32_t kMinTile = 8;
// Blocks up to this many voxels are decided voxel by voxel (each with its own
// distance from the centre, and its jumps when the block cuts through caps);
// larger ones by runs of equal W (voxel by voxel where a run meets the 0.5
// level). A larger block through caps counts every voxel's jumps only while
// volume x cut triangles <= kJumpsPerEvaluation x cap triangles (a jump test
// costs about a sixteenth of one triangle's part of an evaluation, and a split
// costs eight evaluations), else splits.
constexpr size_t kJumpVolume = 64;
constexpr size_t kJumpsPerEvaluation = 64;

/// The interior of one tile of edge x edge columns of the box, by |winding
/// number| > 0.5 at the voxel centre: integer winding W of the capped mesh
/// along +z minus the caps' solid angle, which is evaluated per block with
/// CapField's bound (an octree descent from edge^3 blocks) and per voxel only
/// where the bound cannot decide. W is kept per column as runs between +z
/// crossings, the surface and the result as bits (z fastest), so a block far
/// from the holes costs a few word operations per column, not per voxel.
class WindingTile {
 public:
  WindingTile(int32_t x0, int32_t y0, int32_t edge, const std::vector<Crossing>& zCross, const CapField& caps,
              const BoxBits& surfaceBits, const VoxelBox& box)
      : x0_(x0), y0_(y0), z0_(box.lo[2]), edge_(edge), caps_(caps),
        nx_(std::min(edge, box.hi[0] - x0 + 1)), ny_(std::min(edge, box.hi[1] - y0 + 1)), nz_(box.ext[2]),
        words_((size_t(nz_) + 63) / 64) {
    const size_t columns = size_t(nx_) * size_t(ny_);
    surface_.assign(columns * words_, 0);
    inside_.assign(columns * words_, 0);
    done_.assign(columns * words_, 0);
    runBegin_.resize(columns + 1);
    for (int32_t i = 0; i < nx_; ++i)
      for (int32_t j = 0; j < ny_; ++j) {
        const size_t col = column(i, j);
        // Runs of equal W: a crossing changes W from voxel `start` on.
        const uint64_t c = box.columnIndex(2, x0 + i, y0 + j);
        runBegin_[col] = uint32_t(runs_.size());
        runs_.push_back({0, 0, -1});
        int w = 0, cls = -1;
        for (auto cur = std::lower_bound(zCross.begin(), zCross.end(), Crossing{c, INT32_MIN, -128, 0});
             cur != zCross.end() && cur->column == c; ++cur) {
          if (enters(w, cur->delta)) cls = cur->cls;
          w += cur->delta;
          const int32_t k = std::clamp(cur->start - z0_, 0, nz_);
          if (runs_.back().begin == k) runs_.back() = {k, w, int16_t(cls)};
          else runs_.push_back({k, w, int16_t(cls)});
        }
        if (runs_.back().begin == nz_ && runs_.size() - runBegin_[col] > 1) runs_.pop_back();
        const uint64_t base = box.localIndex(x0 + i, y0 + j, z0_);
        for (size_t wd = 0; wd < words_; ++wd) surface_[col * words_ + wd] = surfaceBits.get64(base + 64 * wd) & mask(wd, 0, nz_);
      }
    runBegin_[columns] = uint32_t(runs_.size());
  }

  /// Decides every voxel: W != 0 without caps (closed: w = W exactly).
  void decideAll() {
    if (caps_.empty()) {
      for (int32_t i = 0; i < nx_; ++i)
        for (int32_t j = 0; j < ny_; ++j)
          forRuns(column(i, j), 0, nz_, [&](const Run& r, int32_t a, int32_t b) {
            if (r.w != 0) setBits(inside_, column(i, j), a, b);
            return true;
          });
      return;
    }
    for (int32_t k0 = 0; k0 < nz_; k0 += edge_) decide(0, nx_, 0, ny_, k0, std::min(nz_, k0 + edge_));
  }

  /// The interior voxels (inside, not surface) as runs of one class.
  void emit(uint8_t fallbackClass, VoxelBlocks& out) const {
    for (int32_t i = 0; i < nx_; ++i)
      for (int32_t j = 0; j < ny_; ++j) {
        const size_t col = column(i, j);
        const uint32_t rEnd = runBegin_[col + 1];
        uint32_t r = runBegin_[col];
        for (int32_t k = next(col, 0, true); k < nz_; k = next(col, k, true)) {
          while (r + 1 < rEnd && runs_[r + 1].begin <= k) ++r;
          int32_t e = next(col, k, false);
          uint32_t rr = r;  // merge the following runs of the same class
          while (rr + 1 < rEnd && runs_[rr + 1].begin < e && runs_[rr + 1].cls == runs_[r].cls) ++rr;
          if (rr + 1 < rEnd) e = std::min(e, runs_[rr + 1].begin);
          const uint8_t c = runs_[r].cls >= 0 ? uint8_t(runs_[r].cls) : fallbackClass;
          out.addRun({x0_ + i, y0_ + j, z0_ + k}, uint32_t(e - k), c, kInteriorVotes, false);
          k = e;
        }
      }
  }

 private:
  struct Run {
    int32_t begin;  // first voxel (tile-local z) of the run; it ends where the next begins, or at nz
    int32_t w;      // winding number of the capped mesh
    int16_t cls;    // class of the part entered last, -1: none
  };

  size_t column(int32_t i, int32_t j) const { return size_t(i) * size_t(ny_) + size_t(j); }
  /// Bits of word `wd` for voxels [a, b).
  static uint64_t mask(size_t wd, int32_t a, int32_t b) {
    const int64_t lo = std::max<int64_t>(a - int64_t(64 * wd), 0), hi = std::min<int64_t>(b - int64_t(64 * wd), 64);
    if (hi <= lo) return 0;
    const uint64_t upto = hi == 64 ? ~uint64_t(0) : (uint64_t(1) << hi) - 1;
    return upto & ~((uint64_t(1) << lo) - 1);
  }
  /// A voxel in [a, b) still to decide (not surface, not decided yet)?
  bool anyFree(size_t col, int32_t a, int32_t b) const {
    for (size_t wd = size_t(a) / 64; wd * 64 < size_t(b); ++wd)
      if (~(surface_[col * words_ + wd] | done_[col * words_ + wd]) & mask(wd, a, b)) return true;
    return false;
  }
  void setBits(std::vector<uint64_t>& bits, size_t col, int32_t a, int32_t b) {
    for (size_t wd = size_t(a) / 64; wd * 64 < size_t(b); ++wd) bits[col * words_ + wd] |= mask(wd, a, b);
  }
  /// The first voxel at or after k that is interior (inside and not surface)
  /// when `set`, else the first that is not; nz when none.
  int32_t next(size_t col, int32_t k, bool set) const {
    for (size_t wd = size_t(k) / 64; wd < words_; ++wd) {
      uint64_t bits = inside_[col * words_ + wd] & ~surface_[col * words_ + wd];
      if (!set) bits = ~bits;
      bits &= mask(wd, k, nz_);
      if (bits) return int32_t(64 * wd) + std::countr_zero(bits);
    }
    return nz_;
  }
  /// Calls f(run, a, b) for the parts [a, b) of the column's runs within [k0, k1) until f returns false.
  template <class F>
  bool forRuns(size_t col, int32_t k0, int32_t k1, F&& f) const {
    const uint32_t rEnd = runBegin_[col + 1];
    for (uint32_t r = runBegin_[col]; r < rEnd; ++r) {
      const int32_t a = std::max(runs_[r].begin, k0), b = std::min(r + 1 < rEnd ? runs_[r + 1].begin : nz_, k1);
      if (a < b && !f(runs_[r], a, b)) return false;
      if (b >= k1) break;
    }
    return true;
  }
  int32_t windingAt(size_t col, int32_t k) const {
    uint32_t r = runBegin_[col];
    while (r + 1 < runBegin_[col + 1] && runs_[r + 1].begin <= k) ++r;
    return runs_[r].w;
  }

  /// Octree descent over a block [i0, i1) x [j0, j1) x [k0, k1) (tile-local):
  /// decided by the ball's bound when every voxel stays on one side of 0.5;
  /// else split in 8; single voxels exactly.
  void decide(int32_t i0, int32_t i1, int32_t j0, int32_t j1, int32_t k0, int32_t k1) {
    bool any = false;
    for (int32_t i = i0; i < i1 && !any; ++i)
      for (int32_t j = j0; j < j1 && !any; ++j) any = anyFree(column(i, j), k0, k1);
    if (!any) return;
    if (i1 - i0 == 1 && j1 - j0 == 1 && k1 - k0 == 1) {  // the caps' magnitude, the tree's value, else every cap
      const double p[3] = {x0_ + i0 + 0.5, y0_ + j0 + 0.5, z0_ + k0 + 0.5};
      const int32_t w = windingAt(column(i0, j0), k0);
      if (caps_.magnitudeBound(p, 0, 0.5) < 0.5) {  // |w_caps| < 0.5: inside exactly where W != 0
        if (w != 0) setBits(inside_, column(i0, j0), k0, k1);
        return;
      }
      if (caps_.ballField(p, 0, ball_) && decideVoxel(column(i0, j0), i0, j0, k0, p)) return;
      if (std::abs(double(w) - caps_.winding(p)) > 0.5) setBits(inside_, column(i0, j0), k0, k1);
      return;
    }
    if (decideBlock(i0, i1, j0, j1, k0, k1)) return;
    const int32_t im = i1 - i0 > 1 ? (i0 + i1) / 2 : i1, jm = j1 - j0 > 1 ? (j0 + j1) / 2 : j1,
                  km = k1 - k0 > 1 ? (k0 + k1) / 2 : k1;
    for (auto [a0, a1] : {std::pair{i0, im}, std::pair{im, i1}})
      for (auto [b0, b1] : {std::pair{j0, jm}, std::pair{jm, j1}})
        for (auto [c0, c1] : {std::pair{k0, km}, std::pair{km, k1}})
          if (a0 < a1 && b0 < b1 && c0 < c1) decide(a0, a1, b0, b1, c0, c1);
  }

  /// One evaluation for the block: where the caps' field stays below 0.5 in
  /// magnitude (CapField::magnitudeBound, then the full evaluation's bound),
  /// every voxel by W alone; else decides the voxels (blocks up to
  /// kJumpVolume voxels one by one, larger ones by runs of equal W) that its
  /// bound decides and returns whether none is left to decide.
  bool decideBlock(int32_t i0, int32_t i1, int32_t j0, int32_t j1, int32_t k0, int32_t k1) {
    const double centre[3] = {x0_ + 0.5 * (i0 + i1), y0_ + 0.5 * (j0 + j1), z0_ + 0.5 * (k0 + k1)};
    const double dx = i1 - i0 - 1, dy = j1 - j0 - 1, dz = k1 - k0 - 1;
    const double radius = 0.5 * std::sqrt(dx * dx + dy * dy + dz * dz);
    const size_t volume = size_t(i1 - i0) * size_t(j1 - j0) * size_t(k1 - k0);
    const bool small = caps_.magnitudeBound(centre, radius, 0.5) < 0.5;
    if (!small && !caps_.ballField(centre, radius, ball_)) return false;
    const CapField::Ball& b = ball_;
    if (small || b.magnitude < 0.5) {  // |w_caps| < 0.5 throughout: inside exactly where W != 0
      for (int32_t i = i0; i < i1; ++i)
        for (int32_t j = j0; j < j1; ++j) {
          const size_t col = column(i, j);
          setBits(done_, col, k0, k1);
          forRuns(col, k0, k1, [&](const Run& r, int32_t a, int32_t e) {
            if (r.w != 0) setBits(inside_, col, a, e);
            return true;
          });
        }
      return true;
    }
    if (!b.rimsClear) return false;
    // A ball through caps: each voxel counts its jumps (a plane test per cut
    // triangle), unless splitting (eight evaluations over every cap) costs less.
    if (!b.cut.empty() && volume > kJumpVolume && volume * b.cut.size() > kJumpsPerEvaluation * caps_.size())
      return false;
    bool undecided = false;
    for (int32_t i = i0; i < i1; ++i)
      for (int32_t j = j0; j < j1; ++j) {
        const size_t col = column(i, j);
        if (volume <= kJumpVolume || !b.cut.empty()) {  // voxel by voxel, each with its own distance
          for (int32_t k = k0; k < k1; ++k) undecided = !decideVoxel(col, i, j, k, centre) || undecided;
          continue;
        }
        const double ox = x0_ + i + 0.5 - centre[0], oy = y0_ + j + 0.5 - centre[1];
        forRuns(col, k0, k1, [&](const Run& r, int32_t a, int32_t e) {
          if (!anyFree(col, a, e)) return true;
          const int s = sideOfRun(r.w, radius, ox, oy, z0_ + a + 0.5 - centre[2], z0_ + e - 0.5 - centre[2]);
          if (s >= 0) {
            setBits(done_, col, a, e);
            if (s) setBits(inside_, col, a, e);
          } else {  // the run crosses (or comes close to) the 0.5 level: voxel by voxel
            for (int32_t k = a; k < e; ++k) undecided = !decideVoxel(col, i, j, k, centre) || undecided;
          }
          return true;
        });
      }
    return !undecided;
  }

  /// Whether |w| > 0.5 (1), < 0.5 (0) or undecided (-1) for w in [lo, hi].
  static int sideOf(double lo, double hi) { return lo > 0.5 || hi < -0.5 ? 1 : lo > -0.5 && hi < 0.5 ? 0 : -1; }

  /// The side of a run of winding W at offsets (ox, oy, oz0 .. oz1) from the
  /// ball's centre, every voxel within `radius`, no jumps: the constant model
  /// first, then the linear one.
  int sideOfRun(int32_t w, double radius, double ox, double oy, double oz0, double oz1) const {
    const CapField::Ball& b = ball_;
    const double eA = b.slope * radius + b.slack + b.valueError, m = w - b.value;
    const int sA = sideOf(m - eA, m + eA);
    if (sA >= 0) return sA;
    const double lxy = b.gradient[0] * ox + b.gradient[1] * oy;
    const double l0 = lxy + b.gradient[2] * oz0, l1 = lxy + b.gradient[2] * oz1;
    const double eB = (b.curvature * radius + b.gradientError) * radius + b.slack + b.valueError;
    return sideOf(m - std::max(l0, l1) - eB, m - std::min(l0, l1) + eB);
  }

  /// Decides voxel k of column (i, j) by the current ball with its own
  /// distance from the centre (and its jumps); false when it stays undecided.
  bool decideVoxel(size_t col, int32_t i, int32_t j, int32_t k, const double centre[3]) {
    if (!anyFree(col, k, k + 1)) return true;
    const CapField::Ball& b = ball_;
    if (b.magnitude < 0.5) {  // |w_caps| < 0.5: inside exactly where W != 0
      setBits(done_, col, k, k + 1);
      if (windingAt(col, k) != 0) setBits(inside_, col, k, k + 1);
      return true;
    }
    const double p[3] = {x0_ + i + 0.5, y0_ + j + 0.5, z0_ + k + 0.5};
    int jump = 0;
    if (!b.cut.empty() && !caps_.jumps(b, p, jump)) return false;
    const double q[3] = {p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]};
    const double d2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2], d = std::sqrt(d2);
    const double m = windingAt(col, k) - b.value - jump;
    const double eA = b.slope * d + b.slack + b.valueError;
    int s = sideOf(m - eA, m + eA);
    if (s < 0) {
      const double l = m - (b.gradient[0] * q[0] + b.gradient[1] * q[1] + b.gradient[2] * q[2]);
      const double eB = (b.curvature * d + b.gradientError) * d + b.slack + b.valueError;
      s = sideOf(l - eB, l + eB);
    }
    if (s < 0) return false;
    setBits(done_, col, k, k + 1);
    if (s) setBits(inside_, col, k, k + 1);
    return true;
  }

  const int32_t x0_, y0_, z0_, edge_;
  const CapField& caps_;
  const int32_t nx_, ny_, nz_;
  const size_t words_;            // 64-bit words per column
  std::vector<uint64_t> surface_;  // per column, z fastest
  std::vector<uint64_t> inside_;   // per column: |w| > 0.5 decided (surface voxels may be set too)
  std::vector<uint64_t> done_;     // per column: decided by a block's bound
  std::vector<Run> runs_;
  std::vector<uint32_t> runBegin_;  // per column, into runs_
  CapField::Ball ball_;
};

/// The tiles' edge for a box: kTile, halved down to kMinTile while the box has
/// fewer than four tiles per worker.
int32_t windingTileEdge(const VoxelBox& box, unsigned threads) {
  const uint64_t wanted = 4 * uint64_t(workerCount(threads));
  int32_t edge = kTile;
  auto tiles = [&](int32_t e) { return ((box.extent(0) + e - 1) / e) * ((box.extent(1) + e - 1) / e); };
  while (edge > kMinTile && tiles(edge) < wanted) edge /= 2;
  return edge;
}

/// The interior by the winding-number rule: one piece per tile of columns
/// (windingTileEdge), on `threads` workers, merged in tile order. Progress: the
/// fraction of the box's columns whose tiles are done, from `share0` to 1.
void addWindingInterior(VoxelBlocks& blocks, const Mesh& mesh, const std::vector<uint8_t>& triangleClass,
                        const std::vector<Vec3i>& lattice, const std::vector<CapTriangle>& caps,
                        const BoxBits& surfaceBits, const VoxelBox& box, unsigned threads,
                        const Progress& progress, double share0) {
  const CappedMesh capped = capMesh(mesh, triangleClass, lattice, caps);
  std::vector<Crossing> zCross = collectCrossings(capped.triangles, capped.classes, capped.lattice, box, 2, threads);
  std::sort(zCross.begin(), zCross.end());
  const CapField field(caps);
  const int32_t edge = windingTileEdge(box, threads);
  const size_t tilesX = (box.extent(0) + edge - 1) / edge, tilesY = (box.extent(1) + edge - 1) / edge;
  // One piece per tile, not per x slab: on open meshes and soups the work
  // gathers where the caps are (a tree's crown, a part's holes), so a few
  // slabs left one thread with most of it (a 5,000-card tree at --res 32: 2
  // slabs, 0.65 of 2 cores busy). Tiles are disjoint in voxels, so merging
  // them in tile order gives the scene the slab order gave.
  const size_t tiles = tilesX * tilesY;
  std::vector<std::unique_ptr<VoxelBlocks>> interior(tiles);
  for (auto& b : interior) b = std::make_unique<VoxelBlocks>();
  const double columns = double(box.extent(0)) * double(box.extent(1));
  std::atomic<uint64_t> columnsDone{0};
  parallelPieces(tiles, threads, tiles, [&](size_t tb, size_t te, size_t) {
    for (size_t t = tb; t < te; ++t) {
      const int32_t x0 = box.lo[0] + int32_t(t / tilesY) * edge, y0 = box.lo[1] + int32_t(t % tilesY) * edge;
      WindingTile tile(x0, y0, edge, zCross, field, surfaceBits, box);
      tile.decideAll();
      tile.emit(triangleClass[0], *interior[t]);
      const uint64_t n = uint64_t(std::min(edge, box.hi[0] - x0 + 1)) * uint64_t(std::min(edge, box.hi[1] - y0 + 1));
      progress(share0 + (1 - share0) * double(columnsDone += n) / columns);
    }
  });
  for (auto& b : interior) blocks.merge(std::move(*b));
}

}  // namespace

std::array<bool, 256> classesTouchingDomain(const Mesh& mesh, const std::vector<uint8_t>& triangleClass,
                                            const SceneHeader& header) {
  std::array<bool, 256> used{};
  // As a surface bake sees the triangles: those reaching past the lattice's range clipped.
  const LatticeTriangles triangles = latticeTriangles(mesh, header, FarTriangles::Clip);
  const i64 dimLattice[3] = {i64(header.dims.x) * kS, i64(header.dims.y) * kS, i64(header.dims.z) * kS};
  for (size_t t = 0; t < triangles.size(mesh); ++t) {
    const uint8_t cls = triangleClass[triangles.sourceOf(t)];
    if (used[cls]) continue;
    std::array<int64_t, 3> q[3];
    for (int k = 0; k < 3; ++k) q[k] = triangles.lattice[triangles.corners(mesh, t)[k]];
    bool within = true;
    for (int i = 0; i < 3; ++i) {
      const i64 mn = std::min({q[0][i], q[1][i], q[2][i]}), mx = std::max({q[0][i], q[1][i], q[2][i]});
      within = within && mn >= 0 && mx <= dimLattice[i];
    }
    if (within) {
      used[cls] = true;
      continue;
    }
    // Straddles the domain's boundary (--bounds, or a clipped far triangle):
    // the closed domain is the union of the voxels' closed cubes, so the
    // triangle touches a voxel iff it touches the domain, one exact test (a
    // test per voxel of its box took minutes for a large tilted triangle that
    // misses the grid's corner).
    Vec3i p[3];
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i) p[k][i] = 2 * q[k][i] - dimLattice[i];
    if (satDoubledBox(p, dimLattice)) used[cls] = true;
  }
  return used;
}

VoxelBlocks voxelizeMeshBlocks(const Mesh& mesh, const std::vector<uint8_t>& triangleClass,
                               const SceneHeader& header, const VoxelizeSettings& settings) {
  if (triangleClass.size() != mesh.triangles.size())
    throw Error(ErrorKind::Internal, "voxelizeMesh: one class per triangle expected");
  const unsigned threads = std::max(1u, settings.threads);
  const Progress progress{settings.progress};

  // A surface fill clips the triangles that reach past the lattice's range;
  // a solid fill's inside depends on them whole, so it refuses them.
  const LatticeTriangles triangles =
      latticeTriangles(mesh, header, settings.fill == FillMode::Surface ? FarTriangles::Clip : FarTriangles::Refuse);
  const std::vector<Vec3i>& lattice = triangles.lattice;  // the solid passes': the mesh's own triangles
  std::optional<VoxelBox> box;
  std::vector<CapTriangle> caps;
  // The winding rule works on the mesh with near vertices welded (a soup's
  // float noise closed up; vertices move at most 2^-8 voxel): its crossings
  // and caps then agree, and W changes only within that distance of the
  // surface, inside surface voxels, which the unmoved mesh decides.
  std::vector<Vec3i> weldedLattice;
  if (settings.fill == FillMode::Solid && settings.solidRule == SolidRule::Winding && !mesh.triangles.empty())
    weldedLattice = weldNearVertices(lattice, kWeldSteps);
  const std::vector<Vec3i>& windingLattice = weldedLattice.empty() ? lattice : weldedLattice;
  if (settings.fill == FillMode::Solid && !mesh.triangles.empty()) {
    box = solidFillBox(mesh, lattice, header.dims);
    if (box && settings.solidRule == SolidRule::Winding) {
      caps = capBoundaryLoops(mesh.triangles, windingLattice);
      // Open meshes: |w| can exceed 0.5 just outside the mesh's box (near the
      // caps); grow the box by the caps' reach (CapField::reach), within the domain.
      const int64_t grow = int64_t(std::ceil(CapField::reachOf(caps))) + 1;
      if (!caps.empty()) {
        const int64_t dimv[3] = {int64_t(header.dims.x), int64_t(header.dims.y), int64_t(header.dims.z)};
        int32_t lo[3], hi[3];
        for (int k = 0; k < 3; ++k) {
          lo[k] = int32_t(std::max<int64_t>(0, box->lo[k] - grow));
          hi[k] = int32_t(std::min<int64_t>(dimv[k] - 1, box->hi[k] + grow));
        }
        box = VoxelBox(lo, hi);
      }
    }
    // A region works on its part of the box; its rays start where the whole box's do.
    if (box && settings.region) box = cutToRegion(*box, *settings.region);
    if (box) checkSolidFillMemory(*box, settings.solidRule);
  }
  std::unique_ptr<BoxBits> surfaceBits = box ? std::make_unique<BoxBits>(*box) : nullptr;

  const double surfaceShare = box ? 0.5 : 1.0;
  const IndexBox* region = settings.region ? &*settings.region : nullptr;
  const RowSampling sampling(mesh, settings.textureRows);
  const SurfaceWork work{mesh,   triangleClass,     triangles, header.dims,          mesh.hasColor(),
                         region, surfaceBits.get(), &sampling, settings.textureRows};
  VoxelBlocks blocks = voxelizeSurface(work, threads, progress, surfaceShare);
  if (box && settings.solidRule == SolidRule::Parity) {
    const SolidRays rays = castRays(mesh, triangleClass, lattice, *box, threads);
    progress(surfaceShare + 0.45);
    addInterior(blocks, rays, *surfaceBits, *box, triangleClass[0], threads);
  } else if (box) {
    addWindingInterior(blocks, mesh, triangleClass, windingLattice, caps, *surfaceBits, *box, threads, progress,
                       surfaceShare);
  }
  progress(1.0);
  return blocks;
}

}  // namespace vox
