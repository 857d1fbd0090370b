// The light render module's entry point (vox-render.so): `vox
// render-canonical` of page files and of scenes voxbake wrote, read as leaves
// without OpenVDB in the process, so that a render does not pay the ~45 ms of
// loading OpenVDB (docs/startup.md). The images and reports are the ones
// vox-cmds.so writes. Scenes the leaves reader does not take (foreign .vdb
// files, tiles, refused or unreadable scenes) answer kDeferToFullModule before
// anything is written and run in vox-cmds.so, which names the fault.
#include <CLI/CLI.hpp>
#include <memory>

#include "libvox/core/version.h"
#include "tools/cli/commands.h"
#include "tools/cli/dispatch.h"
#include "tools/cmds/render_canonical.h"

extern "C" __attribute__((visibility("default"))) int vox_render_main(int argc, char** argv) {
  CLI::App app{"vox", "vox"};  // only `vox render-canonical` comes here: the root help is the full module's
  app.set_version_flag("-V,--version", vox::versionString());
  app.require_subcommand(1);
  auto opts = std::make_shared<voxcli::RenderCanonicalOptions>();
  CLI::App* cmd = voxcli::addRenderCanonicalOptions(app, *opts);
  std::vector<voxcli::Command> commands{
      {cmd, [opts] { return voxcli::runRenderCanonical(*opts, voxcli::loadRenderInputLight); }}};
  return voxcli::parseAndRun(app, commands, argc, argv);
}
