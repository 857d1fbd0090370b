#include "formats/scene/vdb_content_uuid.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

#include "libvox/core/crc32c.h"
#include "libvox/core/error.h"

namespace vox {

std::string vdbUuidText(const std::array<uint32_t, 4>& digest) {
  std::array<uint8_t, 16> id;
  std::memcpy(id.data(), digest.data(), 16);
  id[6] = uint8_t((id[6] & 0x0f) | 0x40);  // version 4
  id[8] = uint8_t((id[8] & 0x3f) | 0x80);  // variant 1
  static const char* hex = "0123456789abcdef";
  std::string text;
  for (int i = 0; i < 16; ++i) {
    if (i == 4 || i == 6 || i == 8 || i == 10) text.push_back('-');
    text.push_back(hex[id[size_t(i)] >> 4]);
    text.push_back(hex[id[size_t(i)] & 15]);
  }
  return text;
}

void stampVdbContentUuid(const std::string& path, const std::string& shownName) {
  auto fail = [&](const std::string& what) {
    const std::string reason = errno ? std::string(": ") + std::strerror(errno) : std::string();
    throwIo(shownName + ": cannot set the file's UUID (" + what + reason + ")");
  };
  const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0) fail("open");
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  std::array<uint32_t, 4> digest = kVdbUuidSeeds;
  std::vector<char> buffer(size_t(1) << 20);
  uint64_t at = kVdbUuidOffset + kVdbUuidChars;
  for (;;) {
    const ssize_t n = ::pread(fd, buffer.data(), buffer.size(), off_t(at));
    if (n < 0) {
      if (errno == EINTR) continue;
      fail("read");
    }
    if (n == 0) break;
    for (uint32_t& crc : digest) crc = crc32c(buffer.data(), size_t(n), crc);
    at += uint64_t(n);
  }
  if (at == kVdbUuidOffset + kVdbUuidChars && ::lseek(fd, 0, SEEK_END) < off_t(at)) {
    errno = 0;
    fail("the file is shorter than an OpenVDB header");
  }
  const std::string text = vdbUuidText(digest);
  errno = 0;
  if (::pwrite(fd, text.data(), text.size(), off_t(kVdbUuidOffset)) != ssize_t(text.size())) fail("write");
}

}  // namespace vox
