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

std::string outputName(const std::string& path) {
  const fs::path p(path);
  const std::string name = p.filename().string();
  // The temporary's name: "." + final name + ".tmp" + pid + "." + counter.
  const size_t tmp = name.rfind(".tmp");
  if (name.size() < 2 || name[0] != '.' || tmp == std::string::npos || tmp < 2) return path;
  const std::string tail = name.substr(tmp + 4);
  const size_t dot = tail.find('.');
  const auto digits = [](const std::string& s) {
    return !s.empty() && s.find_first_not_of("0123456789") == std::string::npos;
  };
  if (dot == std::string::npos || !digits(tail.substr(0, dot)) || !digits(tail.substr(dot + 1))) return path;
  return (p.parent_path() / name.substr(1, tmp - 1)).string();
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

void AtomicOutput::renameIntoPlace() {
  if (committed_) return;
  if (std::rename(temp_.c_str(), final_.c_str()) != 0)
    throwIo(final_ + ": cannot move the finished output into place: " + std::strerror(errno));
  committed_ = true;
  // The rename itself reaches the disk with the directory (best effort: some
  // file systems refuse fsync on directories, and the data is already safe).
  const std::string dir = fs::path(final_).parent_path().string();
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

void AtomicOutput::commit() {
  sync();
  renameIntoPlace();
}

void commitAll(std::vector<AtomicOutput*> outputs) {
  for (const AtomicOutput* o : outputs) o->sync();
  for (AtomicOutput* o : outputs) o->renameIntoPlace();
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
