// The light module's entry point (vox-pack.so): `vox pack-chunks` and `vox
// mip` of a scene voxbake wrote, read as leaves without OpenVDB in the
// process, so that they do not pay the ~45 ms of loading OpenVDB
// (docs/startup.md). Both commands read the same leaves, so one module serves
// them. Anything else (pack-chunks --merge, --verify, --mips; mip --source,
// pyramid inputs; other files, scenes a check refuses) answers
// kDeferToFullModule before anything is written and runs in vox-cmds.so.
#include <CLI/CLI.hpp>
#include <memory>

#include "libvox/core/version.h"
#include "tools/cli/commands.h"
#include "tools/cli/dispatch.h"
#include "tools/cmds/mip_light.h"
#include "tools/cmds/pack_chunks_light.h"

extern "C" __attribute__((visibility("default"))) int vox_pack_main(int argc, char** argv) {
  CLI::App app{"vox", "vox"};  // only `vox pack-chunks` and `vox mip` come here: the root help is the full module's
  app.set_version_flag("-V,--version", vox::versionString());
  app.require_subcommand(1);
  auto pack = std::make_shared<voxcli::PackOptions>();
  auto mip = std::make_shared<voxcli::MipOptions>();
  auto orDefer = [](const std::optional<int>& code) { return code ? *code : voxcli::kDeferToFullModule; };
  std::vector<voxcli::Command> commands{
      {voxcli::addPackChunksOptions(app, *pack), [pack, orDefer] { return orDefer(voxcli::runPackFromLeaves(*pack)); }},
      {voxcli::addMipOptions(app, *mip), [mip, orDefer] { return orDefer(voxcli::runMipFromLeaves(*mip)); }}};
  return voxcli::parseAndRun(app, commands, argc, argv);
}
