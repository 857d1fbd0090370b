// Registration of subcommands with the CLI11 app (tools/cmds/app.cpp). Each
// tools/cmd_*.cpp defines one register function: it adds its subcommand with
// its options and returns the function that runs it after parsing.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace voxcli {

/// Returned by a command of the light bake module (vox-bake.so) when the full
/// module (vox-cmds.so) must run the command line instead; tools/cli/main.cpp then
/// loads it. Not an exit code.
inline constexpr int kDeferToFullModule = -100;

struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;  // returns an exit code; may throw vox::Error
};

Command registerVoxelize(CLI::App& root);
Command registerInfo(CLI::App& root);
Command registerDiff(CLI::App& root);
Command registerVerifyBijection(CLI::App& root);
Command registerBuildAtlas(CLI::App& root);
Command registerMip(CLI::App& root);
Command registerPackChunks(CLI::App& root);
Command registerRenderCanonical(CLI::App& root);
Command registerExport(CLI::App& root);
Command registerFuse(CLI::App& root);
Command registerMerge(CLI::App& root);

}  // namespace voxcli
