#include "tools/cmds/render_input.h"

#include <chrono>

#include "formats/pagefile/pagefile_meta.h"
#include "formats/vdb/scene_vdb.h"
#include "libvox/core/error.h"

namespace voxcli {

std::vector<vox::SummaryTexel> RenderInput::summaries(std::span<const vox::Coord3> voxels) const {
  if (scene) return vox::sceneSummaries(*scene, voxels);
  return vox::pageSummaries(*pages, level, voxels);
}

std::vector<vox::VoxelColor8> RenderInput::colors(std::span<const vox::Coord3> voxels) const {
  if (scene) return vox::sceneColors(*scene, voxels);
  return vox::pageColors(*pages, level, voxels);
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

bool RenderInput::hasColor() const {
  if (scene) return scene->hasColor();
  return (pages->header().flags & vox::pagefile::kFlagColor) != 0;
}

RenderInput loadRenderInput(const std::string& path, int level, bool needSummaries) {
  RenderInput in;
  const auto t0 = std::chrono::steady_clock::now();
  auto seconds = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
  in.path = path;
  in.level = level;
  if (vox::pagefile::looksLikePageFile(path)) {
    in.kind = "pages";
    in.pages.emplace(vox::pagefile::Reader::open(path));
    const vox::pagefile::Header& h = in.pages->header();
    if (level < 0 || level >= int(h.levelCount))
      vox::throwUsage("--level " + std::to_string(level) + ": " + path + " holds levels 0.." +
                      std::to_string(h.levelCount - 1));
    const auto d = h.levelDims(level);
    in.dims = {d[0], d[1], d[2]};
    in.frame.origin = h.origin;
    in.frame.voxelSize = h.voxelSize * double(uint64_t(1) << level);
    in.classes = vox::pagefile::readPageMeta(in.pages->metaJson(), path).classes;
    const auto t1 = std::chrono::steady_clock::now();
    in.grid = std::make_unique<vox::RayGrid>(vox::rayGridFromPages(*in.pages, level));
    in.readSeconds = seconds(t0, t1);
    in.gridSeconds = seconds(t1, std::chrono::steady_clock::now());
    return in;
  }
  if (level != 0) vox::throwUsage("--level " + std::to_string(level) + ": only page files (.vpk) hold levels; " + path + " is a scene");
  in.kind = "scene";
  in.scene.emplace(vox::readSceneVdb(path, needSummaries ? vox::SceneParts::All : vox::SceneParts::OccupancyOnly));
  const vox::SceneHeader& h = in.scene->header();
  in.dims = h.dims;
  in.frame.origin = h.origin;
  in.frame.voxelSize = h.voxelSize;  // already the level's voxel size for mip scenes
  in.classes = h.classes;
  const auto t1 = std::chrono::steady_clock::now();
  in.grid = std::make_unique<vox::RayGrid>(vox::rayGridFromScene(*in.scene));
  in.readSeconds = seconds(t0, t1);
  in.gridSeconds = seconds(t1, std::chrono::steady_clock::now());
  return in;
}

}  // namespace voxcli
