// The input of render-canonical and verify-bijection --canonical: a scene
// (.vdb) or a page file (.vpk), loaded once into what rays and shading need.
//
// Two loaders: loadRenderInput reads scenes with OpenVDB (vox-cmds.so only,
// render_input_scene.cpp); loadRenderInputLight reads page files and scenes
// of the form voxbake writes without it (the light render module,
// render_main.cpp, and vox-cmds.so alike) and gives up on everything else.
// For any input both accept, both give the same dims, frame, classes, ray
// grid, summaries and colours.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "libvox/core/scene_header.h"
#include "libvox/core/summary_bytes.h"
#include "libvox/render/ray_grid.h"
#include "libvox/render/render.h"
#include "libvox/render/render_modes.h"
#include "libvox/render/view_framing.h"

namespace vox {
class Scene;
}

namespace voxcli {

/// Where a render's summary bytes and colours come from: a scene, its leaves
/// or a page file. Const calls may come from any thread, one at a time.
class RenderVoxels {
 public:
  virtual ~RenderVoxels() = default;
  virtual std::vector<vox::SummaryTexel> summaries(std::span<const vox::Coord3> voxels) const = 0;
  virtual std::vector<vox::VoxelColor8> colors(std::span<const vox::Coord3> voxels) const = 0;
  virtual bool hasColor() const = 0;
};

struct RenderInput {
  std::string path;
  std::string kind;  // "scene" or "pages"
  int level = 0;     // page files: the level rendered
  vox::Dims dims;
  vox::GridFrame frame;
  vox::ClassTable classes;
  std::shared_ptr<const vox::Scene> scene;  // a scene read with OpenVDB (loadRenderInput), else null
  std::shared_ptr<const RenderVoxels> voxels;
  std::unique_ptr<vox::RayGrid> grid;
  double readSeconds = 0, gridSeconds = 0;  // reading the file, building the ray grid

  /// Summary bytes of `voxels` (empty voxels: zeros).
  std::vector<vox::SummaryTexel> summaries(std::span<const vox::Coord3> at) const { return voxels->summaries(at); }
  /// Display colours of `voxels` (render_modes.h VoxelColor8; no colour: zeros).
  std::vector<vox::VoxelColor8> colors(std::span<const vox::Coord3> at) const { return voxels->colors(at); }
  /// The world box of the occupied voxels (the grid's box when none is
  /// occupied): what --view NAME and --orbit frame.
  vox::WorldBox occupiedWorldBox() const;
  /// Whether the input stores per-voxel colour.
  bool hasColor() const { return voxels->hasColor(); }
};

/// Loads a scene .vdb or a page file (sniffed by magic); `level` selects a page
/// file level (scenes: must be 0). Without `needSummaries` a scene's vote
/// grids are not read (summaries() then returns zeros). Throws vox::Error
/// naming the file. Scenes are read with OpenVDB: vox-cmds.so only.
RenderInput loadRenderInput(const std::string& path, int level, bool needSummaries = true);

/// A page file's level `level` (loadRenderInput's page-file case).
RenderInput loadPageRenderInput(const std::string& path, int level);
/// Throws loadRenderInput's usage error for a --level given with a scene.
void checkSceneLevel(const std::string& path, int level);

/// loadRenderInput without OpenVDB: page files (errors thrown as there) and
/// scenes readSceneLeaves reads. std::nullopt for any other scene file and
/// for a scene file whose read fails (loadRenderInput then reads it and
/// names the fault).
std::optional<RenderInput> loadRenderInputLight(const std::string& path, int level, bool needSummaries = true);

}  // namespace voxcli
