#include "formats/vdb/vdb_grid_input.h"

#include <openvdb/tools/Interpolation.h>

#include <atomic>
#include <cmath>

#include "formats/vdb/vdb_checked_file.h"
#include "libvox/core/error.h"
#include "libvox/core/memory_budget.h"
#include "libvox/core/parallel.h"
#include "libvox/mesh/placement.h"
#include "libvox/scene/scene_grids.h"
#include "libvox/core/sha256.h"
#include "libvox/core/utf8.h"
#include "libvox/mesh/voxelize.h"

namespace vox {

namespace {

/// The memory guard (libvox/core/memory_budget.h): the inside bits cover the
/// whole output grid (one bit per voxel); the scene holds the inside voxels,
/// whose share is measured on a 32^3 lattice of output voxel centres (cheap:
/// 32768 samples). Refuses before the sampling, with the largest resolution
/// that fits (the estimate scales with the voxel count).
template <typename GridT>
void checkGridInputMemory(const GridT& grid, bool levelSet, double thr, const SceneHeader& header,
                          const std::string& path, double sampledShare) {
  const Dims dims = header.dims;
  const double count = double(dims.count()) * sampledShare;  // a region samples its share
  const typename GridT::ConstAccessor accessor = grid.getConstAccessor();
  openvdb::tools::GridSampler<typename GridT::ConstAccessor, openvdb::tools::BoxSampler> sampler(accessor,
                                                                                                 grid.transform());
  const uint32_t n[3] = {std::min(dims.x, 32u), std::min(dims.y, 32u), std::min(dims.z, 32u)};
  uint64_t inside = 0, samples = 0;
  for (uint32_t a = 0; a < n[0]; ++a)
    for (uint32_t b = 0; b < n[1]; ++b)
      for (uint32_t c = 0; c < n[2]; ++c) {
        const double u = (a + 0.5) * dims.x / n[0], v = (b + 0.5) * dims.y / n[1], w = (c + 0.5) * dims.z / n[2];
        const openvdb::Vec3d p(header.origin[0] + u * header.voxelSize, header.origin[1] + v * header.voxelSize,
                               header.origin[2] + w * header.voxelSize);
        const openvdb::Vec3d ip = grid.worldToIndex(p);
        if (!(std::abs(ip.x()) < 1e9 && std::abs(ip.y()) < 1e9 && std::abs(ip.z()) < 1e9)) continue;
        const auto value = sampler.isSample(ip);
        ++samples;
        if (levelSet ? value <= 0 : double(value) >= thr) ++inside;
      }
  const double share = samples ? std::max(double(inside) / double(samples), 0.01) : 1.0;
  // Per inside voxel: its share of an 8^3 builder block with one 2 KB vote
  // block, then of the scene's occupancy, surface and vote leaves (measured:
  // docs/reliability.md "Memory").
  constexpr double kPerInsideVoxel = 12.0;
  const double resident = double(residentBytesNow());
  auto estimateAt = [&](double scale) {  // scale: voxel count relative to this grid's
    MemoryEstimate e;
    e.add("resident before sampling", resident);
    e.add("inside bits", count * scale / 8);
    e.add("scene", count * scale * share * kPerInsideVoxel);
    return e;
  };
  const MemoryEstimate e = estimateAt(1.0);
  const MemoryLimit limit = processMemoryLimit();
  std::string suggestion;
  if (!limit.unlimited() && e.bytes() > limit.bytes) {
    const uint32_t res = dims.maxAxis();
    const uint64_t best = largestFitting(1, res, suggestionBudget(limit.bytes), [&](uint64_t r) {
      const double k = double(r) / res;
      return estimateAt(k * k * k).bytes();
    });
    if (best)
      suggestion = "a resolution of " + std::to_string(best) + " would need about " +
                   formatBytes(estimateAt(std::pow(double(best) / res, 3)).bytes());
  }
  checkProcessMemory(e, "resampling " + path + " at " + toString(dims), suggestion);
}

/// The scene of one level set or fog volume; GridT: FloatGrid or DoubleGrid
/// (sampled and compared in the grid's own precision).
template <typename GridT>
Scene sceneFromGrid(const typename GridT::Ptr& grid, const std::string& path, const VdbGridInputOptions& o) {
  const std::string name = grid->getName().empty() ? "inside" : utf8FromLegacy(grid->getName());  // the class name, written in JSON
  const bool levelSet = grid->getGridClass() == openvdb::GRID_LEVEL_SET;
  if (!levelSet && !o.threshold)
    throwUsage(path + ": grid '" + name + "' is not a level set (a fog volume?); give the density threshold T above "
                   "which a voxel is inside (value >= T)",
               Setting::GridThreshold);
  // A level set's inside is its sign; a threshold would change nothing.
  if (levelSet && o.threshold)
    throwUsage(path + ": grid '" + name + "' is a level set, inside where its value <= 0, so a density threshold "
                   "does not apply to it; drop the threshold",
               Setting::GridThreshold);
  if (grid->activeVoxelCount() == 0) throwBadInput(path + ": grid '" + name + "' has no active voxels");

  // Index box of the active values that are inside (for level sets the narrow
  // band's inner half; deep interior is bounded by it), then its world box.
  const double thr = o.threshold.value_or(0.0);
  openvdb::CoordBBox ibox;
  for (auto it = grid->cbeginValueOn(); it; ++it)
    if (levelSet ? *it <= 0 : double(*it) >= thr) ibox.expand(it.getBoundingBox());
  if (ibox.empty())
    throwBadInput(path + ": grid '" + name + "' has no voxel inside (" +
                  (levelSet ? std::string("no value <= 0") : "no value >= " + std::to_string(thr)) + ")");
  openvdb::Vec3d wmin(std::numeric_limits<double>::max()), wmax(-std::numeric_limits<double>::max());
  for (int c = 0; c < 8; ++c) {
    const openvdb::Vec3d ip(c & 1 ? ibox.max().x() + 0.5 : ibox.min().x() - 0.5,
                            c & 2 ? ibox.max().y() + 0.5 : ibox.min().y() - 0.5,
                            c & 4 ? ibox.max().z() + 0.5 : ibox.min().z() - 0.5);
    const openvdb::Vec3d wp = grid->indexToWorld(ip);
    wmin = openvdb::math::minComponent(wmin, wp);
    wmax = openvdb::math::maxComponent(wmax, wp);
  }
  for (int a = 0; a < 3; ++a)
    if (!(std::fabs(wmin[a]) <= kMaxWorldCoordinate) || !(std::fabs(wmax[a]) <= kMaxWorldCoordinate))
      throwBadInput(path + ": grid '" + name + "': its transform places the grid beyond +-1e15 world units (a "
                    "degenerate or extreme transform); no scene can hold it");
  SceneHeader header;
  PlacementOptions place;
  place.resolution = o.resolution;
  place.voxelSize = o.voxelSize;
  placeGrid({wmin.x(), wmin.y(), wmin.z()}, {wmax.x(), wmax.y(), wmax.z()}, place, header);
  const Dims dims = header.dims;
  const double vs = header.voxelSize;
  header.classes.add({1, name, {200, 200, 200}, std::nullopt}, path);
  uint64_t bytes = 0;
  const std::string sha = sha256File(path, &bytes);
  header.sources.push_back({path, "vdb", sha, bytes});
  // The voxels to build ([lo, hi]: the whole grid, or a region's box) and the
  // ones to sample: those plus a 1-voxel halo, for the surface test.
  int64_t lo[3] = {0, 0, 0}, hi[3] = {int64_t(dims.x) - 1, int64_t(dims.y) - 1, int64_t(dims.z) - 1};
  const int64_t dimv[3] = {dims.x, dims.y, dims.z};
  if (o.regionOf)
    if (const std::optional<IndexBox> box = o.regionOf(header)) {
      const int64_t bl[3] = {box->min.u, box->min.v, box->min.w}, bh[3] = {box->max.u, box->max.v, box->max.w};
      for (int k = 0; k < 3; ++k) lo[k] = std::max(lo[k], bl[k]), hi[k] = std::min(hi[k], bh[k]);
      if (box->empty()) hi[0] = lo[0] - 1;
    }
  SceneBuilder builder(header);
  if (lo[0] > hi[0] || lo[1] > hi[1] || lo[2] > hi[2]) return std::move(builder).build();
  int64_t slo[3], shi[3], sext[3];
  for (int k = 0; k < 3; ++k)
    slo[k] = std::max<int64_t>(0, lo[k] - 1), shi[k] = std::min<int64_t>(dimv[k] - 1, hi[k] + 1),
    sext[k] = shi[k] - slo[k] + 1;
  const uint64_t count = uint64_t(sext[0]) * uint64_t(sext[1]) * uint64_t(sext[2]);
  checkGridInputMemory(*grid, levelSet, thr, header, path, double(count) / double(dims.count()));

  // Inside test at every sampled voxel centre, one slab of w per thread; each
  // voxel sets its own bit, so the result does not depend on the split.
  std::vector<std::atomic<uint64_t>> inside((count + 63) / 64);
  const uint32_t slicesTotal = uint32_t(sext[2]);
  const unsigned slabs = std::max(1u, std::min<unsigned>(o.threads, slicesTotal));
  std::atomic<uint32_t> slices{0};
  // A degenerate or extreme transform (a scale of 1e-170, a near-singular
  // matrix) maps output voxel centres to index coordinates no 32-bit node
  // holds; OpenVDB's sampler would convert them to int regardless.
  constexpr double kIndexLimit = double(1 << 30);
  std::atomic<bool> outOfRange{false};
  auto bit = [&](int64_t u, int64_t v, int64_t w) {
    return (uint64_t(w - slo[2]) * uint64_t(sext[1]) + uint64_t(v - slo[1])) * uint64_t(sext[0]) + uint64_t(u - slo[0]);
  };
  parallelPieces(slicesTotal, slabs, slabs, [&](size_t w0, size_t w1, size_t) {
    // GridSampler keeps a reference to the accessor: it must outlive the sampler.
    const typename GridT::ConstAccessor accessor = grid->getConstAccessor();
    openvdb::tools::GridSampler<typename GridT::ConstAccessor, openvdb::tools::BoxSampler> sampler(
        accessor, grid->transform());
    for (int64_t w = slo[2] + int64_t(w0); w < slo[2] + int64_t(w1); ++w) {
      for (int64_t v = slo[1]; v <= shi[1]; ++v)
        for (int64_t u = slo[0]; u <= shi[0]; ++u) {
          const openvdb::Vec3d p(wmin.x() + (u + 0.5) * vs, wmin.y() + (v + 0.5) * vs, wmin.z() + (w + 0.5) * vs);
          const openvdb::Vec3d ip = grid->worldToIndex(p);
          if (!(std::abs(ip.x()) < kIndexLimit && std::abs(ip.y()) < kIndexLimit && std::abs(ip.z()) < kIndexLimit)) {
            outOfRange.store(true, std::memory_order_relaxed);
            continue;
          }
          const auto value = sampler.isSample(ip);
          if (levelSet ? value <= 0 : double(value) >= thr) {
            const uint64_t i = bit(u, v, w);
            inside[i >> 6].fetch_or(uint64_t(1) << (i & 63), std::memory_order_relaxed);
          }
        }
      if (o.progress) o.progress(double(++slices) / slicesTotal);
    }
  });

  if (outOfRange)
    throwBadInput(path + ": grid '" + name + "': its transform maps the region to sample to index coordinates beyond "
                  "+-2^30 (a degenerate or extreme transform)");
  auto in = [&](int64_t u, int64_t v, int64_t w) {
    if (u < slo[0] || v < slo[1] || w < slo[2] || u > shi[0] || v > shi[1] || w > shi[2]) return false;
    const uint64_t i = bit(u, v, w);
    return ((inside[i >> 6].load(std::memory_order_relaxed) >> (i & 63)) & 1) != 0;
  };
  for (int64_t w = lo[2]; w <= hi[2]; ++w)
    for (int64_t v = lo[1]; v <= hi[1]; ++v)
      for (int64_t u = lo[0]; u <= hi[0]; ++u) {
        if (!in(u, v, w)) continue;
        const bool surface = !in(u - 1, v, w) || !in(u + 1, v, w) || !in(u, v - 1, w) || !in(u, v + 1, w) ||
                             !in(u, v, w - 1) || !in(u, v, w + 1);
        builder.addVotes({int32_t(u), int32_t(v), int32_t(w)}, 1, kInteriorVotes, surface);
      }
  return std::move(builder).build();
}

}  // namespace

Scene readVdbGridAsScene(const std::string& path, const VdbGridInputOptions& o) {
  ensureOpenVdbInitialized();
  if ((o.resolution == 0) == (o.voxelSize <= 0))
    throwUsage(path + ": give exactly one of a resolution or a voxel size for an OpenVDB grid", Setting::Resolution);
  CheckedVdbFile file(path);  // refuses corrupt files before OpenVDB reads them
  openvdb::GridBase::Ptr grid;
  std::string available;
  for (const VdbGridFrame& g : file.frame().grids) {
    available += (available.empty() ? "" : ", ") + g.uniqueName + " (" + g.type + ")";
    const bool isScalar = g.type.rfind("Tree_float_", 0) == 0 || g.type.rfind("Tree_double_", 0) == 0;
    if (!grid && ((o.gridName.empty() && isScalar) || g.uniqueName == o.gridName)) {
      grid = file.readGrid(g.uniqueName);
      if (!grid->isType<openvdb::FloatGrid>() && !grid->isType<openvdb::DoubleGrid>())
        throwBadInput(path + ": grid '" + g.uniqueName + "' has type " + grid->type() +
                      "; vox reads float and double grids (level sets and fog volumes)");
    }
  }
  if (!grid)
    throwBadInput(path + ": " + (o.gridName.empty() ? std::string("no float or double grid") : "no grid named '" + o.gridName + "'") +
                  "; grids in the file: " + (available.empty() ? "none" : available));
  if (auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(grid)) return sceneFromGrid<openvdb::FloatGrid>(f, path, o);
  return sceneFromGrid<openvdb::DoubleGrid>(openvdb::gridPtrCast<openvdb::DoubleGrid>(grid), path, o);
}

}  // namespace vox
