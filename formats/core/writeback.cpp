#include "formats/core/writeback.h"

#include <fcntl.h>

namespace vox {

void startWriteback(int fd, uint64_t from, uint64_t to) {
#ifdef __linux__
  if (fd >= 0 && to > from) ::sync_file_range(fd, off64_t(from), off64_t(to - from), SYNC_FILE_RANGE_WRITE);
#else
  (void)fd;
  (void)from;
  (void)to;
#endif
}

bool handOnWritten(std::FILE* file, uint64_t written, uint64_t& queued) {
  if (written - queued < kWritebackStride) return true;
  if (std::fflush(file) != 0) return false;
  startWriteback(::fileno(file), queued, written);
  queued = written;
  return true;
}

}  // namespace vox
