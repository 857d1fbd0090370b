// Parse argv with a CLI11 app, run the chosen subcommand, and map errors to the
// documented exit codes. Shared by the launcher (tools/cli/main.cpp) and the
// command module (tools/cmds/app.cpp).
#pragma once

#include <string>
#include <vector>

#include "tools/cli/commands.h"

namespace voxcli {

int parseAndRun(CLI::App& app, std::vector<Command>& commands, int argc, char** argv);

/// The command line parseAndRun was given, for reports.
const std::vector<std::string>& invocation();

}  // namespace voxcli
