#include "libvox/core/regions.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <tuple>

#include "libvox/core/error.h"
#include "libvox/core/sha256.h"

namespace vox {

namespace {

[[noreturn]] void badSpec(std::string_view text, const std::string& why) {
  throw Error(ErrorKind::Usage, "--region " + std::string(text) + ": " + why +
                                    "; expected I/N with 0 <= I < N, e.g. 0/4 for the first of four tiles");
}

bool parseUint(std::string_view s, uint32_t& out) {
  if (s.empty()) return false;
  const char* end = s.data() + s.size();
  auto [p, ec] = std::from_chars(s.data(), end, out);
  return ec == std::errc() && p == end;
}

// A box of 32-voxel cells in x and z: [x0, x1) x [z0, z1).
struct CellBox {
  uint64_t x0, x1, z0, z1;
};

CellBox tileCells(CellBox box, uint32_t index, uint32_t count) {
  while (count > 1) {
    const uint32_t lowCount = count / 2;
    const uint64_t xCells = box.x1 - box.x0, zCells = box.z1 - box.z0;
    const bool alongX = xCells >= zCells;
    const uint64_t cells = alongX ? xCells : zCells;
    // round(cells * lowCount / count), ties down, kept inside [1, cells - 1].
    uint64_t cut = (2 * cells * lowCount + count - 1) / (2 * uint64_t(count));
    if (cells >= 2) cut = std::clamp<uint64_t>(cut, 1, cells - 1);
    else cut = std::min<uint64_t>(cut, cells);
    const bool low = index < lowCount;
    if (alongX) {
      if (low) box.x1 = box.x0 + cut;
      else box.x0 = box.x0 + cut;
    } else {
      if (low) box.z1 = box.z0 + cut;
      else box.z0 = box.z0 + cut;
    }
    if (low) {
      count = lowCount;
    } else {
      index -= lowCount;
      count -= lowCount;
    }
  }
  return box;
}

uint64_t cellsOf(uint32_t voxels) { return (uint64_t(voxels) + kRegionAlignVoxels - 1) / kRegionAlignVoxels; }

}  // namespace

RegionSpec parseRegionSpec(std::string_view text) {
  const size_t slash = text.find('/');
  if (slash == std::string_view::npos) badSpec(text, "no '/'");
  RegionSpec spec;
  if (!parseUint(text.substr(0, slash), spec.index) || !parseUint(text.substr(slash + 1), spec.count))
    badSpec(text, "I and N must be non-negative decimal integers");
  if (spec.count == 0) badSpec(text, "N must be at least 1");
  if (spec.count > kMaxRegionCount) badSpec(text, "N is above " + std::to_string(kMaxRegionCount));
  if (spec.index >= spec.count)
    badSpec(text, "I must be below N (tiles are numbered 0.." + std::to_string(spec.count - 1) + ")");
  return spec;
}

IndexBox regionTile(const Dims& dims, uint32_t index, uint32_t count) {
  if (count == 0 || index >= count) throw Error(ErrorKind::Internal, "regionTile: index out of range");
  const CellBox cells = tileCells({0, cellsOf(dims.x), 0, cellsOf(dims.z)}, index, count);
  if (cells.x0 >= cells.x1 || cells.z0 >= cells.z1) return IndexBox{};
  IndexBox box;
  box.min = {int32_t(cells.x0 * kRegionAlignVoxels), 0, int32_t(cells.z0 * kRegionAlignVoxels)};
  box.max = {int32_t(std::min<uint64_t>(cells.x1 * kRegionAlignVoxels, dims.x) - 1), int32_t(dims.y) - 1,
             int32_t(std::min<uint64_t>(cells.z1 * kRegionAlignVoxels, dims.z) - 1)};
  return box;
}

std::vector<IndexBox> regionTiles(const Dims& dims, uint32_t count) {
  std::vector<IndexBox> tiles;
  tiles.reserve(count);
  for (uint32_t i = 0; i < count; ++i) tiles.push_back(regionTile(dims, i, count));
  return tiles;
}

bool isRegionAligned(const IndexBox& box, const Dims& dims) {
  if (box.empty()) return true;
  const int64_t a = kRegionAlignVoxels;
  auto edgeOk = [&](int64_t lo, int64_t hi, uint32_t n) {
    return lo >= 0 && hi < int64_t(n) && lo % a == 0 && ((hi + 1) % a == 0 || hi + 1 == int64_t(n));
  };
  return edgeOk(box.min.u, box.max.u, dims.x) && edgeOk(box.min.v, box.max.v, dims.y) &&
         edgeOk(box.min.w, box.max.w, dims.z);
}

std::string regionWorldKey(const SceneHeader& h, std::string_view settings) {
  // A canonical text of the fields, then its digest. %.17g keeps doubles exact.
  std::string text = "vox-region-world-1\n";
  char buf[128];
  std::snprintf(buf, sizeof buf, "dims %u %u %u\n", h.dims.x, h.dims.y, h.dims.z);
  text += buf;
  std::snprintf(buf, sizeof buf, "placement %.17g %.17g %.17g %.17g\n", h.voxelSize, h.origin[0], h.origin[1],
                h.origin[2]);
  text += buf;
  text += "mip " + std::to_string(h.mipLevel) + "\n";
  for (const ClassInfo& c : h.classes.classes()) {
    std::snprintf(buf, sizeof buf, "class %u %u %u %u ", unsigned(c.id), unsigned(c.color.r), unsigned(c.color.g),
                  unsigned(c.color.b));
    text += buf + c.name + "\n";
  }
  for (const SceneSource& s : h.sources)
    text += "source " + s.kind + " " + (s.sha256.empty() ? s.path : s.sha256 + " " + std::to_string(s.bytes)) + "\n";
  if (h.blockWorld) {
    std::snprintf(buf, sizeof buf, "blockworld %.17g %u %u %u\n", h.blockWorld->worldScale, h.blockWorld->gridSize[0],
                  h.blockWorld->gridSize[1], h.blockWorld->gridSize[2]);
    text += buf;
  }
  text += "settings ";
  text += settings;
  text += "\n";
  Sha256 sha;
  sha.update(text.data(), text.size());
  return sha.hexDigest();
}

bool isTile(const SceneRegion& r, const Dims& dims) {
  return r.count >= 1 && r.index < r.count && regionTile(dims, r.index, r.count) == r.box;
}

namespace {

std::string tileName(const SceneRegion& r) { return "tile " + std::to_string(r.index) + " of " + std::to_string(r.count); }

std::string boxText(const IndexBox& b) {
  return b.empty() ? std::string("an empty box") : toString(b.min) + " .. " + toString(b.max);
}

// Why `h` is not a part of the same world as `first`, or "".
std::string worldDifference(const SceneHeader& h, const SceneHeader& first) {
  if (h.region->worldKey != first.region->worldKey)
    return "its world key " + h.region->worldKey.substr(0, 12) + " differs from " + first.region->worldKey.substr(0, 12);
  if (!(h.dims == first.dims)) return "its dims " + toString(h.dims) + " differ from " + toString(first.dims);
  if (h.voxelSize != first.voxelSize || h.origin != first.origin) return "its voxel size or origin differs";
  if (!(h.classes == first.classes)) return "its class table differs";
  if (h.mipLevel != first.mipLevel) return "its mip level differs";
  if (h.blockWorld != first.blockWorld) return "its block-world placement differs";
  return {};
}

}  // namespace

RegionPartSet checkRegionParts(const std::vector<RegionPart>& parts) {
  if (parts.empty()) throw Error(ErrorKind::Usage, "no parts to merge");
  for (const RegionPart& p : parts)
    if (!p.header->region)
      throwBadInput(p.path + ": not a part of a region bake (no region record); merge the parts that "
                             "`--region I/N` or `--region-box` wrote");
  const SceneHeader& first = *parts.front().header;
  for (const RegionPart& p : parts)
    if (const std::string why = worldDifference(*p.header, first); !why.empty())
      throwBadInput(p.path + ": a part of another bake than " + parts.front().path + " (" + why +
                    "); merge only the parts of one bake, made with the same inputs and settings");
  bool allTiles = true;
  for (const RegionPart& p : parts) allTiles = allTiles && isTile(*p.header->region, first.dims);
  if (allTiles) {
    const uint32_t count = first.region->count;
    std::vector<const RegionPart*> byIndex(count, nullptr);
    for (const RegionPart& p : parts) {
      const SceneRegion& r = *p.header->region;
      if (r.count != count)
        throwBadInput(p.path + ": " + tileName(r) + ", but " + parts.front().path + " is " + tileName(*first.region) +
                      "; merge the parts of one tiling");
      if (byIndex[r.index])
        throwBadInput(p.path + ": " + tileName(r) + " is also " + byIndex[r.index]->path + "; give each tile once");
      byIndex[r.index] = &p;
    }
    for (uint32_t i = 0; i < count; ++i)
      if (!byIndex[i])
        throwBadInput("tile " + std::to_string(i) + " of " + std::to_string(count) +
                      " is missing (the part `--region " + std::to_string(i) + "/" + std::to_string(count) +
                      "` writes); bake it and merge all " + std::to_string(count) + " parts");
    return RegionPartSet::Tiles;
  }
  // Boxes (`--region-box` records tile 0 of 1 with its box): no tiles of a larger tiling among them.
  for (const RegionPart& p : parts) {
    const SceneRegion& r = *p.header->region;
    if (r.count > 1) {
      const RegionPart* other = nullptr;
      for (const RegionPart& q : parts)
        if (q.header->region->count == 1) other = &q;
      throwBadInput(p.path + ": " + tileName(r) + (isTile(r, first.dims) ? "" : " with a box that is not that tile") +
                    (other ? ", but " + other->path + " is a `--region-box` part" : std::string()) +
                    "; merge the parts of one tiling, or of `--region-box` only");
    }
  }
  // Boxes: pairwise disjoint. Sorted by min u so that only neighbours in u are compared.
  std::vector<const RegionPart*> order;
  for (const RegionPart& p : parts) order.push_back(&p);
  std::sort(order.begin(), order.end(), [](const RegionPart* a, const RegionPart* b) {
    return a->header->region->box.min.u < b->header->region->box.min.u;
  });
  for (size_t i = 0; i < order.size(); ++i) {
    const IndexBox& a = order[i]->header->region->box;
    if (a.empty()) continue;
    for (size_t j = i + 1; j < order.size(); ++j) {
      const IndexBox& b = order[j]->header->region->box;
      if (b.empty()) continue;
      if (b.min.u > a.max.u) break;
      if (!intersect(a, b).empty())
        throwBadInput(order[j]->path + ": its box " + boxText(b) + " overlaps the box " + boxText(a) + " of " +
                      order[i]->path + "; merge parts with disjoint boxes");
    }
  }
  return RegionPartSet::Boxes;
}

size_t worldHeaderPart(const std::vector<RegionPart>& parts) {
  // Parts of one bake may differ only where the world key does not look:
  // the sources' paths as spelled on each part's command line (./a.obj, a.obj,
  // another directory). The merge takes them from one part chosen by what the
  // parts hold, never by their order, so any order writes the same bytes.
  auto key = [](const RegionPart& p) {
    const SceneRegion& r = *p.header->region;
    const IndexBox& b = r.box;
    std::string sources;
    for (const SceneSource& s : p.header->sources) sources += s.kind + '\n' + s.path + '\n';
    return std::make_tuple(r.index, b.empty(), b.min.w, b.min.v, b.min.u, b.max.w, b.max.v, b.max.u, sources);
  };
  size_t best = 0;
  for (size_t i = 1; i < parts.size(); ++i)
    if (key(parts[i]) < key(parts[best])) best = i;
  return best;
}

IndexBox intersect(const IndexBox& a, const IndexBox& b) {
  if (a.empty() || b.empty()) return IndexBox{};
  IndexBox r;
  r.min = {std::max(a.min.u, b.min.u), std::max(a.min.v, b.min.v), std::max(a.min.w, b.min.w)};
  r.max = {std::min(a.max.u, b.max.u), std::min(a.max.v, b.max.v), std::min(a.max.w, b.max.w)};
  return r.empty() ? IndexBox{} : r;
}

}  // namespace vox
