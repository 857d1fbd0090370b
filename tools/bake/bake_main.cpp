// The light bake module's entry point (vox-bake.so): `vox voxelize` for meshes,
// without OpenVDB in the process (tools/bake/voxelize_mesh.h says why and how the
// launcher chooses between this module and vox-cmds.so).
#include <CLI/CLI.hpp>

#include "libvox/core/version.h"
#include "tools/cli/commands.h"
#include "tools/cli/dispatch.h"
#include "tools/bake/voxelize_mesh.h"

extern "C" __attribute__((visibility("default"))) int vox_bake_main(int argc, char** argv) {
  CLI::App app{voxcli::kRootDescription, "vox"};
  app.set_version_flag("-V,--version", vox::versionString());
  app.require_subcommand(1);
  std::vector<voxcli::Command> commands{voxcli::registerVoxelizeLight(app)};
  return voxcli::parseAndRun(app, commands, argc, argv);
}
