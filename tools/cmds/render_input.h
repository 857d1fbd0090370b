// The input of render-canonical and verify-bijection --canonical: a scene
// (.vdb) or a page file (.vpk), loaded once into what rays and shading need.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "formats/pagefile/pagefile.h"
#include "formats/pagefile/pagefile_ray_grid.h"
#include "libvox/render/view_framing.h"
#include "libvox/scene/render_scene.h"

namespace voxcli {

struct RenderInput {
  std::string path;
  std::string kind;  // "scene" or "pages"
  int level = 0;     // page files: the level rendered
  vox::Dims dims;
  vox::GridFrame frame;
  vox::ClassTable classes;
  std::optional<vox::Scene> scene;
  std::optional<vox::pagefile::Reader> pages;
  std::unique_ptr<vox::RayGrid> grid;
  double readSeconds = 0, gridSeconds = 0;  // reading the file, building the ray grid

  /// Summary bytes of `voxels` (empty voxels: zeros).
  std::vector<vox::SummaryTexel> summaries(std::span<const vox::Coord3> voxels) const;
  /// Display colours of `voxels` (render_modes.h VoxelColor8; no colour: zeros).
  std::vector<vox::VoxelColor8> colors(std::span<const vox::Coord3> voxels) const;
  /// The world box of the occupied voxels (the grid's box when none is
  /// occupied): what --view NAME and --orbit frame.
  vox::WorldBox occupiedWorldBox() const;
  /// Whether the input stores per-voxel colour.
  bool hasColor() const;
};

/// Loads a scene .vdb or a page file (sniffed by magic); `level` selects a page
/// file level (scenes: must be 0). Without `needSummaries` a scene's vote
/// grids are not read (summaries() then returns zeros). Throws vox::Error
/// naming the file.
RenderInput loadRenderInput(const std::string& path, int level, bool needSummaries = true);

}  // namespace voxcli
