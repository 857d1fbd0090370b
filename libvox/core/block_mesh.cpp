#include "libvox/core/block_mesh.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <tuple>

#include "libvox/core/color.h"
#include "libvox/core/error.h"
#include "libvox/core/parallel.h"

namespace vox {

namespace {

constexpr int kSide = ClassVolume::kBrickSide;

// Palette colours of every class id for every face, linear RGB.
struct FacePalettes {
  std::array<bool, 256> known{};
  std::array<std::array<RgbLinear, kBlockFaceCount>, 256> color{};

  explicit FacePalettes(const ClassTable& classes) {
    for (const ClassInfo& c : classes.classes()) {
      known[c.id] = true;
      for (int f = 0; f < kBlockFaceCount; ++f) {
        const auto& n = kBlockFaces[size_t(f)].normal;
        const std::array<double, 3> srgb = facePaletteColor(&c, {n[0], n[1], n[2]});
        color[c.id][size_t(f)] = {srgbToLinear(srgb[0]), srgbToLinear(srgb[1]), srgbToLinear(srgb[2])};
      }
    }
  }
};

// The rows of the renderer's loop: for each band of bricks with the same v
// origin, its 8 voxel rows (y values), each visiting the band's bricks by
// (w, u) with 8 z rows per w group.
struct Band {
  size_t first = 0, last = 0;  // [first, last) in volume.bricks()
};

std::vector<Band> bandsOf(const std::vector<ClassVolume::Brick>& bricks) {
  std::vector<Band> bands;
  for (size_t i = 0; i < bricks.size(); ++i)
    if (bands.empty() || bricks[i].origin.v != bricks[bands.back().first].origin.v) bands.push_back({i, i + 1});
    else bands.back().last = i + 1;
  return bands;
}

// Whether the voxel across face `f` of voxel (x, y, z) of brick `b` is occupied.
bool neighbourOccupied(const std::vector<ClassVolume::Brick>& bricks, const ClassVolume::Brick& b, int x, int y,
                       int z, int f) {
  const auto& n = kBlockFaces[size_t(f)].normal;
  int nx = x + n[0], ny = y + n[1], nz = z + n[2];
  if (nx >= 0 && nx < kSide && ny >= 0 && ny < kSide && nz >= 0 && nz < kSide)
    return b.classes[size_t(ClassVolume::voxelIndex(nx, ny, nz))] != 0;
  const int32_t other = b.neighbours[size_t(f)];
  if (other < 0) return false;
  nx = (nx + kSide) % kSide, ny = (ny + kSide) % kSide, nz = (nz + kSide) % kSide;
  return bricks[size_t(other)].classes[size_t(ClassVolume::voxelIndex(nx, ny, nz))] != 0;
}

// Calls emit(brick, voxel index, x, y, z, face) for every visible face of
// voxel rows [rowBegin, rowEnd) (row = band * 8 + y), in the renderer's order.
template <typename Emit>
void visitVisibleFaces(const ClassVolume& volume, const std::vector<Band>& bands, size_t rowBegin, size_t rowEnd,
                       Emit&& emit) {
  const auto& bricks = volume.bricks();
  for (size_t row = rowBegin; row < rowEnd; ++row) {
    const Band& band = bands[row / kSide];
    const int y = int(row % kSide);
    size_t group = band.first;
    while (group < band.last) {  // bricks with the same w origin, ascending u
      size_t groupEnd = group;
      while (groupEnd < band.last && bricks[groupEnd].origin.w == bricks[group].origin.w) ++groupEnd;
      for (int z = 0; z < kSide; ++z)
        for (size_t bi = group; bi < groupEnd; ++bi) {
          const ClassVolume::Brick& b = bricks[bi];
          uint64_t bytes;  // the 8 class bytes of this row: skip empty rows at once
          std::memcpy(&bytes, &b.classes[size_t(ClassVolume::voxelIndex(0, y, z))], sizeof bytes);
          if (!bytes) continue;
          for (int x = 0; x < kSide; ++x) {
            const int i = ClassVolume::voxelIndex(x, y, z);
            if (!b.classes[size_t(i)]) continue;
            for (int f = 0; f < kBlockFaceCount; ++f)
              if (!neighbourOccupied(bricks, b, x, y, z, f)) emit(b, i, x, y, z, f);
          }
        }
      group = groupEnd;
    }
  }
}

// Faces of one bucket (direction, plane) are merged when their keys are equal.
bool sameSurface(const BlockQuad& a, const BlockQuad& b) {
  return a.classId == b.classId && std::memcmp(&a.color, &b.color, sizeof(RgbLinear)) == 0;
}

// Merges the unit faces quads[begin, end) of one (direction, plane) bucket,
// sorted by (second axis, first axis), into rectangles appended to `out`.
void mergeBucket(const std::vector<BlockQuad>& quads, size_t begin, size_t end, std::vector<BlockQuad>& out) {
  const auto [a, b] = inPlaneAxes(quads[begin].face);
  auto at = [](const BlockQuad& q, int axis) { return axis == 0 ? q.block.u : axis == 1 ? q.block.v : q.block.w; };
  struct Run {
    int32_t a0 = 0;
    uint32_t width = 0;
    const BlockQuad* first = nullptr;  // its leftmost face: block, class, colour
  };
  struct Open {
    Run run;
    uint32_t height = 1;
    bool extended = false;
  };
  std::vector<Open> open, next;
  std::vector<BlockQuad> rects;
  auto close = [&](const Open& o) {
    BlockQuad r = *o.run.first;
    r.extent = {o.run.width, o.height};
    rects.push_back(r);
  };
  int32_t prevRow = 0;
  size_t i = begin;
  while (i < end) {
    const int32_t row = at(quads[i], b);
    // This row's runs: consecutive first-axis positions with the same surface.
    std::vector<Run> runs;
    while (i < end && at(quads[i], b) == row) {
      Run r{at(quads[i], a), 1, &quads[i]};
      ++i;
      while (i < end && at(quads[i], b) == row && at(quads[i], a) == r.a0 + int32_t(r.width) &&
             sameSurface(quads[i], *r.first))
        ++r.width, ++i;
      runs.push_back(r);
    }
    // Stack a run on the open rectangle of the row below with the same span and surface.
    next.clear();
    const bool adjacent = !open.empty() && row == prevRow + 1;
    size_t k = 0;
    for (const Run& r : runs) {
      while (adjacent && k < open.size() && open[k].run.a0 < r.a0) ++k;
      if (adjacent && k < open.size() && open[k].run.a0 == r.a0 && open[k].run.width == r.width &&
          sameSurface(*open[k].run.first, *r.first)) {
        Open grown = open[k];
        grown.height += 1;
        open[k].extended = true;
        next.push_back(grown);
      } else {
        next.push_back({r, 1, false});
      }
    }
    for (const Open& o : open)
      if (!o.extended) close(o);
    for (Open& o : next) o.extended = false;
    open.swap(next);
    prevRow = row;
  }
  for (const Open& o : open) close(o);
  std::sort(rects.begin(), rects.end(), [&](const BlockQuad& p, const BlockQuad& q) {
    return std::pair(at(p, b), at(p, a)) < std::pair(at(q, b), at(q, a));
  });
  out.insert(out.end(), rects.begin(), rects.end());
}

}  // namespace

std::array<int, 2> inPlaneAxes(BlockFace face) {
  const int n = kBlockFaces[size_t(face)].axis();
  return n == 0 ? std::array{1, 2} : n == 1 ? std::array{0, 2} : std::array{0, 1};
}

BlockMesh meshVisibleFaces(const ClassVolume& volume, const ClassTable& classes, const BlockMeshSettings& settings) {
  if (settings.color == FaceColor::Voxel && !volume.withColor())
    throwUsage("voxel colours were asked for but the volume was read without them");
  const FacePalettes palettes(classes);
  const std::vector<Band> bands = bandsOf(volume.bricks());
  const size_t rows = bands.size() * size_t(kSide);
  // A fixed number of pieces, each written at its place in one array: the
  // result is the serial loop's output whatever the split. Counting first
  // costs a second walk but spares copying (and growing) every quad again.
  // At least one piece: parallelPieces runs one even for no rows (and takes 0
  // pieces as "one per worker"), which must find its offsets.
  const size_t pieces = std::max<size_t>(1, std::min<size_t>(rows, 64));
  std::vector<size_t> offset(pieces + 1, 0);
  parallelPieces(rows, settings.threads, pieces, [&](size_t begin, size_t end, size_t p) {
    size_t n = 0;
    visitVisibleFaces(volume, bands, begin, end, [&](const ClassVolume::Brick& b, int i, int, int, int, int) {
      if (!palettes.known[b.classes[size_t(i)]]) throwClassNotInTable(b.classes[size_t(i)], b.at(i));
      ++n;
    });
    offset[p + 1] = n;
  });
  for (size_t p = 0; p < pieces; ++p) offset[p + 1] += offset[p];
  if (settings.beforeAllocating) settings.beforeAllocating(offset[pieces]);
  BlockMesh mesh;
  mesh.quads.resize(offset[pieces]);
  std::vector<uint64_t> uncolored(pieces, 0);
  parallelPieces(rows, settings.threads, pieces, [&](size_t begin, size_t end, size_t p) {
    BlockQuad* out = mesh.quads.data() + offset[p];
    visitVisibleFaces(volume, bands, begin, end, [&](const ClassVolume::Brick& b, int i, int x, int y, int z, int f) {
      BlockQuad& q = *out++;
      const uint8_t cls = b.classes[size_t(i)];
      q.block = {b.origin.u + x, b.origin.v + y, b.origin.w + z};
      q.face = BlockFace(f);
      q.classId = cls;
      if (settings.color == FaceColor::Voxel && b.hasColor(i)) {
        q.color = b.colors[size_t(i)];
      } else {
        q.color = palettes.color[cls][size_t(f)];
        if (settings.color == FaceColor::Voxel) ++uncolored[p];
      }
    });
  });
  for (uint64_t n : uncolored) mesh.uncoloredFaces += n;
  mesh.unitFaces = mesh.quads.size();
  return mesh;
}

BlockMesh mergeCoplanarFaces(const BlockMesh& culled, unsigned threads) {
  // Bucket by (direction, plane), rows by (second axis, first axis). The sort
  // keys are computed once per quad (not in every comparison) and each
  // direction is sorted on its own, in parallel: this sort was most of a
  // large greedy export. A culled mesh has one face per block and direction,
  // so the keys are unique and the order is the lexicographic one; the index
  // only makes the order total.
  struct SortKey {
    int32_t plane, row, col;
    size_t index;
    bool operator<(const SortKey& o) const {
      return std::tie(plane, row, col, index) < std::tie(o.plane, o.row, o.col, o.index);
    }
  };
  // Memory: the keys and the quads in plane order are allocated at their
  // final size and freed as soon as they are used, so besides the culled
  // quads at most the plane-ordered copy or the joined result is alive, with
  // the merged planes (up to twice their quads while they grow): the bound
  // the export's guard counts, four quads' bytes per culled quad.
  std::array<std::vector<SortKey>, 6> byFace;
  std::array<size_t, 6> perFace{};
  for (const BlockQuad& q : culled.quads) ++perFace[size_t(q.face)];
  for (size_t f = 0; f < 6; ++f) byFace[f].reserve(perFace[f]);
  for (size_t i = 0; i < culled.quads.size(); ++i) {
    const BlockQuad& q = culled.quads[i];
    const int n = kBlockFaces[size_t(q.face)].axis();
    const auto [a, b] = inPlaneAxes(q.face);
    const int32_t c[3] = {q.block.u, q.block.v, q.block.w};
    byFace[size_t(q.face)].push_back({c[n], c[b], c[a], i});
  }
  parallelForEach(6, threads, 1, [&](size_t f) { std::sort(byFace[f].begin(), byFace[f].end()); });
  std::vector<BlockQuad> faces;
  faces.reserve(culled.quads.size());
  std::vector<size_t> starts;
  for (const std::vector<SortKey>& keys : byFace)
    for (size_t k = 0; k < keys.size(); ++k) {
      if (k == 0 || keys[k].plane != keys[k - 1].plane) starts.push_back(faces.size());
      faces.push_back(culled.quads[keys[k].index]);
    }
  starts.push_back(faces.size());
  byFace = {};
  const size_t buckets = starts.size() - 1;
  std::vector<std::vector<BlockQuad>> merged(buckets);
  parallelForEach(buckets, threads, 1, [&](size_t k) { mergeBucket(faces, starts[k], starts[k + 1], merged[k]); });
  faces = {};
  BlockMesh out;
  size_t total = 0;
  for (const auto& m : merged) total += m.size();
  out.quads.reserve(total);
  for (auto& m : merged) {
    out.quads.insert(out.quads.end(), m.begin(), m.end());
    m = {};
  }
  out.unitFaces = culled.unitFaces;
  out.uncoloredFaces = culled.uncoloredFaces;
  return out;
}

std::vector<std::vector<BlockQuad>> quadsByClass(const BlockMesh& mesh) {
  std::array<size_t, 256> count{};
  for (const BlockQuad& q : mesh.quads) ++count[q.classId];
  std::vector<std::vector<BlockQuad>> groups;
  std::array<int, 256> slot{};
  for (int c = 0; c < 256; ++c) {
    if (!count[size_t(c)]) continue;
    slot[size_t(c)] = int(groups.size());
    groups.emplace_back().reserve(count[size_t(c)]);
  }
  for (const BlockQuad& q : mesh.quads) groups[size_t(slot[q.classId])].push_back(q);
  return groups;
}

std::array<BlockVertex, 4> quadVertices(const BlockQuad& quad, const GridFrame& frame) {
  const BlockFaceDef& def = kBlockFaces[size_t(quad.face)];
  const auto [a, b] = inPlaneAxes(quad.face);
  std::array<uint32_t, 3> extent{1, 1, 1};
  extent[size_t(a)] = quad.extent[0];
  extent[size_t(b)] = quad.extent[1];
  // Which axis each texture coordinate follows: uv component k of the face's
  // corners equals that axis's corner offset, or its complement.
  std::array<uint32_t, 2> uvScale{1, 1};
  for (int k = 0; k < 2; ++k)
    for (int axis : {a, b}) {
      bool same = true, complement = true;
      for (int c = 0; c < 4; ++c) {
        same = same && def.uvs[size_t(c)][size_t(k)] == def.corners[size_t(c)][size_t(axis)];
        complement = complement && def.uvs[size_t(c)][size_t(k)] == 1 - def.corners[size_t(c)][size_t(axis)];
      }
      if (same || complement) uvScale[size_t(k)] = extent[size_t(axis)];
    }
  const int32_t base[3] = {quad.block.u, quad.block.v, quad.block.w};
  std::array<BlockVertex, 4> out;
  for (int c = 0; c < 4; ++c) {
    BlockVertex& v = out[size_t(c)];
    for (int i = 0; i < 3; ++i) {
      const double grid = double(base[i]) + double(def.corners[size_t(c)][size_t(i)]) * double(extent[size_t(i)]);
      v.position[size_t(i)] = float(grid * frame.voxelSize + frame.origin[size_t(i)]);
      v.normal[size_t(i)] = float(def.normal[size_t(i)]);
    }
    v.color = {quad.color.r, quad.color.g, quad.color.b};
    for (int k = 0; k < 2; ++k) v.uv[size_t(k)] = float(def.uvs[size_t(c)][size_t(k)] * uvScale[size_t(k)]);
  }
  return out;
}

}  // namespace vox
