// Text from input files as valid UTF-8.
//
// Names and paths come from files and command lines as bytes: an OBJ written
// by a Windows tool names its materials in Windows-1252 ("Mat\xe9riau"), a
// file may be named in Latin-1. Every JSON vox writes (reports, scene and
// image metadata, glTF) must be UTF-8, and nlohmann::json refuses anything
// else when it writes, so such a name ended a run with an internal error.
// Where text enters a name or a JSON document it goes through
// utf8FromLegacy: valid UTF-8 is kept byte for byte; each byte that is not
// part of a valid UTF-8 sequence is read as Windows-1252 (Latin-1 with the
// printable characters of 0x80-0x9F), which is what such files almost always
// are, and the five bytes Windows-1252 leaves undefined become U+FFFD.
// Text inputs (OBJ, MTL, ASCII PLY and STL) saved by Windows editors may also
// start with a UTF-8 byte-order mark, invisible in an editor; the readers skip
// it (utf8BomLength) rather than take it for part of the first keyword.
// Thread-safety: pure functions.
#pragma once

#include <cstring>
#include <string>
#include <string_view>

namespace vox {

/// 3 when `data` starts with the UTF-8 byte-order mark (EF BB BF), else 0.
inline size_t utf8BomLength(const char* data, size_t size) {
  return size >= 3 && std::memcmp(data, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
}

/// True when `text` is well-formed UTF-8 (RFC 3629: no overlong forms, no
/// surrogates, nothing above U+10FFFF).
bool isValidUtf8(std::string_view text);

/// `text` itself when it is valid UTF-8; else the same text with every byte
/// outside a valid sequence transcoded from Windows-1252.
std::string utf8FromLegacy(std::string_view text);

}  // namespace vox
