// The brick layout of a page-file payload (formats/pagefile/PAGEFILE.md,
// "Payload, `bricks` layout"): an occupancy bitmap of the chunk (absent when it
// is full), then the summary bytes, colours and surface bits of the occupied
// voxels in rank order. Its encoder, decoder and size rule; the table in
// layouts.cpp registers them.
#pragma once

#include <cstdint>
#include <vector>

#include "formats/pagefile/layouts.h"

namespace vox::pagefile {

/// Bytes of a bricks payload of a chunk of `chunkVoxels` voxels (C^3).
uint64_t bricksPayloadBytes(uint32_t chunkVoxels, uint32_t occupied, bool full, uint32_t flags);
/// bricksPayloadBytes for an index entry: the layout's size is known from the index alone.
uint64_t bricksSizeFromIndex(const Header& header, const IndexEntry& entry);

std::vector<uint8_t> encodeBricks(const ChunkVoxels& chunk, uint32_t flags, const ChunkPlace& place);
std::vector<DecodedVoxel> decodeBricks(const ChunkPayload& payload);

}  // namespace vox::pagefile
