// loadRenderInput: scenes read with OpenVDB (vox-cmds.so only; the light
// render module reads scenes as leaves, render_input.cpp).
#include <chrono>

#include "formats/pagefile/pagefile.h"
#include "formats/vdb/scene_vdb.h"
#include "libvox/core/error.h"
#include "libvox/scene/render_scene.h"
#include "tools/cmds/render_input.h"

namespace voxcli {

namespace {

class SceneVoxels final : public RenderVoxels {
 public:
  explicit SceneVoxels(std::shared_ptr<const vox::Scene> scene) : scene_(std::move(scene)) {}
  std::vector<vox::SummaryTexel> summaries(std::span<const vox::Coord3> voxels) const override {
    return vox::sceneSummaries(*scene_, voxels);
  }
  std::vector<vox::VoxelColor8> colors(std::span<const vox::Coord3> voxels) const override {
    return vox::sceneColors(*scene_, voxels);
  }
  bool hasColor() const override { return scene_->hasColor(); }

 private:
  std::shared_ptr<const vox::Scene> scene_;
};

}  // namespace

RenderInput loadRenderInput(const std::string& path, int level, bool needSummaries) {
  if (vox::pagefile::looksLikePageFile(path)) return loadPageRenderInput(path, level);
  checkSceneLevel(path, level);
  RenderInput in;
  const auto t0 = std::chrono::steady_clock::now();
  auto seconds = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
  in.path = path;
  in.kind = "scene";
  in.scene = std::make_shared<const vox::Scene>(
      vox::readSceneVdb(path, needSummaries ? vox::SceneParts::All : vox::SceneParts::OccupancyOnly));
  const vox::SceneHeader& h = in.scene->header();
  in.dims = h.dims;
  in.frame.origin = h.origin;
  in.frame.voxelSize = h.voxelSize;  // already the level's voxel size for mip scenes
  in.classes = h.classes;
  const auto t1 = std::chrono::steady_clock::now();
  in.grid = std::make_unique<vox::RayGrid>(vox::rayGridFromScene(*in.scene));
  in.voxels = std::make_shared<SceneVoxels>(in.scene);
  in.readSeconds = seconds(t0, t1);
  in.gridSeconds = seconds(t1, std::chrono::steady_clock::now());
  return in;
}

}  // namespace voxcli
