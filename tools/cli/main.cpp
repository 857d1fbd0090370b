// `vox`: a small launcher. It answers --version itself and loads a command
// module only for commands that need one: vox-bake.so (mesh bakes, no OpenVDB)
// for `vox voxelize`, which defers to vox-cmds.so (every command, links
// OpenVDB) when the command line needs it. So `vox --version` starts in about a
// millisecond and a mesh bake does not pay the ~45 ms and ~33 MB that loading
// OpenVDB and its dependencies costs (docs/startup.md).
#include <dlfcn.h>
#include <limits.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include <CLI/CLI.hpp>

#include "libvox/core/version.h"
#include "tools/cli/commands.h"
#include "tools/cli/dispatch.h"
#include "tools/cli/verify_bijection.h"

namespace {

std::string exeDir() {
  char buf[PATH_MAX];
  ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) return ".";
  buf[n] = '\0';
  std::string p(buf);
  return p.substr(0, p.find_last_of('/'));
}

constexpr int kNoModule = -101;

/// Loads module `file` (beside the binary in the build tree, in ../lib/voxbake
/// when installed; the environment variable `envVar` overrides both) and runs
/// its entry point; kNoModule when no candidate loads (reasons appended to `errors`).
int runModule(const char* envVar, const char* file, const char* symbol, const std::string& dir, int argc,
              char** argv, std::string& errors) {
  std::string candidates[3];
  if (const char* env = std::getenv(envVar)) candidates[0] = env;
  candidates[1] = dir + "/" + file;
  candidates[2] = dir + "/../lib/voxbake/" + file;
  for (const std::string& path : candidates) {
    if (path.empty() || access(path.c_str(), R_OK) != 0) continue;
    void* handle = dlopen(path.c_str(), RTLD_LAZY | RTLD_LOCAL);
    if (!handle) {
      errors += std::string("\n  ") + dlerror();
      continue;
    }
    using Entry = int (*)(int, char**);
    auto entry = reinterpret_cast<Entry>(dlsym(handle, symbol));
    if (!entry) {
      errors += "\n  " + path + ": no " + symbol;
      continue;
    }
    return entry(argc, argv);
  }
  return kNoModule;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && (std::strcmp(argv[1], "--version") == 0 || std::strcmp(argv[1], "-V") == 0)) {
    std::printf("%s\n", vox::versionReport().c_str());
    return 0;
  }
  // verify-bijection proofs and format checks need no scene: run them here.
  if (argc >= 2 && std::strcmp(argv[1], "verify-bijection") == 0 && !voxcli::needsSceneModule(argc, argv)) {
    CLI::App app{"vox", "vox"};
    app.require_subcommand(1);
    std::vector<voxcli::Command> commands{voxcli::registerVerifyBijection(app)};
    return voxcli::parseAndRun(app, commands, argc, argv);
  }
  const std::string dir = exeDir();
  std::string errors;
  // Mesh bakes first try the light module (no OpenVDB: ~45 ms and ~33 MB less
  // per run); it answers kDeferToFullModule, before any work, when the command
  // line needs the full one.
  if (argc >= 2 && std::strcmp(argv[1], "voxelize") == 0) {
    const int code = runModule("VOX_BAKE_MODULE", "vox-bake.so", "vox_bake_main", dir, argc, argv, errors);
    if (code != kNoModule && code != voxcli::kDeferToFullModule) return code;
  }
  // Packing a scene voxbake wrote, or building its pyramid, runs in the light
  // pack module (no OpenVDB); it defers everything else before writing anything.
  if (argc >= 2 && (std::strcmp(argv[1], "pack-chunks") == 0 || std::strcmp(argv[1], "mip") == 0)) {
    const int code = runModule("VOX_PACK_MODULE", "vox-pack.so", "vox_pack_main", dir, argc, argv, errors);
    if (code != kNoModule && code != voxcli::kDeferToFullModule) return code;
  }
  // Renders of page files and of scenes voxbake wrote run in the light render
  // module (no OpenVDB); it defers other scene files before writing anything.
  if (argc >= 2 && std::strcmp(argv[1], "render-canonical") == 0) {
    const int code = runModule("VOX_RENDER_MODULE", "vox-render.so", "vox_render_main", dir, argc, argv, errors);
    if (code != kNoModule && code != voxcli::kDeferToFullModule) return code;
  }
  // Exports of page files and of scenes voxbake wrote to meshes and point
  // files run in the light export module (no OpenVDB); it defers .vdb
  // volumes, pyramids and other scene files before writing anything.
  if (argc >= 2 && std::strcmp(argv[1], "export") == 0) {
    const int code = runModule("VOX_EXPORT_MODULE", "vox-export.so", "vox_export_main", dir, argc, argv, errors);
    if (code != kNoModule && code != voxcli::kDeferToFullModule) return code;
  }
  const int code = runModule("VOX_CMDS_MODULE", "vox-cmds.so", "vox_cli_main", dir, argc, argv, errors);
  if (code != kNoModule) return code;
  std::fprintf(stderr,
               "vox: error: cannot load the command module vox-cmds.so (looked beside %s and in "
               "%s/../lib/voxbake)%s\nReinstall vox, or set VOX_CMDS_MODULE to the module's path.\n",
               dir.c_str(), dir.c_str(), errors.c_str());
  return 4;
}
