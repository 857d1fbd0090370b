#include "formats/core/file_util.h"

#include <cctype>

#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <utility>
#include <vector>

#include "libvox/core/error.h"

namespace vox {

namespace fs = std::filesystem;

namespace {

// ---- Temporary names: ".NAME.tmp-HOST-PID-N" -------------------------------
// HOST is a hash of the host name (8 hex digits), so a run removing the
// temporaries of dead runs never touches those of a live run on another
// machine sharing the directory (a cluster's file system); PID and the
// counter make the name unique on this machine.

uint32_t hostHash() {
  static const uint32_t hash = [] {
    char host[256] = {};
    if (gethostname(host, sizeof host - 1) != 0) host[0] = '\0';
    uint32_t h = 2166136261u;  // FNV-1a
    for (const char* c = host; *c; ++c) h = (h ^ uint8_t(*c)) * 16777619u;
    return h;
  }();
  return hash;
}

// A name near NAME_MAX (255 bytes) leaves no room for the dot and the tag: its
// temporary takes the name's first bytes and a hash of all of it instead
// (".NAME-START~HASH.tmp-HOST-PID-N"), the same for every run, so a dead run's
// temporaries are still found. Names shortened by this process are kept for
// outputName's messages.
constexpr size_t kNameMax = 255, kTagMax = 40;  // ".tmp-" + 8 + "-" + pid + "-" + counter, with room

std::mutex gShortenedMutex;
std::vector<std::pair<std::string, std::string>> gShortened;  // (stem, final name)

std::string temporaryStem(const std::string& name) {
  if (1 + name.size() + kTagMax <= kNameMax) return name;
  uint64_t h = 14695981039346656037ull;  // FNV-1a, 64 bits
  for (const char c : name) h = (h ^ uint8_t(c)) * 1099511628211ull;
  char hash[20];
  std::snprintf(hash, sizeof hash, "~%016llx", static_cast<unsigned long long>(h));
  std::string stem = name.substr(0, kNameMax - 1 - kTagMax - 17) + hash;
  std::lock_guard<std::mutex> lock(gShortenedMutex);
  if (std::find_if(gShortened.begin(), gShortened.end(), [&](const auto& e) { return e.first == stem; }) == gShortened.end())
    gShortened.emplace_back(stem, name);
  return stem;
}

struct TemporaryName {
  std::string finalName;  // NAME (its stem when shortened)
  uint32_t host = 0;
  long pid = 0;
};

std::optional<TemporaryName> parseTemporaryName(const std::string& name) {
  const size_t tmp = name.rfind(".tmp-");
  if (name.size() < 2 || name[0] != '.' || tmp == std::string::npos || tmp < 2) return std::nullopt;
  const std::string tail = name.substr(tmp + 5);  // HOST-PID-N
  const size_t dash1 = tail.find('-'), dash2 = tail.rfind('-');
  if (dash1 != 8 || dash2 == dash1) return std::nullopt;
  const std::string host = tail.substr(0, 8), pid = tail.substr(9, dash2 - 9), n = tail.substr(dash2 + 1);
  const auto all = [](const std::string& s, const char* set) {
    return !s.empty() && s.size() <= 18 && s.find_first_not_of(set) == std::string::npos;
  };
  if (!all(host, "0123456789abcdef") || !all(pid, "0123456789") || !all(n, "0123456789")) return std::nullopt;
  return TemporaryName{name.substr(1, tmp - 1), uint32_t(std::stoul(host, nullptr, 16)), std::stol(pid)};
}

// ---- Live paths, for signal handlers ---------------------------------------
// Lists a signal handler can walk without locks or allocation: the temporaries
// of the uncommitted outputs, and the directories runs created for them.
// Nodes are pushed at the head with a compare-and-swap and never freed (a
// handler may be walking them), only reused; a node's path is written while
// it is Claimed and read by the handler only once it is Live. A list grows to
// the most paths live at once (a run writing 700 render views tracks all
// 700), and costs nothing before the first one (a static table was written
// page by page at start-up: docs/bench-voxelize.md).
enum SlotState : int { kFree = 0, kClaimed = 1, kLive = 2 };

}  // namespace

struct TrackedPath {
  std::atomic<int> state{kClaimed};
  char* path = nullptr;
  size_t capacity = 0;
  TrackedPath* next = nullptr;
};

namespace {

std::atomic<TrackedPath*> gLiveTemporaries{nullptr}, gCreatedDirectories{nullptr};

TrackedPath* trackPath(std::atomic<TrackedPath*>& head, const std::string& path) {
  for (TrackedPath* n = head.load(); n; n = n->next) {
    if (n->capacity <= path.size()) continue;
    int expected = kFree;
    if (!n->state.compare_exchange_strong(expected, kClaimed)) continue;
    std::memcpy(n->path, path.c_str(), path.size() + 1);
    n->state.store(kLive);
    return n;
  }
  auto* n = new TrackedPath;  // never freed: see above
  n->capacity = std::max<size_t>(path.size() + 1, 256);
  n->path = new char[n->capacity];
  std::memcpy(n->path, path.c_str(), path.size() + 1);
  n->state.store(kLive);
  n->next = head.load();
  while (!head.compare_exchange_weak(n->next, n)) {
  }
  return n;
}

void untrackPath(TrackedPath* node) {
  if (node) node->state.store(kFree);
}

// ---- Temporaries of dead runs ----------------------------------------------
// A temporary is stale when its name is one of ours (".NAME.tmp-HOST-PID-N")
// with this host's tag, another process's PID, and that process no longer
// exists (killed with SIGKILL, or by the OOM killer). Creating an output
// removes the stale temporaries of that output's name. Each directory is read
// once per process, at its first output: the candidates (this host, another
// PID) are kept by name, so a run writing 700 outputs in one directory reads
// it once, not 700 times (each read also meeting the run's own temporaries).
// Directories are known by their canonical path (links and "./" seen
// through). A temporary left in a directory after this process read it is the
// next run's to remove. A forked child is another run: it reads them again.

struct StaleCandidate {
  std::string entry;  // the file's name in its directory
  long pid = 0;
};

std::mutex gScannedMutex;
pid_t gScannedBy = 0;  // the process the cache belongs to
// Per directory read, the candidates by the output name (stem) they belong to.
std::map<std::string, std::map<std::string, std::vector<StaleCandidate>>> gScanned;

// Removes the temporaries of `finalPath` left by runs on this host that no
// longer exist.
void removeStaleTemporaries(const fs::path& finalPath) {
  const std::string name = temporaryStem(finalPath.filename().string());
  const fs::path dir = finalPath.parent_path().empty() ? fs::path(".") : finalPath.parent_path();
  const std::unique_ptr<char, void (*)(void*)> canonical(::realpath(dir.c_str(), nullptr), &std::free);
  if (!canonical) return;  // no directory to remove from (the write will say why)
  const std::string key = canonical.get();
  std::lock_guard<std::mutex> lock(gScannedMutex);
  if (gScannedBy != getpid()) {
    gScanned.clear();
    gScannedBy = getpid();
  }
  auto [at, fresh] = gScanned.try_emplace(key);
  if (fresh) {
    std::error_code ec;
    fs::directory_iterator it(dir, ec), end;
    for (; !ec && it != end; it.increment(ec)) {
      std::string entry = it->path().filename().string();
      const std::optional<TemporaryName> t = parseTemporaryName(entry);
      if (!t || t->host != hostHash() || t->pid == long(getpid())) continue;
      at->second[t->finalName].push_back({std::move(entry), t->pid});
    }
  }
  const auto found = at->second.find(name);
  if (found == at->second.end()) return;
  std::vector<StaleCandidate>& candidates = found->second;
  for (size_t i = 0; i < candidates.size();) {
    const StaleCandidate& c = candidates[i];
    if (::kill(pid_t(c.pid), 0) == 0 || errno != ESRCH) {  // alive (or not ours to judge): asked again next time
      ++i;
      continue;
    }
    std::remove((dir / c.entry).c_str());
    candidates.erase(candidates.begin() + std::ptrdiff_t(i));
  }
  if (candidates.empty()) at->second.erase(found);
}

}  // namespace

namespace {
std::atomic<int> gCommittedOutputs{0};
}  // namespace

int committedOutputCount() noexcept { return gCommittedOutputs.load(); }

int removeUncommittedOutputs() noexcept {
  int removed = 0;
  for (TrackedPath* n = gLiveTemporaries.load(); n; n = n->next)
    if (n->state.load() == kLive && ::unlink(n->path) == 0) ++removed;
  return removed;
}

int removeCreatedDirectories() noexcept {
  // rmdir removes empty directories only. The list is newest first, and a run
  // creates a path's levels from the top down, so a first pass meets the
  // deepest first; a parent refused while it still held a child (a node
  // reused out of order) is tried again once the child is gone.
  int removed = 0;
  for (bool progress = true; progress;) {
    progress = false;
    for (TrackedPath* n = gCreatedDirectories.load(); n; n = n->next)
      if (n->state.load() == kLive && ::rmdir(n->path) == 0) ++removed, progress = true;
  }
  return removed;
}

namespace {
// A new temporary name for `finalPath`: same directory, so the rename is
// atomic; a dot-name keeps it out of globs.
std::string temporaryPathFor(const std::string& finalPath) {
  static std::atomic<unsigned> counter{0};
  const fs::path p(finalPath);
  char tag[64];
  std::snprintf(tag, sizeof tag, ".tmp-%08x-%ld-%u", hostHash(), long(getpid()), counter++);
  return (p.parent_path() / ("." + temporaryStem(p.filename().string()) + tag)).string();
}
}  // namespace

AtomicOutput::AtomicOutput(std::string finalPath) : final_(std::move(finalPath)) {
  removeStaleTemporaries(fs::path(final_));
  temp_ = temporaryPathFor(final_);
  live_ = trackPath(gLiveTemporaries, temp_);
}

AtomicOutput::AtomicOutput(AtomicOutput&& o) noexcept
    : final_(std::move(o.final_)), temp_(std::move(o.temp_)), committed_(o.committed_), live_(o.live_) {
  o.committed_ = true;  // the moved-from object owns nothing
  o.live_ = nullptr;
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) std::remove(temp_.c_str());
  untrackPath(live_);
}

