// The CLI conventions every `vox` subcommand shares (README "Conventions of every command"), in one
// place: exit codes, common options, atomic outputs, --report, --depfile,
// --threads, progress on stderr, --quiet.
//
// A subcommand's life:
//   Run run("voxelize", common);              // parses nothing; starts the clock
//   run.phase("parse"); run.input(path);     // every file read goes to the depfile
//   std::string tmp = run.output("a.vdb");   // write there; renamed at finish()
//   run.counts()["voxels"] = n;               // lands in the report
//   return run.finish();                      // commit outputs, report, depfile
// If the subcommand throws, the Run's destructor removes every temporary file,
// so a failed run leaves no output behind.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "formats/core/file_util.h"
#include "libvox/core/counted.h"
#include "libvox/core/memory_budget.h"

namespace CLI {
class App;
}

namespace voxcli {

/// Documented exit codes (README "Exit codes").
enum ExitCode : int {
  kExitOk = 0,           // success
  kExitCheckFailed = 1,  // a check found failures / compared files differ
  kExitUsage = 2,        // bad command line
  kExitBadInput = 3,     // an input is missing, malformed or not what was expected
  kExitIoOrInternal = 4, // cannot write outputs, or an internal error
};

/// The most worker threads a run may ask for: per-thread state (accumulators,
/// bit sets, tiles) makes absurd counts slow or worse (70000 crashed the
/// thread pool), and no machine vox runs on has more cores.
inline constexpr unsigned kMaxThreads = 1024;

struct CommonOptions {
  std::string reportPath;   // --report FILE.json
  std::string depfilePath;  // --depfile FILE
  unsigned threads = 0;     // --threads N (0 = all cores, at most kMaxThreads)
  bool progress = false;    // --progress: bars even when stderr is not a terminal
  bool quiet = false;       // --quiet: no messages or bars, errors only
  std::string maxMemory;    // --max-memory SIZE ("" = the default share of physical memory, "0" = no limit)
};

/// Adds --report, --depfile, --threads, --progress, --quiet, --max-memory to a subcommand.
void addCommonOptions(CLI::App& cmd, CommonOptions& options);
/// Only --max-memory, for commands without the other common options (info).
void addMaxMemoryOption(CLI::App& cmd, std::string& text);

/// A progress bar on stderr, drawn only when stderr is a terminal (or
/// --progress) and not --quiet. update() is cheap and thread-safe.
class ProgressBar {
 public:
  ProgressBar(std::string label, bool enabled);
  ~ProgressBar();
  void update(double fraction);
  void done();

 private:
  std::string label_;
  bool enabled_;
  int lastPermille_ = -1;
  bool finished_ = false;
};

class Run {
 public:
  /// The report records the command line parseAndRun was given.
  Run(std::string command, const CommonOptions& options);
  ~Run();

  /// Ends the current phase (if any) and starts a new one, timed in the report.
  void phase(const std::string& name);
  /// Records an input file for the depfile and the report. Throws vox::Error
  /// (Usage, exit 2) when it is a file this run writes (see output()).
  void input(const std::string& path);
  /// Registers an output; returns the temporary path to write it to. Throws
  /// vox::Error (Usage, exit 2) when `finalPath` is the same file (by
  /// identity: links and spellings such as ./a.vdb are seen through) as an
  /// input, another output, the report or the depfile: one would silently
  /// replace the other when the run commits. See mayReplace().
  std::string output(const std::string& finalPath);
  /// Checks `finalPath` as output() does without registering it: commands
  /// whose outputs are registered only when written call it before the work.
  void checkOutputPath(const std::string& finalPath) const;
  /// Declares that writing over this input is what the command is for (vox
  /// fuse -i S -o S adds votes to S; vox mip S -o S keeps S as level 0).
  void mayReplace(const std::string& inputPath);
  nlohmann::json& counts() { return report_["counts"]; }
  nlohmann::json& error() { return report_["error"]; }
  nlohmann::json& report() { return report_; }
  unsigned threads() const { return threads_; }
  bool quiet() const { return options_.quiet; }
  std::unique_ptr<ProgressBar> progress(const std::string& label) const;
  /// A message on stderr ("vox CMD: ..."), suppressed by --quiet.
  void note(const std::string& message) const;
  /// A note printed by finish() once every output is in place ("wrote ..."):
  /// a run that fails to commit never claims to have written anything.
  void noteWhenDone(const std::string& message);

