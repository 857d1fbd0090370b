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
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "formats/core/file_util.h"

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

struct CommonOptions {
  std::string reportPath;   // --report FILE.json
  std::string depfilePath;  // --depfile FILE
  unsigned threads = 0;     // --threads N (0 = all cores)
  bool progress = false;    // --progress: bars even when stderr is not a terminal
  bool quiet = false;       // --quiet: no messages or bars, errors only
};

/// Adds --report, --depfile, --threads, --progress, --quiet to a subcommand.
void addCommonOptions(CLI::App& cmd, CommonOptions& options);

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
  /// Records an input file for the depfile and the report.
  void input(const std::string& path);
  /// Registers an output; returns the temporary path to write it to.
  std::string output(const std::string& finalPath);
  nlohmann::json& counts() { return report_["counts"]; }
  nlohmann::json& error() { return report_["error"]; }
  nlohmann::json& report() { return report_; }
  unsigned threads() const { return threads_; }
  bool quiet() const { return options_.quiet; }
  std::unique_ptr<ProgressBar> progress(const std::string& label) const;
  /// A message on stderr ("vox CMD: ..."), suppressed by --quiet.
  void note(const std::string& message) const;

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
  nlohmann::json report_;
  std::vector<std::string> inputs_;
  std::vector<vox::AtomicOutput> outputs_;
  std::chrono::steady_clock::time_point start_, phaseStart_;
  std::string phaseName_;
};

/// Parses "X,Y,Z" into three positive integers; throws vox::Error (Usage).
std::array<uint32_t, 3> parseTriple(const std::string& text, const std::string& option);
/// "X,Y,Z": the text parseTriple reads, for defaults shown in help.
std::string formatTriple(const std::array<uint32_t, 3>& values);

/// Escapes a path for a Make rule (spaces, '#', '$').
std::string makeEscape(const std::string& path);

}  // namespace voxcli
