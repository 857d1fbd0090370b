#include "tools/cli/dispatch.h"
#include "tools/cli/signal_cleanup.h"

#include <tbb/global_control.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstring>
#include <exception>
#include <iostream>
#include <new>

#include "libvox/core/error.h"
#include "tools/cli/cli.h"

namespace voxcli {

namespace {

/// Joins TBB's worker threads when a command ends, however it ends, so that
/// the process reaches exit() with one thread: otherwise the workers are still
/// shutting down while static destructors and LeakSanitizer's exit check run.
class WorkerThreadsJoinedAtEnd {
 public:
  ~WorkerThreadsJoinedAtEnd() { tbb::finalize(handle_, std::nothrow); }

 private:
  tbb::task_scheduler_handle handle_{tbb::attach{}};
};

}  // namespace

int exitCodeFor(vox::ErrorKind kind) {
  switch (kind) {
    case vox::ErrorKind::Usage: return kExitUsage;
    case vox::ErrorKind::BadInput: return kExitBadInput;
    case vox::ErrorKind::Io:
    case vox::ErrorKind::Resource:
    case vox::ErrorKind::Internal: return kExitIoOrInternal;
  }
  return kExitIoOrInternal;
}

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
    case vox::Setting::MemoryLimit: return "--max-memory";
  }
  return "";
}

std::string messageFor(const vox::Error& e) {
  std::string m = vox::withOutputNames(e.what());
  if (e.setting != vox::Setting::None) m += std::string(" (") + optionFor(e.setting) + ")";
  return m;
}

namespace {
std::vector<std::string> gInvocation;

char gTerminateCommand[64] = "vox";

void writeStderr(const char* s) {
  size_t left = std::strlen(s);
  while (left > 0) {
    const ssize_t n = ::write(STDERR_FILENO, s, left);
    if (n <= 0) return;
    s += n;
    left -= size_t(n);
  }
}

/// The out-of-memory advice, the same for a caught std::bad_alloc and one that
/// reached std::terminate.
const char* const kOutOfMemoryAdvice =
    ": lower --res (or raise --voxel-size), or give the run more memory; --max-memory sets the limit the "
    "estimate is checked against (docs/reliability.md)";

// std::terminate: an exception escaped where none may (a noexcept function, a
// destructor, a thread) or terminate was called directly. Whatever the cause,
// the run ends like any other failed run: its unfinished outputs (and the
// directories it made for them, left empty) removed, one
// line on stderr, exit 4 (an allocation failure above all must never abort).
// Writes with write(2) only: the heap may be exhausted. A second thread that
// terminates meanwhile waits here until the first one has exited.
[[noreturn]] void onTerminate() {
  static std::atomic<bool> entered{false};
  if (entered.exchange(true))
    for (;;) pause();
  bool outOfMemory = false;
  if (std::exception_ptr e = std::current_exception()) try {
      std::rethrow_exception(e);
    } catch (const std::bad_alloc&) {
      outOfMemory = true;
    } catch (...) {
    }
  vox::removeUncommittedOutputs();
  vox::removeCreatedDirectories();  // once emptied of the temporaries: build-atlas's -o DIR
  writeStderr(gTerminateCommand);
  if (outOfMemory) {
    writeStderr(": error: out of memory");
    writeStderr(kOutOfMemoryAdvice);
  } else {
    writeStderr(": internal error: the run was terminated (an exception escaped where none may)");
  }
  writeStderr("; no output was written\n");
  ::_exit(kExitIoOrInternal);
}
}  // namespace

const std::vector<std::string>& invocation() { return gInvocation; }