CreatedDirectories::~CreatedDirectories() {
  // Deepest first; a level that is not empty (or gone) stays, and so do its parents.
  for (size_t i = made_.size(); i-- > 0;) {
    ::rmdir(paths_[i].c_str());
    untrackPath(made_[i]);
  }
}

void CreatedDirectories::keep() {
  for (TrackedPath* n : made_) untrackPath(n);
  made_.clear();
  paths_.clear();
}

std::vector<std::string> CreatedDirectories::made() const { return {paths_.rbegin(), paths_.rend()}; }

void CreatedDirectories::create(const std::string& path) {
  // The levels from the top down, each made by mkdir: a level counts as made
  // by this run only when its mkdir succeeded (not one another process made
  // meanwhile, nor one that existed).
  std::vector<std::string> levels;  // the deepest first
  for (fs::path p = fs::path(path).lexically_normal(); !p.empty(); p = p.parent_path()) {
    if (p.filename().empty() && p != p.parent_path()) continue;  // "dir/": its "dir" is next
    levels.push_back(p.string());
    if (p == p.parent_path()) break;
  }
  for (size_t i = levels.size(); i-- > 0;) {
    const std::string& level = levels[i];
    if (::mkdir(level.c_str(), 0777) == 0) {
      made_.push_back(trackPath(gCreatedDirectories, level));
      paths_.push_back(level);
      continue;
    }
    const int err = errno;
    struct stat st {};
    if (::stat(level.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) continue;
    throwIo(path + ": cannot create the output directory" + (i > 0 ? " " + level : std::string()) + ": " +
            std::strerror(err == EEXIST ? ENOTDIR : err));
  }
}

std::string outputName(const std::string& path) {
  const fs::path p(path);
  const std::optional<TemporaryName> t = parseTemporaryName(p.filename().string());
  if (!t) return path;
  std::lock_guard<std::mutex> lock(gShortenedMutex);
  for (const auto& [stem, name] : gShortened)
    if (stem == t->finalName) return (p.parent_path() / name).string();
  return (p.parent_path() / t->finalName).string();
}

std::string withOutputNames(const std::string& message) {
  std::string out;
  size_t from = 0;
  for (size_t tmp = message.find(".tmp-"); tmp != std::string::npos; tmp = message.find(".tmp-", tmp + 5)) {
    // The token around it: from after a space, quote or bracket, to the end of "tmp-HOST-PID-N".
    size_t begin = message.find_last_of(" '\"(", tmp);
    begin = begin == std::string::npos ? 0 : begin + 1;
    if (begin < from) continue;
    size_t end = tmp + 5;
    int dashes = 0;
    while (end < message.size() && (std::isxdigit(static_cast<unsigned char>(message[end])) || message[end] == '-')) {
      if (message[end] == '-' && ++dashes > 2) break;
      ++end;
    }
    const std::string token = message.substr(begin, end - begin);
    const std::string name = outputName(token);
    if (name == token) continue;  // not one of ours
    out += message.substr(from, begin - from) + name;
    from = end;
  }
  return out + message.substr(from);
}

void AtomicOutput::sync() const {
  if (committed_) return;
  const int fd = ::open(temp_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throwIo(final_ + ": the output was not written: " + std::strerror(errno));
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (rc != 0) throwIo(final_ + ": cannot write the output: " + std::strerror(err));
}

namespace {

// ---- The commit window -----------------------------------------------------
// While a run's outputs are renamed into place, a terminating signal waits:
// the renames take microseconds, and a handler running between two of them
// would leave new outputs beside old ones. 0: no commit; 1: committing; more:
// committing, and that signal arrived meanwhile (raised again at the end).
std::atomic<int> gCommitWindow{0};

struct CommitWindow {
  CommitWindow() { gCommitWindow.store(1); }
  ~CommitWindow() {
    const int pending = gCommitWindow.exchange(0);
    if (pending > 1) ::raise(pending);
  }
  CommitWindow(const CommitWindow&) = delete;
  CommitWindow& operator=(const CommitWindow&) = delete;
};

// `dir` ("" for the current one): a rename reaches the disk with its
// directory (best effort: some file systems refuse fsync on directories, and
// the data is already safe).
void syncDirectory(const std::string& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

}  // namespace

bool deferSignalDuringCommit(int signal) noexcept {
  int expected = 1;
  if (gCommitWindow.compare_exchange_strong(expected, signal)) return true;
  return expected > 1;  // one is already waiting: the run ends with it
}

void AtomicOutput::renameIntoPlace() {
  if (committed_) return;
  if (std::rename(temp_.c_str(), final_.c_str()) != 0)
    throwIo(final_ + ": cannot move the finished output into place: " + std::strerror(errno));
  committed_ = true;
  gCommittedOutputs.fetch_add(1);
  untrackPath(live_);  // after the rename: a signal before it still removes the temporary
  live_ = nullptr;
}

void AtomicOutput::commit() {
  sync();
  const CommitWindow window;
  renameIntoPlace();
  syncDirectory(fs::path(final_).parent_path().string());
}

void commitAll(std::vector<AtomicOutput*> outputs) {
  for (const AtomicOutput* o : outputs) o->sync();
  // A destination that became a directory meanwhile would fail its rename
  // after the others were renamed: check them all first.
  for (const AtomicOutput* o : outputs) {
    std::error_code ec;
    if (fs::is_directory(o->finalPath(), ec))
      throwIo(o->finalPath() + ": cannot move the finished output into place: it is a directory");
  }
  const CommitWindow window;
  // A rename can still fail after others succeeded (an immutable file, a
  // sticky directory, a file system gone read-only): each existing
  // destination is kept under a second name (a hard link, no copy) until all
  // are in place, so a failure puts every earlier one back.
  struct Previous {
    std::string keptAt;  // "" when the destination did not exist or cannot be linked
    bool existed = false;
  };
  std::vector<Previous> previous(outputs.size());
  struct RemoveKept {  // on every way out: after success, or after a failure put some back
    std::vector<Previous>& previous;
    ~RemoveKept() {
      for (const Previous& p : previous)
        if (!p.keptAt.empty()) ::unlink(p.keptAt.c_str());
    }
  } removeKept{previous};
  for (size_t i = 0; i < outputs.size(); ++i) {
    struct stat st {};
    previous[i].existed = ::lstat(outputs[i]->finalPath().c_str(), &st) == 0;
    // Named like a temporary of this run: a run killed here leaves it to the next run's cleanup.
    const std::string keptAt = temporaryPathFor(outputs[i]->finalPath());
    if (previous[i].existed && ::link(outputs[i]->finalPath().c_str(), keptAt.c_str()) == 0) previous[i].keptAt = keptAt;
  }
  for (size_t i = 0; i < outputs.size(); ++i) {
    try {
      outputs[i]->renameIntoPlace();
    } catch (const Error& e) {
      std::vector<std::string> restored, replaced;
      for (size_t j = 0; j < i; ++j) {
        const std::string& path = outputs[j]->finalPath();
        bool back = false;
        if (!previous[j].existed) {
          back = ::unlink(path.c_str()) == 0;
        } else if (!previous[j].keptAt.empty() && std::rename(previous[j].keptAt.c_str(), path.c_str()) == 0) {
          back = true;
          previous[j].keptAt.clear();
        }
        (back ? restored : replaced).push_back(path);
        if (back) gCommittedOutputs.fetch_sub(1);
      }
      std::string message = e.what();
      const auto list = [](const std::vector<std::string>& paths) {
        std::string text;
        for (size_t k = 0; k < paths.size(); ++k) text += (k ? ", " : "") + paths[k];
        return text;
      };
      if (!restored.empty()) message += "; the outputs already moved were put back as they were (" + list(restored) + ")";
      if (!replaced.empty()) message += "; these outputs were already replaced and could not be put back: " + list(replaced);
      throwIo(message);
    }
  }
  // Once per directory, not per output: 700 render views share one.
  std::vector<std::string> directories;
  for (const AtomicOutput* o : outputs) {
    const std::string dir = fs::path(o->finalPath()).parent_path().string();
    if (std::find(directories.begin(), directories.end(), dir) == directories.end()) directories.push_back(dir);
  }
  for (const std::string& dir : directories) syncDirectory(dir);
}

void requireRegularFile(const std::string& path) { requireRegularFile(path, "", ""); }

void requireRegularFile(const std::string& path, const std::string& ifDirectory, const std::string& ifNotRegular) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int err = errno;
    if (err == ENOENT || err == ENOTDIR) throwBadInput(path + ": no such file");
    throwBadInput(path + ": cannot open the file: " + std::strerror(err));
  }
  if (S_ISREG(st.st_mode)) {
    // stat needs no read permission: open it, or a reader sniffing the first
    // bytes would call an unreadable file "not a PNG" or "not a scene".
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throwBadInput(path + ": cannot open the file: " + std::strerror(errno));
    ::close(fd);
    return;
  }
  if (S_ISDIR(st.st_mode) && !ifDirectory.empty()) throwBadInput(path + ": " + ifDirectory);
  if (!S_ISDIR(st.st_mode) && !ifNotRegular.empty()) throwBadInput(path + ": " + ifNotRegular);
  const char* what = S_ISDIR(st.st_mode)    ? "a directory"
                     : S_ISFIFO(st.st_mode) ? "a FIFO (named pipe)"
                     : S_ISSOCK(st.st_mode) ? "a socket"
                     : S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode) ? "a device"
                                                                   : "not a regular file";
  throwBadInput(path + ": is " + what + ", expected a regular file");
}

