// Text inputs (OBJ, MTL, ASCII PLY and STL) saved by Windows editors may start
// with a UTF-8 byte-order mark. The formats are ASCII and say nothing of it,
// but the mark is invisible in an editor, so a reader that took it for part
// of the first keyword would drop that line without a word. The readers skip it.
// Thread-safety: pure functions.
#pragma once

#include <cstddef>
#include <cstring>

namespace vox {

/// 3 when `data` starts with the UTF-8 byte-order mark (EF BB BF), else 0.
inline size_t utf8BomLength(const char* data, size_t size) {
  return size >= 3 && std::memcmp(data, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
}

}  // namespace vox
