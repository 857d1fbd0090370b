// The render inputs that need no OpenVDB (page files, scenes read as leaves):
// linked by the light render module and by vox-cmds.so.
#include "tools/cmds/render_input.h"

#include <chrono>

#include "formats/pagefile/pagefile.h"
#include "formats/pagefile/pagefile_meta.h"
#include "formats/pagefile/pagefile_ray_grid.h"
#include "formats/vdb/vdb_leaves_render.h"
#include "formats/vdb/vdb_scene_leaves.h"
#include "libvox/core/error.h"
#include "tools/cli/cli.h"

namespace voxcli {

namespace {

double secondsBetween(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

class PageVoxels final : public RenderVoxels {
 public:
  PageVoxels(vox::pagefile::Reader reader, int level) : reader_(std::move(reader)), level_(level) {}
  std::vector<vox::SummaryTexel> summaries(std::span<const vox::Coord3> voxels) const override {
    return vox::pageSummaries(reader_, level_, voxels);
  }
  std::vector<vox::VoxelColor8> colors(std::span<const vox::Coord3> voxels) const override {
    return vox::pageColors(reader_, level_, voxels);
  }
  bool hasColor() const override { return (reader_.header().flags & vox::pagefile::kFlagColor) != 0; }
  const vox::pagefile::Reader& reader() const { return reader_; }

 private:
  vox::pagefile::Reader reader_;
  int level_;
};

class LeavesVoxels final : public RenderVoxels {
 public:
  explicit LeavesVoxels(vox::SceneLeaves leaves) : leaves_(std::move(leaves)), lookup_(leaves_) {}
  LeavesVoxels(const LeavesVoxels&) = delete;  // lookup_ refers to leaves_
  LeavesVoxels& operator=(const LeavesVoxels&) = delete;
  std::vector<vox::SummaryTexel> summaries(std::span<const vox::Coord3> voxels) const override {
    return lookup_.summaries(voxels);
  }
  std::vector<vox::VoxelColor8> colors(std::span<const vox::Coord3> voxels) const override {
    return lookup_.colors(voxels);
  }
  bool hasColor() const override { return leaves_.hasColor; }
  const vox::SceneLeaves& leaves() const { return leaves_; }

 private:
  vox::SceneLeaves leaves_;
  vox::SceneLeavesLookup lookup_;  // refers to leaves_
};

}  // namespace

RenderInput loadPageRenderInput(const std::string& path, int level) {
  RenderInput in;
  const auto t0 = std::chrono::steady_clock::now();
  in.path = path;
  in.level = level;
  in.kind = "pages";
  auto pages = std::make_shared<PageVoxels>(vox::pagefile::Reader::open(path), level);
  const vox::pagefile::Reader& reader = pages->reader();
  const vox::pagefile::Header& h = reader.header();
  if (level < 0 || level >= int(h.levelCount))
    throwLevelOutOfRange(level, path, h.levelCount);
  const auto d = h.levelDims(level);
  in.dims = {d[0], d[1], d[2]};
  in.frame.origin = h.origin;
  in.frame.voxelSize = h.voxelSize * double(uint64_t(1) << level);
  in.classes = vox::pagefile::readPageMeta(reader.metaJson(), path).classes;
  const auto t1 = std::chrono::steady_clock::now();
  in.grid = std::make_unique<vox::RayGrid>(vox::rayGridFromPages(reader, level));
  in.voxels = std::move(pages);
  in.readSeconds = secondsBetween(t0, t1);
  in.gridSeconds = secondsBetween(t1, std::chrono::steady_clock::now());
  return in;
}

void checkSceneLevel(const std::string& path, int level) {
  if (level != 0) vox::throwUsage("--level " + std::to_string(level) + ": only page files (.vpk) hold levels; " + path + " is a scene");
}

vox::WorldBox RenderInput::occupiedWorldBox() const {
  std::array<int64_t, 3> lo = grid->occupiedMin(), hi = grid->occupiedEnd();
  if (grid->occupiedCount() == 0) lo = {0, 0, 0}, hi = {dims.x, dims.y, dims.z};
  vox::WorldBox box;
  for (size_t a = 0; a < 3; ++a) {
    box.min[a] = frame.origin[a] + double(lo[a]) * frame.voxelSize;
    box.max[a] = frame.origin[a] + double(hi[a]) * frame.voxelSize;
  }
  return box;
}

std::optional<RenderInput> loadRenderInputLight(const std::string& path, int level, bool needSummaries) {
  if (vox::pagefile::looksLikePageFile(path)) return loadPageRenderInput(path, level);
  checkSceneLevel(path, level);
  const auto t0 = std::chrono::steady_clock::now();
  std::optional<vox::SceneLeaves> leaves;
  try {
    leaves = vox::readSceneLeaves(path, needSummaries ? vox::SceneLeafParts::All : vox::SceneLeafParts::OccupancyOnly);
  } catch (const vox::Error&) {
    return std::nullopt;  // missing, corrupt, too large: the OpenVDB reader names it in its own words
  } catch (const std::bad_alloc&) {
    return std::nullopt;
  }
  if (!leaves) return std::nullopt;
  RenderInput in;
  in.path = path;
  in.kind = "scene";
  in.dims = leaves->header.dims;
  in.frame.origin = leaves->header.origin;
  in.frame.voxelSize = leaves->header.voxelSize;  // already the level's voxel size for mip scenes
  in.classes = leaves->header.classes;
  auto voxels = std::make_shared<LeavesVoxels>(std::move(*leaves));
  const auto t1 = std::chrono::steady_clock::now();
  in.grid = std::make_unique<vox::RayGrid>(vox::rayGridFromLeaves(voxels->leaves()));
  in.voxels = std::move(voxels);
  in.readSeconds = secondsBetween(t0, t1);
  in.gridSeconds = secondsBetween(t1, std::chrono::steady_clock::now());
  return in;
}

}  // namespace voxcli
