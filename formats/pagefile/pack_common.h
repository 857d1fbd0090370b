// What the two packers of pack_chunks.h share: packChunks of scenes
// (pack_chunks.cpp, OpenVDB trees) and of scene leaves (pack_leaves.cpp, no
// OpenVDB, also linked by the light pack module). Internal to formats/pagefile.
#pragma once

#include <exception>
#include <span>
#include <vector>

#include "formats/pagefile/layouts.h"
#include "formats/pagefile/pack_chunks.h"
#include "formats/pagefile/pagefile.h"
#include "formats/pagefile/pagefile_meta.h"
#include "libvox/core/morton.h"
#include "libvox/core/parallel.h"

namespace vox::packing {

/// Throws vox::Error (Usage) for an unsupported chunk side, alignment or layout.
void checkSettings(const PackSettings& s, size_t levelCount);

/// The file header from the base level's header and the channels of all levels.
pagefile::Header fileHeader(const SceneHeader& bh, const PackSettings& s, size_t levelCount, bool anyColor,
                            bool anyInterior);

/// A ChunkVoxels for chunks of side `side`, reused chunk after chunk (its
/// buffers are sized once per worker).
pagefile::ChunkVoxels chunkBuffers(uint32_t side, bool withVotes);

/// Occupied voxel k (chunk-local index) of `sc`: its votes (sorted by class),
/// surface flag and linear colour (nullptr: none).
void putVoxel(pagefile::ChunkVoxels& sc, uint32_t k, bool surface, std::span<const ClassVotes> votes,
              const float* color);

/// Starts a chunk in `sc`: no voxel.
void clearChunk(pagefile::ChunkVoxels& sc);

/// The page file's metadata but its levels, from the base level's header.
pagefile::PageMeta packMeta(const SceneHeader& bh, const PackSettings& s);

/// Level `li` (header `sh`, chunks `levelBlobs`) added to the file's blobs, the
/// result's counts and the metadata.
void addLevel(size_t li, const SceneHeader& sh, const pagefile::Header& h, std::vector<pagefile::ChunkBlob> levelBlobs,
              std::vector<pagefile::ChunkBlob>& blobs, PackResult& result, pagefile::PageMeta& meta);

// The chunks with Morton keys `keys` (ascending) of one level, encoded.
// Workers take contiguous ranges of chunks; each chunk's payload lands in its
// own slot, so the result does not depend on the thread count. A layout's
// refusal is reported for the first chunk in order. `makeGatherer()` gives a
// worker's gatherer, whose gather(ci, chunk coordinates) returns chunk ci's voxels.
template <typename MakeGatherer>
std::vector<pagefile::ChunkBlob> encodeChunks(const std::vector<uint64_t>& keys, int level, const pagefile::Header& h,
                                              unsigned threads, const MakeGatherer& makeGatherer) {
  const pagefile::LayoutCodec& codec = pagefile::codecOf(h.layout);
  const uint32_t N = h.chunkVoxels();
  std::vector<pagefile::ChunkBlob> out(keys.size());
  std::vector<std::exception_ptr> errors(keys.size());
  parallelPieces(keys.size(), threads, 0, [&](size_t begin, size_t end, size_t) {
    auto gatherer = makeGatherer();
    for (size_t ci = begin; ci < end; ++ci) {
      const auto cc = mortonDecode(keys[ci]);
      const pagefile::ChunkVoxels& sc = gatherer.gather(ci, cc);
      pagefile::ChunkBlob& blob = out[ci];
      blob.level = uint8_t(level);
      blob.key = keys[ci];
      blob.occupied = sc.count;
      blob.full = sc.count == N;
      if (sc.count == 0) continue;  // a leaf without active voxels
      try {
        blob.bytes = codec.encode(sc, h.flags, {level, cc});
      } catch (...) {
        errors[ci] = std::current_exception();
      }
    }
  });
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
  std::erase_if(out, [](const pagefile::ChunkBlob& b) { return b.occupied == 0; });  // leaves without active voxels
  return out;
}


}  // namespace vox::packing
