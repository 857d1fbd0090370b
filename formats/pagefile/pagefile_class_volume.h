// A page file level as a ClassVolume (libvox/core/class_volume.h), for
// exporters: each stored voxel's `cls` summary byte and, when asked for, its
// colour (stored as sRGB8, decoded to linear light), clipped to an index box of
// that level. No OpenVDB.
#pragma once

#include "formats/pagefile/pagefile.h"
#include "libvox/core/class_volume.h"
#include "libvox/core/classes.h"

namespace vox {

/// Level `level` of `reader` inside `box` (inclusive, in the level's index
/// space). Chunks are decoded (CRC-checked) in parallel on up to `threads`
/// workers; the result does not depend on `threads`. Throws vox::Error
/// (BadInput) on a corrupt chunk, naming it, and when a voxel's `cls` has no
/// entry in `classes` (the file's class table): a file damaged or written by
/// another tool, named with the level (when not 0), the chunk, the voxel
/// (the first in file order, whatever `threads`), the class and the fix.
ClassVolume classVolumeFromPages(const pagefile::Reader& reader, int level, const IndexBox& box,
                                 const ClassTable& classes, bool withColor, unsigned threads);

}  // namespace vox
