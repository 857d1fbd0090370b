// `vox pack-chunks --verify`: everything a reader of a page file relies on,
// checked once, so that a file --verify passes is one that `vox info`,
// `export` and `render-canonical` read.
#pragma once

#include <cstdint>

#include "formats/pagefile/pagefile.h"

namespace vox::pagefile {

/// Checks an opened page file (Reader::open has checked the header, the
/// index and the metadata's CRC) beyond what opening checks:
/// * the metadata, read by readPageMeta (pagefile_meta.h), the reader of
///   `vox info` and the exporters: JSON, its keys' types and ranges;
/// * every payload: CRC32C and decoding by its layout (Reader::decode);
/// * every voxel's class in the metadata's class table, the mip bricks of an
///   `svo` chunk included (a class the table lacks cannot be named or coloured);
/// * the padding between the metadata and the payloads and between payloads
///   (Reader::checkPadding).
/// Returns the voxels of the chunks (as Reader::verify). Throws vox::Error
/// (BadInput) naming the file, and the chunk and voxel when one is at fault:
/// the first faulty chunk in index order, at any thread count.
/// Chunks are checked on up to `threads` workers (0 = every core,
/// vox::parallelForEach); the Reader is only read, so it may be shared.
uint64_t verifyPageFile(const Reader& reader, unsigned threads = 0);

}  // namespace vox::pagefile
