#include "tools/cli/dispatch.h"

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
    try {
      return c.run();
    } catch (const vox::Error& e) {
      std::cerr << "vox " << name << ": error: " << e.what() << "\n";
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
