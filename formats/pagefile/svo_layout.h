// The sparse-voxel-octree layout of a page-file payload
// (formats/pagefile/PAGEFILE.md, "Payload, `svo` layout"): per chunk a
// pointerless octree of 64-bit nodes over 8^3 bricks, breadth first; every node
// owns one brick of the brick pool (leaves: the chunk's voxels; inner nodes: a
// mip brick, the node's region reduced to 8^3 as a mip pyramid with `Any`
// occupancy reduces a scene, libvox/scene/mip.h), then the per-voxel data of
// the bricks' occupied voxels.
// Its encoder, decoder and size rule; the table in layouts.cpp registers them.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "formats/pagefile/layouts.h"
#include "formats/pagefile/pagefile.h"

namespace vox::pagefile {

/// Node flags.
inline constexpr uint8_t kSvoNodeFull = 1;   // the node's brick has all 512 voxels (no bitmap stored)
inline constexpr uint8_t kSvoNodeColor = 2;  // some voxel of the node's brick has a colour
/// The brick table's bitmap slot of a full brick.
inline constexpr uint32_t kSvoNoBitmap = 0xFFFFFFFFu;

/// Byte offsets of the payload's fixed part: three u32 counts and a reserved u32.
namespace svo_field {
inline constexpr size_t kNodeCount = 0;
inline constexpr size_t kBitmapCount = 4;
inline constexpr size_t kRecordCount = 8;
inline constexpr size_t kReserved = 12;
}  // namespace svo_field
inline constexpr uint32_t kSvoFixedBytes = 16;

/// Bytes of an svo payload with `nodes` nodes (= bricks), `bitmaps` stored
/// bitmaps and `records` voxel records (leaf and mip voxels).
uint64_t svoPayloadBytes(uint64_t nodes, uint64_t bitmaps, uint64_t records, uint32_t flags);

/// The payload of one chunk. `chunk.withVotes` must be set (mip bricks sum votes).
std::vector<uint8_t> encodeSvo(const ChunkVoxels& chunk, uint32_t flags, const ChunkPlace& place);
/// The chunk's level-0 voxels (the leaf bricks), after checking the whole tree.
std::vector<DecodedVoxel> decodeSvo(const ChunkPayload& payload);

/// One node of an svo-layout chunk with its decoded brick.
struct SvoBrick {
  uint32_t node = 0;      // index in the node pool (= brick index)
  uint8_t level = 0;      // 0: a leaf brick (voxels of the chunk); L > 0: a mip brick, voxels 2^L wide
  uint8_t childMask = 0;  // octants of the brick that hold an occupied voxel (inner nodes: the children)
  uint8_t flags = 0;      // kSvoNodeFull, kSvoNodeColor
  uint32_t childPtr = 0;  // inner nodes: first child; leaves: the brick (= node)
  std::array<uint32_t, 3> origin{};  // chunk-local level-0 voxel at the node's min corner
  std::vector<DecodedVoxel> voxels;  // index = bx + 8 * (by + 8 * bz) within the brick, ascending
};

/// The payload of one chunk from its decoded bricks (svoBricks of one or more
/// files: every brick voxel, leaf and mip, is placed in its level's grid, so
/// bricks of the same chunk from several region parts join by union), written
/// by the same tree builder and writer as encodeSvo. For re-encoding without
/// votes: the mip bricks are taken as they are, not recomputed. `side` is C.
std::vector<uint8_t> encodeSvoFromBricks(std::span<const SvoBrick> bricks, uint32_t side, uint32_t flags);
/// Every node of entry i of an svo-layout file with its brick, in node order
/// (the same checks as Reader::decode). Throws vox::Error (BadInput) when the
/// file has another layout.
std::vector<SvoBrick> svoBricks(const Reader& reader, size_t i);

}  // namespace vox::pagefile
