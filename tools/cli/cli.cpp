#include "tools/cli/cli.h"

#include "tools/cli/dispatch.h"

#include <sys/stat.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <unordered_map>
#include <thread>

#include "formats/core/json_text.h"
#include "libvox/core/error.h"
#include "libvox/core/version.h"
#include "tools/cli/comma_list.h"

namespace voxcli {

// Every parallel loop (voxbake's and OpenVDB's) runs on TBB: cap them at --threads.
struct ThreadLimit {
  explicit ThreadLimit(unsigned n) : control(tbb::global_control::max_allowed_parallelism, n) {}
  tbb::global_control control;
};

void addCommonOptions(CLI::App& cmd, CommonOptions& o) {
  cmd.add_option("--report", o.reportPath, "Write phase timings, counts and error metrics as JSON")
      ->type_name("FILE.json");
  cmd.add_option("--depfile", o.depfilePath, "Write a Make rule listing every input read")->type_name("FILE");
  cmd.add_option("--threads", o.threads,
                 "Worker threads (0 = all cores, at most " + std::to_string(kMaxThreads) +
                     "); outputs do not depend on it")
      ->type_name("N")
      ->check(CLI::Range(0u, kMaxThreads));
  cmd.add_flag("--progress", o.progress, "Draw progress bars even when stderr is not a terminal");
  cmd.add_flag("-q,--quiet", o.quiet, "Print nothing but errors");
  addMaxMemoryOption(cmd, o.maxMemory);
}

void addMaxMemoryOption(CLI::App& cmd, std::string& text) {
  cmd.add_option("--max-memory", text,
                 "Refuse, before the work, a run whose estimated peak memory exceeds SIZE (12G, 500M; 0 = no "
                 "limit; default " + std::to_string(int(vox::kDefaultMemoryFraction * 100)) +
                     "% of physical memory)")
      ->type_name("SIZE");
}

namespace {
std::mutex gPhaseMutex;
std::string gPhase;
}  // namespace

std::string currentPhase() {
  std::lock_guard<std::mutex> lock(gPhaseMutex);
  return gPhase;
}

std::string suggestSetting(const std::string& option, uint64_t lo, uint64_t hi, const vox::MemoryLimit& limit,
                           const std::function<uint64_t(uint64_t)>& estimateAt,
                           const std::function<std::string(uint64_t)>& show) {
  if (limit.unlimited()) return "";
  if (lo > hi || estimateAt(lo) > limit.bytes) return "";
  const uint64_t best = vox::largestFitting(lo, hi, vox::suggestionBudget(limit.bytes), estimateAt);
  if (best == 0) return "";
  return option + " " + (show ? show(best) : std::to_string(best)) + " would need about " +
         vox::formatBytes(estimateAt(best));
}

void Run::checkMemory(const vox::MemoryEstimate& estimate, const std::string& what, const std::string& suggestion) {
  vox::checkProcessMemory(estimate, what, suggestion);
}

namespace {
uint64_t gridsRead() {
  uint64_t grids = 0;
  for (const vox::CheckedEstimate& c : vox::checkedEstimates())
    for (const vox::MemoryPart& p : c.estimate.parts)
      if (p.name == "grids") grids += p.bytes;
  return grids;
}
}  // namespace

uint64_t Run::workMemoryBase(double perGridByte) const {
  return vox::residentBytesNow() + uint64_t(double(gridsRead()) * perGridByte);
}

void Run::checkWorkMemory(const std::string& what, double perGridByte, const vox::MemoryEstimate& extra,
                          const std::string& suggestion) {
  vox::MemoryEstimate e;
  e.add("resident after reading", vox::residentBytesNow());
  e.add("working copies", double(gridsRead()) * perGridByte);
  for (const vox::MemoryPart& p : extra.parts) e.parts.push_back(p);
  checkMemory(e, what, suggestion);
}

namespace {
/// The report's "memory": the limit and every estimate checked (the largest
/// is the run's estimated peak), for docs/reliability.md's calibration.
nlohmann::json memoryReport(const vox::MemoryLimit& limit) {
  nlohmann::json checks = nlohmann::json::array();
  uint64_t largest = 0;
  for (const vox::CheckedEstimate& c : vox::checkedEstimates()) {
    nlohmann::json parts = nlohmann::json::object();
    for (const vox::MemoryPart& p : c.estimate.parts) parts[p.name] = p.bytes;
    checks.push_back({{"what", c.what}, {"estimate_bytes", c.estimate.bytes()}, {"parts", parts}});
    largest = std::max(largest, c.estimate.bytes());
  }
  return {{"limit_bytes", limit.bytes}, {"limit", limit.description}, {"estimate_bytes", largest}, {"checks", checks}};
}
}  // namespace

namespace {
std::mutex gStderrMutex;
}

ProgressBar::ProgressBar(std::string label, bool enabled) : label_(std::move(label)), enabled_(enabled) {}
ProgressBar::~ProgressBar() { done(); }

void ProgressBar::update(double fraction) {
  if (!enabled_ || finished_) return;
  const int permille = int(std::clamp(fraction, 0.0, 1.0) * 1000);
  std::lock_guard<std::mutex> lock(gStderrMutex);
  if (permille / 10 == lastPermille_ / 10) return;
  lastPermille_ = permille;
  const int width = 30, filled = permille * width / 1000;
  std::fprintf(stderr, "\r%-12s [%s%s] %3d%%", label_.c_str(), std::string(filled, '#').c_str(),
               std::string(width - filled, ' ').c_str(), permille / 10);
  std::fflush(stderr);
}

void ProgressBar::done() {
  if (!enabled_ || finished_) return;
  update(1.0);
  finished_ = true;
  std::lock_guard<std::mutex> lock(gStderrMutex);
  std::fputc('\n', stderr);
}

namespace {
/// What sameFile compares, worked out once per path: a run with 700 outputs
/// compared each new one with every earlier one by stat and path resolution
/// again (18 s of system calls); comparing identities costs nothing.
struct FileIdentity {
  bool exists = false;
  dev_t device = 0;
  ino_t inode = 0;
  std::string resolved;  // when it does not exist: the normalised absolute path, its existing part's links resolved
};

FileIdentity identityOf(const std::string& path) {
  FileIdentity id;
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) {
    id.exists = true;
    id.device = st.st_dev;
    id.inode = st.st_ino;
    return id;
  }
  std::error_code ec;
  const std::filesystem::path p = std::filesystem::weakly_canonical(std::filesystem::absolute(path), ec);
  id.resolved = ec ? std::string() : p.string();
  return id;
}

/// True when `a` and `b` name one file: the same file when both exist (hard
/// and symbolic links seen through), else the same resolved path.
bool sameFile(const FileIdentity& a, const FileIdentity& b) {
  if (a.exists != b.exists) return false;
  if (a.exists) return a.device == b.device && a.inode == b.inode;
  return !a.resolved.empty() && a.resolved == b.resolved;
}
bool sameFile(const std::string& a, const std::string& b) { return sameFile(identityOf(a), identityOf(b)); }
}  // namespace

