// The big built-in demo world: a procedural city (street grid, blocks of
// hollow buildings with floors, windows and roofs, parks with trees and ponds,
// rivers with bridges, a ground slab everywhere), large enough to exercise
// bakes past one machine (up to 65536 x 4096 x 65536 voxels).
//
// Everything is a pure function of integer coordinates (a hash, never a
// random generator): the layout of a street block, its lots and each
// building's parameters depend only on the block's and lot's integer
// coordinates, so any voxel, and any column, is computed without its
// neighbours' state. That gives the contract region bakes are built on:
//
//   buildCity({extent, box = B}) == buildCity({extent}) cropped to B,
//
// voxel for voxel (votes, surface flag, class), and the header (dims, voxel
// size, origin, class table, sources) is the same for every box. The surface
// flag is decided from the procedural occupancy at the 6 neighbours (outside
// the domain counts as empty), not from voxels in memory, so it does not
// depend on where a box ends.
//
// Cost: generation visits the box column by column in 8x8 tiles (one 8^3
// block column each) and, in each column, jumps from one occupied voxel to the
// next (building interiors and air are skipped analytically), so its time
// grows with the voxels produced inside the box (plus a small term per column
// of the box), never with the box's or the world's volume. Memory: the 8^3
// blocks of the voxels produced.
//
// Classes are the block palette (vox::blockPalette()), all seven used by the
// whole city (Grass parks and green roofs, Dirt ground, Stone roads and
// walls, Plank floors, wooden houses and trunks, Snow lane markings and
// roofs, Sand sidewalks and river beds, Water rivers and ponds); like the
// hamlet, the table is the whole palette whatever the box holds, so every
// part of a region bake has the same header. Votes vary per voxel (a
// coordinate hash): observation counts grow near the streets and with height,
// a quarter of the voxels are contested by a plausible confusion, some as
// exact ties. The scene carries no colour.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <string>

#include "libvox/core/city_extent.h"  // kCityName, kCityVoxelSize, extent limits, cityExtentProblem
#include "libvox/core/memory_budget.h"
#include "libvox/core/progress.h"
#include "libvox/core/scene_header.h"
#include "libvox/mesh/voxel_blocks.h"
#include "libvox/scene/scene.h"

namespace vox {

/// A box holding every voxel of any city (the default: the whole domain).
inline constexpr IndexBox kWholeCity{{0, 0, 0},
                                     {std::numeric_limits<int32_t>::max(), std::numeric_limits<int32_t>::max(),
                                      std::numeric_limits<int32_t>::max()}};

struct CityOptions {
  std::array<uint32_t, 3> extent = kCityDefaultExtent;  // voxels along x, y, z
  unsigned threads = 1;  // 1 = serial; the result does not depend on it
  ProgressFn progress;   // optional, called with the fraction of the box's tiles done
  /// Inclusive index box: only voxels inside it are generated (the box is
  /// clipped to the domain; an empty box gives an empty scene).
  IndexBox box = kWholeCity;
};

/// The city's header for `extent`: dims = extent, voxel size kCityVoxelSize,
/// origin (-X/2, 0, -Z/2) * kCityVoxelSize (centred on x and z, ground at
/// y = 0), the block palette, source kCityName. Throws vox::Error (Usage) when
/// cityExtentProblem() is not empty.
SceneHeader cityHeader(const std::array<uint32_t, 3>& extent);

/// The voxels of the city inside options.box, as blocks (for the direct scene
/// writer, formats/scene/scene_vdb_direct.h); the header is cityHeader().
VoxelBlocks buildCityBlocks(const CityOptions& options);

/// The city inside options.box as a scene with cityHeader(options.extent).
Scene buildCity(const CityOptions& options);

/// What generating a box will produce, from a sample of its 8x8-column tiles
/// (all of them when there are at most `maxSampledTiles`): the memory
/// guard's input. Deterministic; costs about maxSampledTiles tiles' work.
struct CityFootprint {
  uint64_t tiles = 0;          // 8x8-column tiles the box touches
  uint64_t sampledTiles = 0;   // tiles generated to measure
  double blocks = 0;           // 8^3 blocks with voxels (extrapolated)
  double classBlocks = 0;      // per-class vote blocks
  double classBytes = 0;       // their heap bytes as generated (classBlockHeapBytes)
  double occupied = 0;         // occupied voxels
};
CityFootprint estimateCityFootprint(const CityOptions& options, uint64_t maxSampledTiles = 2048);

/// The peak memory of generating a footprint into blocks and writing them
/// with the direct scene writer (formats/scene/scene_vdb_direct.h), without
/// what the process held before: a VoxelBlock with its hash-map entry per
/// 8^3 block, the vote blocks in it as the sample measured them (a count per
/// voted voxel, or per voxel once a block is dense), both held until the
/// writer is done, and the writer's per-leaf tables. Calibrated against measured
/// peaks at 1024^2, 2048^2 and 4096^2 (docs/city.md "Memory guard").
MemoryEstimate cityBakeMemory(const CityFootprint& footprint);

}  // namespace vox
