// Touched-set files (formats/image/RENDER.md, "voxbake-touched"): the chunks a
// camera path's rays hit, with the count of distinct voxels hit in each, as
// render-canonical --touched writes them.
//
// One writer (touchedSetJson) and one reader (parseTouchedSet); the reader
// checks what the format promises (Morton order, counts adding up) and names
// the element it refuses.
//
// Thread safety: pure functions.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "libvox/core/types.h"
#include "libvox/render/touched_voxels.h"

namespace vox {

/// The value of the file's "format" key.
inline constexpr const char* kTouchedSetFormat = "voxbake-touched";

struct TouchedSet {
  std::string scene;           // the input's path, as given
  Dims dims;                   // the grid's extent in voxels
  uint32_t chunkSide = 0;      // C: chunks are C^3 voxels
  uint64_t views = 0;          // cameras of the path
  uint64_t rays = 0, hits = 0;  // over every view
  uint64_t voxelsTouched = 0;  // distinct voxels hit: the sum of the chunks' counts
  std::vector<TouchedChunk> chunks;  // sorted by Morton key
  bool operator==(const TouchedSet&) const = default;
};

/// The file's text: JSON with sorted keys, one space of indent, a final newline.
std::string touchedSetJson(const TouchedSet& set);

/// Parses a file's text; throws vox::Error (BadInput) naming `name` and the element.
TouchedSet parseTouchedSet(const std::string& text, const std::string& name);

/// readFileBytes + parseTouchedSet.
TouchedSet readTouchedSet(const std::string& path);

}  // namespace vox
