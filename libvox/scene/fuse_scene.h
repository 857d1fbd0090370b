// The scene a fusion makes (`vox fuse`, docs/fuse.md): the input scene's votes
// plus the new ones, with the carve rule applied to the sum of every free
// count, old and new.
//
// Carve rule, per voxel, on totals: V = every class vote (input scene + new),
// F = every free count (input `free` grid + new). With carving on, a voxel
// with F > V is empty: it keeps no votes and its `free` entry becomes F - V
// (the net evidence for empty space, so that a later run sees the same
// balance: fusing views in several runs empties the same voxels as one run).
// Otherwise the voxel is occupied with all its votes and keeps F. With
// carving off nothing is removed and F is kept as is.
// Surface flags: an input voxel keeps its flag; a voxel first occupied by a
// fusion is a surface voxel (a view saw it). Colour: an occupied voxel with
// colour samples gets their average in linear light (replacing an input
// colour); other input voxels keep theirs.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "libvox/render/fuse.h"
#include "libvox/scene/scene.h"

namespace vox {

struct FuseTotals {
  uint64_t occupiedBefore = 0, occupiedAfter = 0;
  uint64_t voxelsVoted = 0;   // distinct voxels that got new votes
  uint64_t created = 0;       // occupied now, not in the input
  uint64_t removed = 0;       // occupied in the input, carved now
  uint64_t rejected = 0;      // got new votes but stayed (or became) empty by the carve rule
  uint64_t freeVoxels = 0;    // voxels with a free count in the output
  uint64_t colored = 0;       // occupied voxels given a colour by this fusion
};

struct FusedScene {
  Scene scene;
  FuseCounts free;  // the output's free counts (its votes are empty); writers clamp them to 2^31 - 1
  FuseTotals totals;
};

/// `header` is the output's (the input scene's when `base` is given); every
/// new vote's class must be in its class table. `counts` holds the new votes
/// and every free count, the input's (its `free` grid) included.
FusedScene applyFusion(const SceneHeader& header, const Scene* base, FuseCounts&& counts, bool carve);

}  // namespace vox
