// The light export module's entry point (vox-export.so): `vox export` of page
// files and of scenes voxbake wrote (read as leaves) to glTF, PLY and
// MagicaVoxel, without OpenVDB in the process, so that an export does not pay
// the ~45 ms of loading OpenVDB (docs/startup.md). The files and reports are
// the ones vox-cmds.so writes. .vdb outputs, pyramids and scenes the leaves
// reader does not take (foreign .vdb files, tiles, refused scenes) answer
// kDeferToFullModule before anything is written and run in vox-cmds.so,
// which names any fault.
#include <CLI/CLI.hpp>
#include <memory>

#include "formats/vdb/scene_leaves_class_volume.h"
#include "formats/vdb/vdb_scene_leaves.h"
#include "libvox/core/error.h"
#include "libvox/core/version.h"
#include "tools/cli/alloc_tuning.h"
#include "tools/cli/commands.h"
#include "tools/cli/dispatch.h"
#include "tools/cmds/export_command.h"

namespace {

/// A scene voxbake wrote, read as leaves; false for pyramids (--level > 0 or
/// a pyramid file) and files the leaves reader does not take.
bool readSceneAsLeaves(const voxcli::ExportOptions& o, const std::optional<vox::IndexBox>& region, bool withColor,
                       voxcli::Run& run, voxcli::ExportInput& in) {
  if (o.level != 0) return false;  // a pyramid's level, or the full module's usage error
  std::optional<vox::SceneLeaves> leaves = vox::readSceneLeaves(o.input);
  if (!leaves || leaves->metadata.count(vox::kPyramidKey)) return false;
  const vox::SceneHeader& h = leaves->header;
  in.kind = "scene";
  in.dims = h.dims;
  in.frame.origin = h.origin;
  in.frame.voxelSize = h.voxelSize;
  in.classes = h.classes;
  in.box = voxcli::regionIn(region, in.dims, o.input);
  if (withColor && !leaves->hasColor)
    vox::throwBadInput(o.input + ": the scene has no baked colours; export the class palette (--color palette)");
  run.phase("volume");
  voxcli::checkVolumeMemory(run, o.input, leaves->occupancy.size(), withColor);
  in.volume.emplace(vox::classVolumeFromLeaves(*leaves, in.box, withColor, run.threads()));
  return true;
}

}  // namespace

extern "C" __attribute__((visibility("default"))) int vox_export_main(int argc, char** argv) {
  CLI::App app{"vox", "vox"};  // only `vox export` comes here: the root help is the full module's
  app.set_version_flag("-V,--version", vox::versionString());
  app.require_subcommand(1);
  auto opts = std::make_shared<voxcli::ExportOptions>();
  CLI::App* cmd = voxcli::addExportOptions(app, *opts);
  std::vector<voxcli::Command> commands{{cmd, [opts] {
                                           // A few hundred MB of fresh heap at most; a deferred file is
                                           // then read by vox-cmds.so with the same tuning.
                                           const voxcli::ExportBackend light{readSceneAsLeaves, {},
                                                                             voxcli::tuneAllocatorForShortRun};
                                           const std::optional<int> code = voxcli::runExport(*opts, light);
                                           return code ? *code : voxcli::kDeferToFullModule;
                                         }}};
  return voxcli::parseAndRun(app, commands, argc, argv);
}
