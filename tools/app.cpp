// The command module's entry point: builds the CLI11 app with every subcommand,
// parses argv, runs the chosen subcommand and maps errors to exit codes. `vox`
// (tools/main.cpp) loads this module with dlopen so that commands that need no
// OpenVDB start fast.
#include <CLI/CLI.hpp>
#include <iostream>
#include <new>

#include "libvox/error.h"
#include "libvox/version.h"
#include "tools/cli.h"
#include "tools/commands.h"

namespace {

int exitCodeFor(vox::ErrorKind kind) {
  switch (kind) {
    case vox::ErrorKind::Usage: return voxcli::kExitUsage;
    case vox::ErrorKind::BadInput: return voxcli::kExitBadInput;
    case vox::ErrorKind::Io:
    case vox::ErrorKind::Internal: return voxcli::kExitIoOrInternal;
  }
  return voxcli::kExitIoOrInternal;
}

}  // namespace

extern "C" __attribute__((visibility("default"))) int vox_cli_main(int argc, char** argv) {
  CLI::App app{"vox: bake triangle meshes, OpenVDB grids and block maps into sparse voxel scenes, and\n"
               "turn scenes into atlases, bitmaps, LOD pyramids, page files and canonical renders.\n"
               "Exit codes: 0 ok, 1 check failed / differs, 2 usage, 3 bad input, 4 I/O or internal error.",
               "vox"};
  app.set_version_flag("-V,--version", vox::versionString());
  app.require_subcommand(1);
  app.fallthrough(false);
  std::vector<voxcli::Command> commands;
  commands.push_back(voxcli::registerVoxelize(app));
  commands.push_back(voxcli::registerInfo(app));
  commands.push_back(voxcli::registerDiff(app));

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return voxcli::kExitUsage;
  }
  for (voxcli::Command& c : commands) {
    if (!c.app->parsed()) continue;
    const std::string name = c.app->get_name();
    try {
      return c.run();
    } catch (const vox::Error& e) {
      std::cerr << "vox " << name << ": error: " << e.what() << "\n";
      return exitCodeFor(e.kind);
    } catch (const std::bad_alloc&) {
      std::cerr << "vox " << name << ": error: out of memory\n";
      return voxcli::kExitIoOrInternal;
    } catch (const std::exception& e) {
      std::cerr << "vox " << name << ": internal error: " << e.what() << "\n";
      return voxcli::kExitIoOrInternal;
    }
  }
  return voxcli::kExitUsage;
}
