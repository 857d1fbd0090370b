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

}  // namespace vox
