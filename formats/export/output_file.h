// A file written front to back in one go, for the exporters' large outputs:
// buffered, every failure a vox::Error (Io) naming the file, and close()
// reports what the last buffered write hit (a full disk shows up there).
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

namespace vox {

class OutputFile {
 public:
  /// Creates or truncates `path`. Throws vox::Error (Io) when it cannot.
  explicit OutputFile(const std::string& path);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  void write(const void* data, size_t bytes);
  void write(std::string_view text) { write(text.data(), text.size()); }
  /// Little-endian integers (every format here is little-endian).
  void u32(uint32_t v);
  void i32(int32_t v) { u32(uint32_t(v)); }
  void repeat(uint8_t byte, size_t count);
  uint64_t written() const { return written_; }
  /// Flushes and closes; throws vox::Error (Io) on failure. The destructor
  /// closes silently (after an exception the file is removed anyway).
  void close();

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
  uint64_t written_ = 0;
  uint64_t queued_ = 0;  // bytes handed to the kernel's writeback (formats/core/writeback.h)
};

}  // namespace vox