/// The identities of the paths a run compared, each worked out once.
struct PathIdentities {
  std::unordered_map<std::string, FileIdentity> known;
  const FileIdentity& of(const std::string& path) {
    auto it = known.find(path);
    if (it == known.end()) it = known.emplace(path, identityOf(path)).first;
    return it->second;
  }
  bool same(const std::string& a, const std::string& b) { return sameFile(of(a), of(b)); }
};

namespace {

/// Outputs replace a regular file whole (a temporary renamed over it): a
/// directory, a device (/dev/null: as root the rename would replace the node),
/// a pipe or /dev/stdout cannot take one.
void refuseUnreplaceable(const std::string& path) {
  if (path == "-")
    throw vox::Error(vox::ErrorKind::Usage, "'-' names no file: vox writes every output, --report and --depfile to "
                                            "a file (written whole, then renamed into place, so a failed run leaves "
                                            "nothing), never to standard output; give a file name");
  std::error_code ec;
  const std::filesystem::file_status st = std::filesystem::status(path, ec);
  if (st.type() == std::filesystem::file_type::directory)
    throw vox::Error(vox::ErrorKind::Io, path + ": cannot write: it is a directory");
  if (std::filesystem::exists(st) && st.type() != std::filesystem::file_type::regular)
    throw vox::Error(vox::ErrorKind::Io, path + ": cannot write: it is not a regular file (a device, pipe or "
                                         "socket); vox writes every output as a file it replaces whole");
}

/// Fails before the work, with the name the user gave, when `finalPath` cannot be created.
void checkDestination(const std::string& finalPath) {
  const std::filesystem::path p(finalPath);
  const std::string dir = p.parent_path().empty() ? "." : p.parent_path().string();
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    throw vox::Error(vox::ErrorKind::Io, finalPath + ": cannot write: directory '" + dir + "' does not exist");
  if (access(dir.c_str(), W_OK) != 0)
    throw vox::Error(vox::ErrorKind::Io, finalPath + ": cannot write: directory '" + dir + "' is not writable");
  refuseUnreplaceable(finalPath);
}
}  // namespace

