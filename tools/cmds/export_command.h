// `vox export`: its options and the whole command but for what needs OpenVDB.
// Both command modules link this: the light module vox-export.so
// (export_main.cpp) reads scenes voxbake wrote as leaves and page files, and
// writes glTF, PLY and MagicaVoxel files; vox-cmds.so (cmd_export.cpp) also
// reads pyramids and other OpenVDB files and writes .vdb volumes. The bytes
// and reports are the same whichever module runs (tests/cli/lightexport_test.sh).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <optional>
#include <string>

#include "libvox/core/block_mesh.h"
#include "libvox/core/class_volume.h"
#include "libvox/render/render.h"
#include "tools/cli/cli.h"

namespace voxcli {

enum class ExportFormat { FromExtension, Glb, Gltf, Ply, MagicaVoxel, Vdb };
enum class ExportSplit { None, Classes };

/// The command line of `vox export`.
struct ExportOptions {
  std::string input;
  std::string output;
  ExportFormat format = ExportFormat::FromExtension;
  int level = 0;
  std::string region;  // "umin,vmin,wmin,umax,vmax,wmax", inclusive
  vox::FaceColor color = vox::FaceColor::Palette;
  ExportSplit split = ExportSplit::None;
  bool dedup = false;
  bool greedy = false;
  bool fog = false, levelSet = false;
  int halfWidth = 3;
  bool quantize = false;
  CommonOptions common;
  /// The parsed subcommand (addExportOptions sets it): which options were
  /// given, so that an option of another format is refused even at its
  /// default value (--split none with a .ply).
  const CLI::App* app = nullptr;
};

/// Adds the export subcommand and its options, which fill `opts`.
CLI::App* addExportOptions(CLI::App& root, ExportOptions& opts);

/// What is exported: the blocks of the chosen level inside the region.
struct ExportInput {
  std::string kind;  // "scene", "pyramid", "pages"
  vox::Dims dims;    // of the level
  vox::GridFrame frame;
  vox::ClassTable classes;
  vox::IndexBox box;
  std::optional<vox::ClassVolume> volume;
};

/// What a module reads and writes with OpenVDB, or without it.
struct ExportBackend {
  /// Fills `in` from the .vdb file o.input (a scene, or a pyramid's --level),
  /// clipped to `region` (regionIn), with colours when `withColor`; starts
  /// the phase "volume" before building in.volume. false: this module does not
  /// read that file (the full module must), having written nothing.
  std::function<bool(const ExportOptions& o, const std::optional<vox::IndexBox>& region, bool withColor, Run& run,
                     ExportInput& in)>
      readVdb;
  /// Writes a .vdb fog volume or level set; empty: .vdb outputs are the full
  /// module's.
  std::function<void(const ExportOptions& o, const ExportInput& in, Run& run)> writeVdbVolume;
  /// Called once it is certain this module runs the command (light modules
  /// tune the allocator there); may be empty.
  std::function<void()> starting;
};

/// The format --format names, or the output's extension's. Throws vox::Error
/// (Usage) when neither says, or when --format names another format than a
/// known extension (-o out.glb --format ply).
ExportFormat outputFormat(const ExportOptions& o);

/// The guard before a scene's volume is built (phase "volume"): resident
/// memory now plus a volume of `bricks` bricks (the scene's occupancy
/// leaves), with colour when `withColor` (ClassVolume::bytesFor).
void checkVolumeMemory(Run& run, const std::string& input, uint64_t bricks, bool withColor);

/// `region` checked against the level's dims (inclusive; the whole domain when
/// none). Throws vox::Error (BadInput) naming `path` when it leaves the scene.
vox::IndexBox regionIn(const std::optional<vox::IndexBox>& region, const vox::Dims& dims, const std::string& path);

/// {"min": [u, v, w], "max": [u, v, w]} for reports.
nlohmann::json boxJson(const vox::IndexBox& box);

/// The whole command. std::nullopt, having written nothing, when the backend
/// does not read the input or write the format (the full module runs it).
std::optional<int> runExport(const ExportOptions& o, const ExportBackend& backend);

}  // namespace voxcli
