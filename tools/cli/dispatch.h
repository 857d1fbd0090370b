// Parse argv with a CLI11 app, run the chosen subcommand, and map errors to the
// documented exit codes. Shared by the launcher (tools/cli/main.cpp) and the
// command module (tools/cmds/app.cpp).
#pragma once

#include <string>
#include <vector>

#include "libvox/core/error.h"
#include "tools/cli/commands.h"

namespace voxcli {

int parseAndRun(CLI::App& app, std::vector<Command>& commands, int argc, char** argv);

/// The exit code of an error of `kind` (README "Exit codes").
int exitCodeFor(vox::ErrorKind kind);

/// The command-line option that sets `setting` ("--res"); "" for Setting::None.
const char* optionFor(vox::Setting setting);

/// An error's message as the CLI prints it: the library's words, then the
/// option its fix changes, e.g. "...; lower the resolution (--res)".
std::string messageFor(const vox::Error& error);

/// The command line parseAndRun was given, for reports.
const std::vector<std::string>& invocation();

}  // namespace voxcli
