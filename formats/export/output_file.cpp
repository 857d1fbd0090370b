#include "formats/export/output_file.h"

#include <cerrno>
#include <cstring>

#include "formats/core/writeback.h"
#include "libvox/core/error.h"

namespace vox {

namespace {
[[noreturn]] void fail(const std::string& path, const char* what) {
  throwIo(path + ": cannot " + what + ": " + std::strerror(errno));
}
}  // namespace

OutputFile::OutputFile(const std::string& path) : path_(path) {
  file_ = std::fopen(path.c_str(), "wb");
  if (!file_) fail(path_, "create the file");
  std::setvbuf(file_, nullptr, _IOFBF, size_t(1) << 20);
}

OutputFile::~OutputFile() {
  if (file_) std::fclose(file_);
}

void OutputFile::write(const void* data, size_t bytes) {
  if (bytes && std::fwrite(data, 1, bytes, file_) != bytes) fail(path_, "write");
  written_ += bytes;
  // Each finished MB goes to the kernel's writeback at once: the disk works
  // while the rest is meshed, and the commit's fsync waits for the tail only.
  if (!handOnWritten(file_, written_, queued_)) fail(path_, "write");
}

void OutputFile::u32(uint32_t v) {
  const uint8_t b[4] = {uint8_t(v), uint8_t(v >> 8), uint8_t(v >> 16), uint8_t(v >> 24)};
  write(b, 4);
}

void OutputFile::repeat(uint8_t byte, size_t count) {
  char block[4096];
  std::memset(block, byte, sizeof block);
  while (count) {
    const size_t n = count < sizeof block ? count : sizeof block;
    write(block, n);
    count -= n;
  }
}

void OutputFile::close() {
  if (!file_) return;
  std::FILE* f = file_;
  file_ = nullptr;
  const bool flushed = std::fflush(f) == 0;
  if (std::fclose(f) != 0 || !flushed) fail(path_, "write");
}

}  // namespace vox
