#include "tools/cli/dispatch.h"
#include "tools/cli/signal_cleanup.h"

#include <CLI/CLI.hpp>
#include <iostream>
#include <new>

#include "libvox/core/error.h"
#include "tools/cli/cli.h"

namespace voxcli {

namespace {
int exitCodeFor(vox::ErrorKind kind) {
  switch (kind) {
    case vox::ErrorKind::Usage: return kExitUsage;
    case vox::ErrorKind::BadInput: return kExitBadInput;
    case vox::ErrorKind::Io:
    case vox::ErrorKind::Internal: return kExitIoOrInternal;
  }
  return kExitIoOrInternal;
}
}  // namespace

const char* optionFor(vox::Setting s) {
  switch (s) {
    case vox::Setting::None: return "";
    case vox::Setting::Resolution: return "--res";
    case vox::Setting::VoxelSize: return "--voxel-size";
    case vox::Setting::VoxelSpacing: return "--res/--voxel-size";
    case vox::Setting::Bounds: return "--bounds";
    case vox::Setting::Padding: return "--pad";
    case vox::Setting::FillMode: return "--fill";
    case vox::Setting::DropInvalid: return "--drop-invalid";
    case vox::Setting::IgnoreMissingMaterials: return "--ignore-missing-materials";
    case vox::Setting::ClassRules: return "--classes";
    case vox::Setting::GridThreshold: return "--threshold";
    case vox::Setting::GridName: return "--grid";
    case vox::Setting::BlockWorldGrid: return "--grid-size";
    case vox::Setting::MipLevels: return "--levels";
    case vox::Setting::ChunkSide: return "--chunk";
    case vox::Setting::PageAlignment: return "--align";
    case vox::Setting::PageLayout: return "--layout";
    case vox::Setting::AtlasFormat: return "--format";
    case vox::Setting::AtlasMaxSide: return "--max-side";
    case vox::Setting::AtlasTilesPerRow: return "--tiles-per-row";
    case vox::Setting::CameraPose: return "--eye/--target/--up";
    case vox::Setting::CameraUp: return "--up";
    case vox::Setting::FieldOfView: return "--fov";
    case vox::Setting::ImageSize: return "--size";
    case vox::Setting::RenderLevel: return "--level";
  }
  return "";
}

std::string messageFor(const vox::Error& e) {
  std::string m = e.what();
  if (e.setting != vox::Setting::None) m += std::string(" (") + optionFor(e.setting) + ")";
  return m;
}

namespace {
std::vector<std::string> gInvocation;
}

const std::vector<std::string>& invocation() { return gInvocation; }

int parseAndRun(CLI::App& app, std::vector<Command>& commands, int argc, char** argv) {
  gInvocation.assign(argv, argv + argc);
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
    return kExitUsage;
  }
  for (Command& c : commands) {
    if (!c.app->parsed()) continue;
    const std::string name = c.app->get_name();
    installSignalCleanup(("vox " + name).c_str());
    try {
      return c.run();
    } catch (const vox::Error& e) {
      std::cerr << "vox " << name << ": error: " << messageFor(e) << "\n";
      return exitCodeFor(e.kind);
    } catch (const std::bad_alloc&) {
      std::cerr << "vox " << name << ": error: out of memory\n";
      return kExitIoOrInternal;
    } catch (const std::exception& e) {
      std::cerr << "vox " << name << ": internal error: " << e.what() << "\n";
      return kExitIoOrInternal;
    }
  }
  return kExitUsage;
}

}  // namespace voxcli