namespace {
const CLI::App* parsedCommand(const CLI::App& app, const std::vector<Command>& commands) {
  for (const Command& c : commands)
    if (c.app->parsed()) return c.app;
  return &app;
}

// CLI11 words a missing required argument "NAME is required", which for a
// positional reads as a sentence fragment ("a is required", "inputs is
// required"). Say what is missing and show the usage line instead.
std::string explainMissing(const CLI::App* cmd, const std::string& commandName, const std::string& what) {
  const std::string tail = " is required";
  if (what.size() <= tail.size() || what.compare(what.size() - tail.size(), tail.size(), tail) != 0) return what;
  const std::string name = what.substr(0, what.size() - tail.size());
  const CLI::Option* opt = cmd->get_option_no_throw(name);
  if (!opt) return what;
  std::string description = opt->get_description();
  if (!description.empty()) description[0] = char(std::tolower(static_cast<unsigned char>(description[0])));
  if (!opt->get_positional()) return description.empty() ? what : what + ": " + description;
  std::string usage = CLI::Formatter().make_usage(cmd, commandName);
  while (!usage.empty() && (usage.back() == '\n' || usage.back() == ' ')) usage.pop_back();
  const std::string prefix = "Usage: ";
  if (usage.compare(0, prefix.size(), prefix) == 0) usage = "usage: " + usage.substr(prefix.size());
  std::string out = "missing the argument '" + name + "'";
  if (!description.empty()) out += ": " + description;
  if (!usage.empty()) out += "; " + usage;
  return out;
}

// Levenshtein distance, for "did you mean": command names are short.
size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// No command was parsed: CLI11 says "A subcommand is required" whether the
// command is missing or misspelt. Name the word it did not know and list the
// commands, with the nearest one when it is close.
std::string explainNoCommand(const CLI::App& app, int argc, char** argv, const std::string& what) {
  if (what != "A subcommand is required") return what;  // CLI11's words for this case only
  std::string names, nearest;
  size_t best = std::string::npos;
  const std::string word = argc > 1 ? argv[1] : "";
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    names += (names.empty() ? "" : ", ") + sub->get_name();
    // Also against the name's first part: "rendr" is near render-canonical.
    const std::string head = sub->get_name().substr(0, sub->get_name().find('-'));
    const size_t d = std::min(editDistance(word, sub->get_name()), editDistance(word, head));
    if (d < best) best = d, nearest = sub->get_name();
  }
  if (names.empty()) return what;
  if (word.empty() || word[0] == '-') return "give a command first: " + names;
  std::string out = "unknown command '" + word + "'";
  if (best <= std::max<size_t>(2, word.size() / 3)) out += " (did you mean '" + nearest + "'?)";
  return out + "; the commands are " + names;
}
}  // namespace

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
    // One line like every other error ("vox CMD: error: ..."), not CLI11's two,
    // so a log filtered for "error:" shows usage mistakes too.
    std::string name = "vox";
    for (const Command& c : commands)
      if (c.app->parsed()) {
        name += " " + c.app->get_name();
        break;
      }
    std::string what = e.what();
    std::replace(what.begin(), what.end(), '\n', ' ');
    if (name == "vox") what = explainNoCommand(app, argc, argv, what);
    else what = explainMissing(parsedCommand(app, commands), name, what);
    std::cerr << name << ": error: " << what << "; see '" << name << " --help'\n";
    return kExitUsage;
  }
  for (Command& c : commands) {
    if (!c.app->parsed()) continue;
    const std::string name = c.app->get_name();
    installSignalCleanup(("vox " + name).c_str());
    std::strncpy(gTerminateCommand, ("vox " + name).c_str(), sizeof gTerminateCommand - 1);
    std::set_terminate(onTerminate);
    WorkerThreadsJoinedAtEnd joinWorkers;
    try {
      return c.run();
    } catch (const vox::Error& e) {
      std::cerr << "vox " << name << ": error: " << messageFor(e) << "\n";
      return exitCodeFor(e.kind);
    } catch (const std::bad_alloc&) {
      // Outputs are AtomicOutputs: the unwinding already removed their temporaries.
      const std::string phase = currentPhase();
      std::cerr << "vox " << name << ": error: out of memory" << (phase.empty() ? "" : " while in phase '" + phase + "'")
                << kOutOfMemoryAdvice << "; no output was written\n";
      return kExitIoOrInternal;
    } catch (const std::exception& e) {
      std::cerr << "vox " << name << ": internal error: " << e.what() << "\n";
      return kExitIoOrInternal;
    }
  }
  return kExitUsage;
}

}  // namespace voxcli
