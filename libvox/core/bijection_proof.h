// Proof that an AtlasLayout is a bijection between the voxel domain and the
// in-domain texels, for `vox verify-bijection --dims`.
//
// Exhaustive (up to `exhaustiveLimit` voxels): every voxel is mapped forward;
// the texel must lie in the atlas, must not be hit twice (a bit per texel, set
// 64 at a time with atomic OR so a collision is seen by whichever thread comes
// second), and must map back to the voxel; then every texel that was not hit
// must be reported as padding by the inverse. Together: the forward map is
// injective, its image is exactly the texels the inverse accepts, and the
// inverse undoes it.
//
// By parts (larger layouts): the in-tile map is separable (x depends on u and
// w, y on v and w), so the u and v axes are checked exhaustively at the extreme
// tile positions, the tile-index map w <-> (layer, row, column) for every w and
// tile slot, and the composition is argued in `argument` (Euclidean division).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "libvox/core/atlas_mapping.h"

namespace vox {

struct BijectionFailure {
  std::string what;                 // "collision", "out of range", "inverse differs", "padding aliased"
  Coord3 voxel;                     // the voxel concerned (for padding: the voxel the inverse claimed)
  TexelAddress texel;
  std::optional<Coord3> decoded;    // what the inverse returned
  std::optional<Coord3> otherVoxel; // for collisions: the voxel that hit the texel first (if known)
};

struct BijectionResult {
  std::string method;            // "exhaustive" or "by-parts"
  uint64_t voxelsChecked = 0;   // exhaustive: every voxel; by parts: axis positions checked
  uint64_t texelsChecked = 0;   // exhaustive: every texel; by parts: tile slots checked
  uint64_t paddingTexels = 0;
  uint64_t failures = 0;
  std::optional<BijectionFailure> first;  // the first failure in voxel order (w, v, u), then texel order
  std::string argument;          // for by-parts: why the parts compose
  bool ok() const { return failures == 0; }
};

BijectionResult proveBijection(const AtlasLayout& layout, unsigned threads,
                               uint64_t exhaustiveLimit = uint64_t(1) << 32);

}  // namespace vox
