// File helpers shared by the formats: atomic outputs and whole-file reads.
#pragma once

#include <cstdint>
#include <string>

namespace vox {

/// An output written under a temporary name in the destination's directory and
/// renamed over the destination by commit(), so a failed run never leaves a
/// partial file that `make` would take for done. Destroying an uncommitted
/// AtomicOutput removes the temporary file.
class AtomicOutput {
 public:
  explicit AtomicOutput(std::string finalPath);
  AtomicOutput(AtomicOutput&&) noexcept;
  AtomicOutput& operator=(AtomicOutput&&) = delete;
  ~AtomicOutput();

  const std::string& finalPath() const { return final_; }
  const std::string& tempPath() const { return temp_; }
  /// Renames the temporary file to the final path. Throws vox::Error (Io) when
  /// the temporary file is missing or the rename fails.
  void commit();

 private:
  std::string final_, temp_;
  bool committed_ = false;
};

/// Reads a whole file. Throws vox::Error (BadInput) naming the file if it is
/// missing or unreadable.
std::string readFileBytes(const std::string& path);

/// A whole file, read-only, mapped into memory when it is a regular file (no
/// copy and no fresh pages to fault in, which is most of what reading a large
/// mesh cost), else read into memory. Throws vox::Error (BadInput) like
/// readFileBytes. Not copyable.
class FileView {
 public:
  explicit FileView(const std::string& path);
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
void writeFileBytes(const std::string& path, const std::string& bytes);

/// Size in bytes, or -1 when the file does not exist.
int64_t fileSizeOrMinusOne(const std::string& path);

}  // namespace vox