Run::Run(std::string command, const CommonOptions& options)
    : command_(std::move(command)), options_(options), ids_(std::make_unique<PathIdentities>()) {
  const std::vector<std::string>& argv = invocation();
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  threads_ = options.threads == 0 ? cores : options.threads;
  limit_ = std::make_unique<ThreadLimit>(threads_);
  // TBB starts its worker threads at the first parallel loop, and on a VM a
  // new thread takes milliseconds to run: started here, they are running
  // by the time the first phase (a mesh's parallel read) has work for them.
  if (threads_ > 1) tbb::parallel_for(0, int(threads_), [](int) {});
  memoryLimit_ = vox::memoryLimitFrom(options.maxMemory, "--max-memory");
  vox::setProcessMemoryLimit(memoryLimit_, "--max-memory");
  start_ = phaseStart_ = std::chrono::steady_clock::now();
  report_ = {{"tool", "vox"},         {"version", vox::kToolVersion}, {"command", command_},
             {"argv", argv},          {"threads", threads_},          {"phases", nlohmann::json::array()},
             {"counts", nlohmann::json::object()}, {"error", nlohmann::json::object()}};
  // The report and the depfile are committed with the outputs. A directory in
  // their place can never take them: say so before the work. (Their own
  // directory may not exist yet: build-atlas makes its output directory, and
  // the demo writes the atlas's report into it. If it still does not exist
  // when the run ends, writing them fails before anything is committed.)
  for (const std::string* path : {&options.reportPath, &options.depfilePath}) {
    if (path->empty()) continue;
    refuseUnreplaceable(*path);
    const std::filesystem::path p(*path);
    const std::string dir = p.parent_path().empty() ? "." : p.parent_path().string();
    std::error_code ec;
    if (std::filesystem::is_directory(dir, ec) && access(dir.c_str(), W_OK) != 0)
      throw vox::Error(vox::ErrorKind::Io, *path + ": cannot write: directory '" + dir + "' is not writable");
  }
  if (!options.reportPath.empty() && !options.depfilePath.empty() && sameFile(options.reportPath, options.depfilePath))
    throw vox::Error(vox::ErrorKind::Usage, options.reportPath + ": given as both --report and --depfile; give them different names");
}

Run::~Run() = default;  // uncommitted AtomicOutputs remove their temporary files

void Run::endPhase() {
  if (phaseName_.empty()) return;
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - phaseStart_).count();
  report_["phases"].push_back({{"name", phaseName_}, {"seconds", s}});
  phaseName_.clear();
}

void Run::phase(const std::string& name) {
  endPhase();
  {
    std::lock_guard<std::mutex> lock(gPhaseMutex);
    gPhase = name;
  }
  phaseName_ = name;
  phaseStart_ = std::chrono::steady_clock::now();
}

void Run::checkOutputPath(const std::string& finalPath) const {
  auto clash = [&](const std::string& what, const std::string& fix) {
    throw vox::Error(vox::ErrorKind::Usage,
                     finalPath + ": this run would write it as an output and it is also " + what + "; " + fix);
  };
  for (const std::string& in : inputs_)
    if (ids_->same(finalPath, in) &&
        std::none_of(replaceable_.begin(), replaceable_.end(), [&](const std::string& r) { return ids_->same(r, in); }))
      clash("an input (" + in + "), which the output would replace", "write the output to another file");
  for (const vox::AtomicOutput& o : outputs_)
    if (ids_->same(finalPath, o.finalPath())) clash("another output (" + o.finalPath() + ")", "give the outputs different names");
  if (!options_.reportPath.empty() && ids_->same(finalPath, options_.reportPath))
    clash("the --report file", "give --report another name");
  if (!options_.depfilePath.empty() && ids_->same(finalPath, options_.depfilePath))
    clash("the --depfile file", "give --depfile another name");
}

void Run::mayReplace(const std::string& inputPath) { replaceable_.push_back(inputPath); }

void Run::input(const std::string& path) {
  if (std::find(inputs_.begin(), inputs_.end(), path) != inputs_.end()) return;
  auto clash = [&](const std::string& what, const std::string& fix) {
    throw vox::Error(vox::ErrorKind::Usage, path + ": this run reads it and would also write it as " + what +
                                                ", replacing it; " + fix);
  };
  const bool replaceable =
      std::any_of(replaceable_.begin(), replaceable_.end(), [&](const std::string& r) { return ids_->same(r, path); });
  for (const vox::AtomicOutput& o : outputs_)
    if (!replaceable && ids_->same(path, o.finalPath())) clash("an output (" + o.finalPath() + ")", "write the output to another file");
  if (!options_.reportPath.empty() && ids_->same(path, options_.reportPath)) clash("its --report", "give --report another name");
  if (!options_.depfilePath.empty() && ids_->same(path, options_.depfilePath)) clash("its --depfile", "give --depfile another name");
  inputs_.push_back(path);
}


