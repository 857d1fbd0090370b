// The command module's entry point: builds the CLI11 app with every subcommand
// and runs it. `vox` (tools/cli/main.cpp) loads this module with dlopen so that
// commands that need no OpenVDB start fast.
#include <CLI/CLI.hpp>

#include "libvox/core/version.h"
#include "tools/cli/commands.h"
#include "tools/cli/dispatch.h"
#include "tools/bake/voxelize_mesh.h"

extern "C" __attribute__((visibility("default"))) int vox_cli_main(int argc, char** argv) {
  CLI::App app{voxcli::kRootDescription, "vox"};
  app.set_version_flag("-V,--version", vox::versionString());
  app.require_subcommand(1);
  std::vector<voxcli::Command> commands;
  commands.push_back(voxcli::registerVoxelize(app));
  commands.push_back(voxcli::registerInfo(app));
  commands.push_back(voxcli::registerDiff(app));
  commands.push_back(voxcli::registerVerifyBijection(app));
  commands.push_back(voxcli::registerBuildAtlas(app));
  commands.push_back(voxcli::registerMip(app));
  commands.push_back(voxcli::registerPackChunks(app));
  commands.push_back(voxcli::registerRenderCanonical(app));
  commands.push_back(voxcli::registerExport(app));
  commands.push_back(voxcli::registerFuse(app));
  commands.push_back(voxcli::registerMerge(app));
  return voxcli::parseAndRun(app, commands, argc, argv);
}
