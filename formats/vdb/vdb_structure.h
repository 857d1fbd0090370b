// A bounds-checked walk over an OpenVDB file's framing (header, file metadata,
// grid descriptors and their byte ranges) before OpenVDB reads it.
//
// Why our own: OpenVDB's reader trusts lengths read from the file. On a
// truncated file a failed read leaves a garbage string length that it then
// allocates: a 100-byte prefix of a scene made it allocate 14 GB and spend 45 s
// before failing. This walk reads only framing, checks every length against the
// bytes that remain, and every grid's [start, end) range against the file size,
// so truncated and most corrupt files are refused in microseconds with the
// element that is wrong. Grid payloads themselves are left to OpenVDB.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace vox {

struct VdbGridFrame {
  std::string uniqueName, type;
  int64_t gridPos = 0, blockPos = 0, endPos = 0;
};

struct VdbFrame {
  uint32_t fileVersion = 0;
  uint32_t libraryMajor = 0, libraryMinor = 0;
  std::vector<std::string> metadataNames;
  std::vector<VdbGridFrame> grids;
};

/// Walks the framing of `path`. Throws vox::Error (BadInput) naming the file and
/// the element (header field, metadata entry, grid descriptor) that is
/// truncated or out of range.
VdbFrame checkVdbStructure(const std::string& path);

/// Same on bytes in memory.
VdbFrame checkVdbStructure(const uint8_t* data, size_t size, const std::string& nameForMessages);

}  // namespace vox
