// `vox`: a small launcher. It answers --version itself and loads the command
// module (vox-cmds.so, which links OpenVDB) only for commands that need it, so
// that `vox --version` starts in about a millisecond instead of the ~50 ms that
// loading OpenVDB and its dependencies costs (DESIGN section 13).
#include <dlfcn.h>
#include <limits.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include <CLI/CLI.hpp>

#include "libvox/version.h"
#include "tools/commands.h"
#include "tools/dispatch.h"
#include "tools/verify_bijection.h"

namespace {

std::string exeDir() {
  char buf[PATH_MAX];
  ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) return ".";
  buf[n] = '\0';
  std::string p(buf);
  return p.substr(0, p.find_last_of('/'));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && (std::strcmp(argv[1], "--version") == 0 || std::strcmp(argv[1], "-V") == 0)) {
    std::printf("%s\n", vox::versionString().c_str());
    return 0;
  }
  // verify-bijection proofs and format checks need no scene: run them here.
  if (argc >= 2 && std::strcmp(argv[1], "verify-bijection") == 0 && !voxcli::needsSceneModule(argc, argv)) {
    CLI::App app{"vox", "vox"};
    app.require_subcommand(1);
    std::vector<voxcli::Command> commands{voxcli::registerVerifyBijection(app)};
    return voxcli::parseAndRun(app, commands, argc, argv);
  }
  // The module sits beside the binary in the build tree, in ../lib/voxbake when
  // installed; VOX_CMDS_MODULE overrides both.
  std::string candidates[3];
  if (const char* env = std::getenv("VOX_CMDS_MODULE")) candidates[0] = env;
  const std::string dir = exeDir();
  candidates[1] = dir + "/vox-cmds.so";
  candidates[2] = dir + "/../lib/voxbake/vox-cmds.so";
  std::string errors;
  for (const std::string& path : candidates) {
    if (path.empty() || access(path.c_str(), R_OK) != 0) continue;
    void* handle = dlopen(path.c_str(), RTLD_LAZY | RTLD_LOCAL);
    if (!handle) {
      errors += std::string("\n  ") + dlerror();
      continue;
    }
    using Entry = int (*)(int, char**);
    auto entry = reinterpret_cast<Entry>(dlsym(handle, "vox_cli_main"));
    if (!entry) {
      errors += "\n  " + path + ": no vox_cli_main";
      continue;
    }
    return entry(argc, argv);
  }
  std::fprintf(stderr,
               "vox: error: cannot load the command module vox-cmds.so (looked beside %s and in "
               "%s/../lib/voxbake)%s\nReinstall vox, or set VOX_CMDS_MODULE to the module's path.\n",
               dir.c_str(), dir.c_str(), errors.c_str());
  return 4;
}
