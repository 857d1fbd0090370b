#include "formats/core/file_util.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>

#include "libvox/core/error.h"

namespace vox {

namespace fs = std::filesystem;

AtomicOutput::AtomicOutput(std::string finalPath) : final_(std::move(finalPath)) {
  static std::atomic<unsigned> counter{0};
  const fs::path p(final_);
  // Same directory, so the rename is atomic; a dot-name keeps it out of globs.
  std::string name(1, '.');
  name.append(p.filename().string()).append(".tmp").append(std::to_string(getpid()));
  name.append(".").append(std::to_string(counter++));
  temp_ = (p.parent_path() / name).string();
}

AtomicOutput::AtomicOutput(AtomicOutput&& o) noexcept
    : final_(std::move(o.final_)), temp_(std::move(o.temp_)), committed_(o.committed_) {
  o.committed_ = true;  // the moved-from object owns nothing
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) std::remove(temp_.c_str());
}

void AtomicOutput::commit() {
  if (committed_) return;
  if (std::rename(temp_.c_str(), final_.c_str()) != 0)
    throwIo(final_ + ": cannot move the finished output into place: " + std::strerror(errno));
  committed_ = true;
}

std::string readFileBytes(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throwBadInput(path + ": is a directory, expected a file");
  // One allocation and one read: a stringstream copy costs more than parsing.
  std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) throwBadInput(path + ": cannot open the file (missing or unreadable)");
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

FileView::FileView(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throwBadInput(path + ": is a directory, expected a file");
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throwBadInput(path + ": cannot open the file (missing or unreadable)");
  struct stat st {};
  if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0) {
    void* p = ::mmap(nullptr, size_t(st.st_size), PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
    if (p != MAP_FAILED) {
      mapped_ = p;
      data_ = static_cast<const char*>(p);
      size_ = size_t(st.st_size);
    }
  }
  ::close(fd);
  if (!mapped_) {  // pipes, devices, empty files, or mmap refused: read it
    owned_ = readFileBytes(path);
    data_ = owned_.data();
    size_ = owned_.size();
  }
}

FileView::~FileView() {
  if (mapped_) ::munmap(mapped_, size_);
}

void writeFileBytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throwIo(path + ": cannot create the file: " + std::strerror(errno));
  out.write(bytes.data(), std::streamsize(bytes.size()));
  out.close();
  if (!out) throwIo(path + ": write failed (disk full?)");
}

int64_t fileSizeOrMinusOne(const std::string& path) {
  std::error_code ec;
  auto n = fs::file_size(path, ec);
  return ec ? -1 : int64_t(n);
}

}  // namespace vox
