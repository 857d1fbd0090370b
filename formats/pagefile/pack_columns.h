// The `columns` page-file layout (formats/pagefile/PAGEFILE.md, seed 004): per chunk a
// solid mask and a surface mask of z-innermost u32 words, a mip ladder of solid
// masks, summary bytes of every occupied voxel, and colour offsets per column
// with packed colours of the surface voxels only.
#pragma once

#include <cstdint>
#include <vector>

#include "formats/pagefile/pack_chunks.h"

namespace vox::packdetail {

/// The payload of one chunk. Throws vox::Error (Usage) when an interior voxel
/// has a colour (the layout stores colour for surface voxels only), naming it.
std::vector<uint8_t> encodeColumns(const ChunkVoxels& chunk, uint32_t flags, const ChunkPlace& place);

}  // namespace vox::packdetail