std::string readFileBytes(const std::string& path) {
  requireRegularFile(path);
  // One allocation and one read: a stringstream copy costs more than parsing.
  std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) throwBadInput(path + ": cannot open the file: " + std::strerror(errno));
  std::string bytes;
  char buf[1 << 16];
  if (std::fseek(f.get(), 0, SEEK_END) == 0) {
    const long size = std::ftell(f.get());
    if (size > 0) bytes.reserve(size_t(size));
    std::rewind(f.get());
  }
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f.get())) > 0) bytes.append(buf, n);
  if (std::ferror(f.get())) throwBadInput(path + ": read error");
  return bytes;
}

FileView::FileView(const std::string& path, bool populate) {
  requireRegularFile(path);
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throwBadInput(path + ": cannot open the file: " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0) {
    void* p = ::mmap(nullptr, size_t(st.st_size), PROT_READ, MAP_PRIVATE | (populate ? MAP_POPULATE : 0), fd, 0);
    if (p != MAP_FAILED) {
      mapped_ = p;
      data_ = static_cast<const char*>(p);
      size_ = size_t(st.st_size);
    }
  }
  ::close(fd);
  if (!mapped_) {  // empty files, or mmap refused: read it
    owned_ = readFileBytes(path);
    data_ = owned_.data();
    size_ = owned_.size();
  }
}

FileView::~FileView() {
  if (mapped_) ::munmap(mapped_, size_);
}

void writeFileBytes(const std::string& path, const std::string& bytes, const std::string& nameForMessages) {
  writeFileBytes(path, bytes.data(), bytes.size(), nameForMessages);
}

void writeFileBytes(const std::string& path, const void* data, size_t size, const std::string& nameForMessages) {
  const std::string name = nameForMessages.empty() ? outputName(path) : nameForMessages;
  // POSIX calls rather than a stream: the system's reason reaches the message.
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) throwIo(name + ": cannot create the file: " + std::strerror(errno));
  const char* p = static_cast<const char*>(data);
  size_t left = size;
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int err = n < 0 ? errno : ENOSPC;
      ::close(fd);
      throwIo(name + ": cannot write the file: " + std::strerror(err));
    }
    p += n;
    left -= size_t(n);
  }
  if (::close(fd) != 0) throwIo(name + ": cannot write the file: " + std::strerror(errno));
}

int64_t fileSizeOrMinusOne(const std::string& path) {
  std::error_code ec;
  auto n = fs::file_size(path, ec);
  return ec ? -1 : int64_t(n);
}

}  // namespace vox
