// The column layout of a page-file payload (formats/pagefile/PAGEFILE.md,
// "Payload, `columns` layout"): per chunk a solid mask and a surface mask of
// z-innermost u32 words (one column of C voxels is C consecutive bits), a mip
// ladder of solid masks, the summary bytes of every occupied voxel, and colour
// offsets per column with packed colours of the surface voxels only. Its
// encoder, decoder and size rules; the table in layouts.cpp registers them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "formats/pagefile/layouts.h"

namespace vox::pagefile {

/// Byte offsets of the payload's fixed part: `surface_count` and a reserved u32.
namespace columns_field {
inline constexpr size_t kSurfaceCount = 0;
inline constexpr size_t kReserved = 4;
}  // namespace columns_field
inline constexpr uint32_t kColumnsFixedBytes = 8;

/// u32 words of a mask of side^3 bits: ceil(side^3 / 32).
uint32_t columnsLadderWordCount(uint32_t side);
/// Bytes of the mip ladder of a chunk of side C (levels 1 .. log2 C - 1).
uint64_t columnsLadderBytes(uint32_t chunkSide);
/// Bytes of a columns payload.
uint64_t columnsPayloadBytes(uint32_t chunkSide, uint32_t occupied, uint32_t surfaceCount, bool full, uint32_t flags);

/// The payload of one chunk. Throws vox::Error (Usage, Setting::PageLayout)
/// when an interior voxel has a colour (the layout stores colour for surface
/// voxels only), naming the voxel.
std::vector<uint8_t> encodeColumns(const ChunkVoxels& chunk, uint32_t flags, const ChunkPlace& place);
std::vector<DecodedVoxel> decodeColumns(const ChunkPayload& payload);

}  // namespace vox::pagefile
