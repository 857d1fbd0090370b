// File helpers shared by the formats: atomic outputs and whole-file reads.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace vox {

/// An output written under a temporary name in the destination's directory and
/// renamed over the destination by commit(), so a failed run never leaves a
/// partial file that `make` would take for done. Destroying an uncommitted
/// AtomicOutput removes the temporary file.
///
/// A run with several outputs commits them together (commitAll): every
/// temporary file is flushed to disk first (fsync: a full disk or an I/O error
/// that the writes did not report surfaces here), and only when all of them are
/// safe are they renamed into place. So a failure leaves every existing output
/// untouched and no temporary file behind. A rename that fails after others
/// succeeded (an immutable file) puts the earlier ones back; a terminating
/// signal during the renames waits for them (deferSignalDuringCommit).
///
/// The temporary is "DIR/.NAME.tmp-HOST-PID-N" (HOST: 8 hex digits hashing the
/// host name). Live temporaries are tracked so that removeUncommittedOutputs()
/// can delete them from a signal handler; creating an AtomicOutput removes the
/// temporaries of the same output left by dead runs on this host (SIGKILL, the
/// OOM killer). A process reads each directory for those once, at its first
/// output there (a run writing 700 views in one directory reads it once): a
/// temporary left by a run that died after that is the next process's to
/// remove. Thread-safe: outputs may be created and destroyed on any thread.
class AtomicOutput {
 public:
  explicit AtomicOutput(std::string finalPath);
  AtomicOutput(AtomicOutput&&) noexcept;
  AtomicOutput& operator=(AtomicOutput&&) = delete;
  ~AtomicOutput();

  const std::string& finalPath() const { return final_; }
  const std::string& tempPath() const { return temp_; }
  /// Flushes the temporary file to disk (fsync). Throws vox::Error (Io) naming
  /// the final path and the system's reason ("No space left on device").
  void sync() const;
  /// sync(), then renames the temporary file to the final path and flushes the
  /// directory entry. Throws vox::Error (Io) when the temporary file is missing,
  /// cannot be flushed, or the rename fails.
  void commit();
  /// Renames without syncing the file again or its directory: for commitAll,
  /// which synced every file first and syncs each directory once after.
  void renameIntoPlace();

 private:
  std::string final_, temp_;
  bool committed_ = false;
  struct TrackedPath* live_ = nullptr;  // its entry in the list of live temporaries
};

/// Deletes the temporary file of every uncommitted AtomicOutput of this
/// process and returns how many files it deleted. Async-signal-safe (unlink
/// only): for the CLI's SIGINT/SIGTERM handlers, which then exit without
/// running destructors.
int removeUncommittedOutputs() noexcept;

/// The output directories a run creates (and their missing parents), removed
/// again when the run does not finish: on destruction unless keep() was called
/// (a failed run), and by removeCreatedDirectories() (a signal). Only the
/// levels this object made are removed, deepest first, and only while empty:
/// the run's temporaries are removed first, so a directory holding anything
/// else (an output already in place, a user's file) stays with its parents.
/// Thread-safe like AtomicOutput. Not copyable.
class CreatedDirectories {
 public:
  CreatedDirectories() = default;
  ~CreatedDirectories();
  CreatedDirectories(const CreatedDirectories&) = delete;
  CreatedDirectories& operator=(const CreatedDirectories&) = delete;
  /// Creates `path` and its missing parents (an existing directory is fine)
  /// and remembers the levels this call made. Throws vox::Error (Io) naming
  /// `path` and the system's reason when a level cannot be made or is not a
  /// directory (the levels made before are remembered, so still removed).
  void create(const std::string& path);
  /// The run succeeded: its directories stay, and are forgotten.
  void keep();
  /// The levels made so far, deepest first.
  std::vector<std::string> made() const;

 private:
  std::vector<struct TrackedPath*> made_;  // in the order made: parents first
  std::vector<std::string> paths_;
};