std::string Run::output(const std::string& finalPath) {
  checkDestination(finalPath);
  checkOutputPath(finalPath);
  // The report and the depfile are committed with the outputs: a directory of
  // theirs that is missing now (build-atlas has made its own by the time it
  // names its files) would fail the run after the work.
  for (const std::string* path : {&options_.reportPath, &options_.depfilePath}) {
    if (path->empty()) continue;
    const std::filesystem::path p(*path);
    const std::string dir = p.parent_path().empty() ? "." : p.parent_path().string();
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec))
      throw vox::Error(vox::ErrorKind::Io, *path + ": cannot write: directory '" + dir + "' does not exist");
  }
  outputs_.emplace_back(finalPath);
  return outputs_.back().tempPath();
}

std::unique_ptr<ProgressBar> Run::progress(const std::string& label) const {
  const bool enabled = !options_.quiet && (options_.progress || isatty(STDERR_FILENO));
  return std::make_unique<ProgressBar>(label, enabled);
}

void Run::note(const std::string& message) const {
  if (options_.quiet) return;
  std::lock_guard<std::mutex> lock(gStderrMutex);
  std::cerr << "vox " << command_ << ": " << message << "\n";
}

void Run::noteWhenDone(const std::string& message) { finishNotes_.push_back(message); }

void throwLevelOutOfRange(int level, const std::string& path, uint64_t levels) {
  vox::throwUsage("--level " + std::to_string(level) + ": " + path +
                  (levels <= 1 ? std::string(" holds level 0 only") : " holds levels 0.." + std::to_string(levels - 1)));
}

std::string makeEscape(const std::string& path) {
  std::string out;
  for (char c : path) {
    if (c == ' ' || c == '#' || c == ':') out += '\\';  // a bare ':' would end the target list
    if (c == '$') out += '$';
    out += c;
  }
  return out;
}

int Run::finish(int code) {
  endPhase();
  // The depfile and the report are written first and committed with the
  // outputs: all of a run's files land together, or none does.
  std::vector<vox::AtomicOutput> sidecars;
  sidecars.reserve(2);
  if (!options_.depfilePath.empty()) {
    std::string rule;
    for (size_t i = 0; i < outputs_.size(); ++i) rule += (i ? " " : "") + makeEscape(outputs_[i].finalPath());
    if (outputs_.empty()) rule += makeEscape(options_.depfilePath);
    rule += ":";
    for (const std::string& in : inputs_) rule += " \\\n  " + makeEscape(in);
    rule += "\n";
    sidecars.emplace_back(options_.depfilePath);
    vox::writeFileBytes(sidecars.back().tempPath(), rule);
  }
  if (!options_.reportPath.empty()) {
    report_["exit_code"] = code;
    report_["memory"] = memoryReport(memoryLimit_);
    report_["total_seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    report_["inputs"] = inputs_;
    nlohmann::json outs = nlohmann::json::array();
    for (const vox::AtomicOutput& o : outputs_) outs.push_back(o.finalPath());
    report_["outputs"] = outs;
    sidecars.emplace_back(options_.reportPath);
    vox::writeFileBytes(sidecars.back().tempPath(), vox::jsonText(report_, 2) + "\n");
  }
  std::vector<vox::AtomicOutput*> all;
  for (vox::AtomicOutput& o : outputs_) all.push_back(&o);
  for (vox::AtomicOutput& s : sidecars) all.push_back(&s);
  vox::commitAll(std::move(all));
  for (const std::string& message : finishNotes_) note(message);
  return code;
}

std::string formatTriple(const std::array<uint32_t, 3>& v) {
  return std::to_string(v[0]) + "," + std::to_string(v[1]) + "," + std::to_string(v[2]);
}

std::array<uint32_t, 3> parseTriple(const std::string& text, const std::string& option) {
  const std::string expected = "X,Y,Z (three positive integers)";
  const std::vector<std::string> parts = splitCommaList(text, option, expected);
  if (parts.size() != 3) throw vox::Error(vox::ErrorKind::Usage, option + " expects " + expected + ", got '" + text + "'");
  std::array<uint32_t, 3> out{};
  for (size_t i = 0; i < 3; ++i) {
    const std::string& part = parts[i];
    char* stop = nullptr;
    const unsigned long v = std::strtoul(part.c_str(), &stop, 10);
    // Digits only: strtoul alone would take "+8", " 8" and "-8" (wrapped).
    if (part.find_first_not_of("0123456789") != std::string::npos || *stop != '\0' || v == 0 || v > 0xffffffffUL)
      throw vox::Error(vox::ErrorKind::Usage, option + " expects " + expected + ", got '" + text + "'");
    out[i] = uint32_t(v);
  }
  return out;
}

}  // namespace voxcli
