// The light pack module's entry point (vox-pack.so): `vox pack-chunks` of a
// scene voxbake wrote, packed from its leaves without OpenVDB in the process,
// so that it does not pay the ~45 ms of loading OpenVDB (docs/startup.md).
// Anything else (--merge, --verify, --mips, other files, scenes a check
// refuses) answers kDeferToFullModule and runs in vox-cmds.so.
#include <CLI/CLI.hpp>
#include <memory>

#include "libvox/core/version.h"
#include "tools/cli/commands.h"
#include "tools/cli/dispatch.h"
#include "tools/cmds/pack_chunks_light.h"

extern "C" __attribute__((visibility("default"))) int vox_pack_main(int argc, char** argv) {
  CLI::App app{"vox", "vox"};  // only `vox pack-chunks` comes here: the root help is the full module's
  app.set_version_flag("-V,--version", vox::versionString());
  app.require_subcommand(1);
  auto opts = std::make_shared<voxcli::PackOptions>();
  CLI::App* cmd = voxcli::addPackChunksOptions(app, *opts);
  std::vector<voxcli::Command> commands{{cmd, [opts] {
                                           const std::optional<int> code = voxcli::runPackFromLeaves(*opts);
                                           return code ? *code : voxcli::kDeferToFullModule;
                                         }}};
  return voxcli::parseAndRun(app, commands, argc, argv);
}