/// Removes (rmdir) every directory of a live CreatedDirectories of this
/// process that is empty, deepest first, and returns how many it removed.
/// Async-signal-safe (rmdir only): for the CLI's SIGINT/SIGTERM handlers,
/// after removeUncommittedOutputs.
int removeCreatedDirectories() noexcept;

/// For the CLI's SIGINT/SIGTERM handlers: true while commitAll is renaming
/// outputs into place, in which case `signal` is recorded and raised again
/// when the renames are done (the handler returns at once), so an interrupt
/// never leaves some new outputs beside old ones. Async-signal-safe.
bool deferSignalDuringCommit(int signal) noexcept;

/// How many AtomicOutputs of this process were renamed into place so far.
/// Async-signal-safe (an atomic load): the signal handlers tell "nothing was
/// written" from "every output was already in place".
int committedOutputCount() noexcept;

/// The name a user knows a file by: for an AtomicOutput's temporary file
/// ("dir/.NAME.tmp-HOST-PID-N") the final output's ("dir/NAME"), else `path`. For messages.
std::string outputName(const std::string& path);
/// `message` with every temporary file's path in it replaced by outputName's
/// (a writer that failed names the file it was writing): for error messages.
std::string withOutputNames(const std::string& message);

/// Commits outputs together: syncs every one first, then renames them all.
/// Nothing is renamed unless every file reached the disk and no destination is
/// a directory. When a rename fails, the outputs renamed before it are put back
/// as they were (kept meanwhile under a hard link; removed when they did not
/// exist) and the vox::Error (Io) names the failed one and any that could not
/// be put back.
void commitAll(std::vector<AtomicOutput*> outputs);

/// The one check every input file passes before it is read: it must exist,
/// be a regular file (or a symbolic link to one) and open for reading.
/// Directories, FIFOs, sockets and devices are refused up front (reading
/// /dev/zero or a FIFO would never end). Throws vox::Error (BadInput) naming
/// `path` and what it is, or "cannot open the file: " and the system's reason
/// (Permission denied).
void requireRegularFile(const std::string& path);

/// requireRegularFile (one stat, one open) with the caller's words for a
/// directory and for any other file that is not regular, each following
/// "PATH: " (a reader of one format names what it expected).
void requireRegularFile(const std::string& path, const std::string& ifDirectory, const std::string& ifNotRegular);

/// Reads a whole file (requireRegularFile first). Throws vox::Error (BadInput)
/// naming the file if it is missing or unreadable.
std::string readFileBytes(const std::string& path);

/// A whole file (requireRegularFile first), read-only, mapped into memory (no
/// copy and no fresh pages to fault in, which is most of what reading a large
/// mesh cost), or read into memory when mapping is refused. Throws vox::Error (BadInput) like
/// readFileBytes. Not copyable.
class FileView {
 public:
  /// `populate`: the whole file is read into the mapping at once (the
  /// reader will touch every page); without, pages come in as touched.
  explicit FileView(const std::string& path, bool populate = true);
  ~FileView();
  FileView(const FileView&) = delete;
  FileView& operator=(const FileView&) = delete;
  const char* data() const { return data_; }
  size_t size() const { return size_; }

 private:
  const char* data_ = "";
  size_t size_ = 0;
  void* mapped_ = nullptr;
  std::string owned_;
};

/// Writes `bytes` to `path` (not atomic by itself; use with AtomicOutput).
/// Throws vox::Error (Io) with the system's reason when a write fails, naming
/// `nameForMessages` (the final output's name when `path` is a temporary) or `path`.
void writeFileBytes(const std::string& path, const std::string& bytes, const std::string& nameForMessages = "");
void writeFileBytes(const std::string& path, const void* data, size_t size, const std::string& nameForMessages = "");

/// Size in bytes, or -1 when the file does not exist.
int64_t fileSizeOrMinusOne(const std::string& path);

}  // namespace vox