  /// The memory limit of this run (--max-memory, else the default share of
  /// physical memory; libvox/core/memory_budget.h).
  const vox::MemoryLimit& memoryLimit() const { return memoryLimit_; }
  /// The one memory guard: records the estimate in the report ("memory") and
  /// throws vox::Error (Resource, exit 4) before the work when it exceeds the
  /// limit. `what` names the work ("a 4096^3 surface bake of cube.obj");
  /// `suggestion` says what would fit ("--res 2048 would need about 7.9 GiB").
  void checkMemory(const vox::MemoryEstimate& estimate, const std::string& what, const std::string& suggestion = "");
  /// After the inputs were read (each read checked its own grids): checks the
  /// work on them, resident memory now plus `perGridByte` times the grids
  /// read (a command's copies, levels, pages; measured, docs/reliability.md
  /// "Memory"), plus `extra` (parts that do not scale with the scene).
  void checkWorkMemory(const std::string& what, double perGridByte, const vox::MemoryEstimate& extra = {},
                       const std::string& suggestion = "");
  /// checkWorkMemory's estimate without `extra`: resident bytes now plus the
  /// working copies (for a command that searches a setting whose extra fits).
  uint64_t workMemoryBase(double perGridByte) const;

  /// Writes the depfile and the report beside the outputs, then commits every
  /// file of the run together (vox::commitAll: all reach the disk before any is
  /// renamed into place). Returns `code` for convenience.
  int finish(int code = kExitOk);

 private:
  void endPhase();
  std::string command_;
  CommonOptions options_;
  unsigned threads_;
  std::unique_ptr<struct ThreadLimit> limit_;
  vox::MemoryLimit memoryLimit_;
  nlohmann::json report_;
  std::vector<std::string> inputs_;
  std::vector<std::string> replaceable_;  // inputs an output may replace (mayReplace)
  std::vector<vox::AtomicOutput> outputs_;
  std::unique_ptr<struct PathIdentities> ids_;  // sameFile's identities, each path's worked out once
  std::vector<std::string> finishNotes_;        // noteWhenDone's, printed once the outputs are in place
  std::chrono::steady_clock::time_point start_, phaseStart_;
  std::string phaseName_;
};

/// The phase the current run is in ("voxelize", "write"...; "" before any),
/// for the out-of-memory message of tools/cli/dispatch.cpp.
std::string currentPhase();

/// "--res 2048 would need about 7.9 GiB": the largest value of `option` in
/// [lo, hi] whose estimate fits `limit` (estimateAt grows with the value), or
/// "" when none does. `smallerIsCheaper` = false for settings such as a voxel
/// size, where larger values cost less (then `lo`..`hi` are indices into the
/// caller's scale and `show` prints the setting for an index).
std::string suggestSetting(const std::string& option, uint64_t lo, uint64_t hi, const vox::MemoryLimit& limit,
                           const std::function<uint64_t(uint64_t)>& estimateAt,
                           const std::function<std::string(uint64_t)>& show = nullptr);

/// Parses "X,Y,Z" into three positive integers; throws vox::Error (Usage).
std::array<uint32_t, 3> parseTriple(const std::string& text, const std::string& option);
/// "X,Y,Z": the text parseTriple reads, for defaults shown in help.
std::string formatTriple(const std::array<uint32_t, 3>& values);

/// "1 triangle", "2 triangles": a count and its noun for messages (libvox/core/counted.h).
using vox::counted;

/// The usage error of a --level a pyramid or page file does not hold
/// ("--level 3: p.vpk holds levels 0..2", "... holds level 0 only").
[[noreturn]] void throwLevelOutOfRange(int level, const std::string& path, uint64_t levels);

/// Escapes a path for a Make rule (spaces, '#', ':', '$').
std::string makeEscape(const std::string& path);

}  // namespace voxcli
