#include "formats/file_util.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "libvox/error.h"

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
  std::ifstream in(path, std::ios::binary);
  if (!in) throwBadInput(path + ": cannot open the file (missing or unreadable)");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throwBadInput(path + ": read error");
  return ss.str();
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
