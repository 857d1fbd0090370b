// Joining the page files of a region bake's parts (libvox/core/regions.h) into
// the page file of the whole world: `vox pack-chunks --merge PART.vpk...`.
//
// The result is byte for byte the file `vox pack-chunks` writes for the
// single-process scene with the same chunk side, layout and alignment
// (formats/pagefile/PAGEFILE.md, "Merging the parts of a region bake", states
// the rule). A level-0 chunk lies wholly in one part (tiles are cut on
// 32-voxel cells), so its payload is copied verbatim when the part's channel
// flags are the world's, and re-encoded through its layout's decoder and
// encoder (no votes needed) when the part lacks a channel the world has.
//
// Deterministic: chunks are processed in parallel into their own slots and
// written in (level, Morton key) order, so the bytes do not depend on the
// thread count.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "formats/pagefile/pagefile.h"

namespace vox {

struct MergeSettings {
  unsigned threads = 1;  // 0: every core; any count gives the same bytes
};

/// What a merge did, for `--report`.
struct MergeStats {
  uint64_t partFileBytes = 0;     // sum of the parts' sizes
  uint64_t copiedChunks = 0, copiedBytes = 0;          // payloads copied verbatim
  uint64_t reencodedChunks = 0, reencodedBytes = 0;    // payloads decoded and encoded again (output bytes)
  uint64_t joinedChunks = 0;      // of those, chunks of a mip level that several parts hold (joined by union)
  uint64_t rebuiltChunks = 0, rebuiltBytes = 0;        // chunks of the levels rebuilt from the seam voxels
  uint64_t seamVoxels = 0;        // voxels of the seam level, from the parts' metadata
  uint64_t flagsFromParts = 0;    // the world's channel flags (OR of the parts')
  double checkSeconds = 0;     // metadata, checkRegionParts, settings, the chunks' places
  double reencodeSeconds = 0;  // decoding and encoding
  double mipsSeconds = 0;      // the seam level joined, coarser levels reduced and packed
  double writeSeconds = 0;     // index, metadata, the file's layout and its first bytes
  double copySeconds = 0;      // every payload written at its offset (copies CRC-checked on the way)
};

struct MergeResult {
  uint64_t fileBytes = 0;  // of the file written
  uint32_t alignment = 0;  // its payload alignment in bytes (the parts' --align; auto chosen over the world's chunks)
  struct Level {
    int level = 0;
    uint64_t chunks = 0, fullChunks = 0, voxels = 0, payloadBytes = 0;
  };
  std::vector<Level> levels;
  MergeStats stats;
};

/// Merges the parts (opened page files; `parts[i].name()` names it in
/// messages). Throws vox::Error (BadInput) naming the part, and the chunk when
/// one is at fault, for: a page file that is not a part (no `region` in its
/// metadata); parts of different bakes, repeated, overlapping or missing tiles
/// (checkRegionParts); parts with different chunk side, layout, alignment,
/// level count or mip occupancy; a chunk outside its part's tile; a payload
/// whose CRC32C or structure is wrong (every chunk's CRC is checked, those of
/// the levels rebuilt from the seam voxels included, as `--verify` would).
/// Checks and re-encoding come before the output is created; a copied
/// payload's CRC is checked as it is copied, so on error
/// `outputPath` may hold a partial file: write to a temporary file
/// (formats/core/file_util.h AtomicOutput) and commit it on success.
/// Writes the file at `outputPath` (extended to its size, then runs of
/// consecutive payloads of a few MiB, each assembled in a buffer and written
/// with one pwrite); throws vox::Error (Io) when it cannot.
MergeResult mergePageFiles(std::span<const pagefile::Reader* const> parts, const MergeSettings& settings,
                           const std::string& outputPath);

}  // namespace vox
