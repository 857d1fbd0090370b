// Writes a scene straight from its voxel blocks into a .vdb file, without
// OpenVDB in the process.
//
// Why our own writer: `vox voxelize MESH` is a short process, and loading
// OpenVDB with its ~20 dependent libraries costs ~45 ms and ~33 MB of resident
// pages (its 25 MB symbol segment is paged in whole) before any work: a third
// of a 256^3 surface bake's run time and more than half of its peak memory
// (docs/bench-voxelize.md). Scenes only ever hold voxel leaves (no tiles), so
// the part of the format they need is small and fixed.
//
// The file is what formats/vdb/scene_vdb.h's writeSceneVdb writes for the same
// scene (OpenVDB 10 file format 224, Blosc-compressed active values, the same
// grids, metadata, transform and grid statistics), byte for byte except the
// 16-byte file UUID: tests/test_scene_vdb_direct.cpp checks this against
// openvdb::io::File on several scenes. The UUID is derived from the content
// (CRC32C of everything after the header, four seeds) rather than random, so
// the same bake gives the same bytes.
//
// Node sizes in the `file_mem_bytes` statistic are OpenVDB 10's on x86-64
// (measured with sizeof and memUsage(); the test catches a mismatch).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "formats/scene/scene_meta.h"
#include "libvox/core/scene_header.h"
#include "libvox/mesh/voxel_blocks.h"

namespace vox {

struct DirectWriteSummary {
  uint64_t occupied = 0;                // active voxels of the occupancy grid
  uint64_t surface = 0;                 // of them, with the surface flag
  std::vector<uint8_t> classesPresent;  // ids with a votes grid, ascending
  bool color = false;
  uint64_t fileBytes = 0;
};

/// Validates `blocks` against `header` (VoxelBlocks::validate: vox::Error
/// Internal on failure), then writes the scene to `path` (which it creates or
/// truncates; callers write to a temporary name and rename). Leaf compression
/// runs on `threads` threads; the bytes do not depend on it. The blocks' votes
/// and colours are released as they are written. Throws vox::Error (Io) when
/// the file cannot be written.
DirectWriteSummary writeSceneVdbDirect(const SceneHeader& header, VoxelBlocks& blocks, const std::string& path,
                                       unsigned threads = 1);

/// What writeSceneVdbDirect needs in memory besides the blocks it writes:
/// the lists of each grid's leaves (`leaves` blocks, `voteLeaves` summed over
/// the vote grids, `colorLeaves` coloured), one batch of leaf buffers per
/// thread at `leafBytes` a leaf (its mask and compressed values: 89 bytes plus
/// 4 a vote or 12 a colour at most), its file buffer. The leaf buffers are
/// written a batch at a time, so nothing grows with the grids' bytes.
double directWriteBytes(double leaves, double voteLeaves, double colorLeaves, double leafBytes, unsigned threads);

/// One scene among several in one file (a level of a pyramid,
/// formats/vdb/pyramid_vdb.h): its grids are named `gridPrefix` + the scene's
/// grid names and carry `gridMetadata` besides their own, as
/// formats/vdb/vdb_scene_grids.h's appendSceneGrids gives them.
struct DirectScenePart {
  const SceneHeader* header = nullptr;
  std::vector<const VoxelBlock*> blocks;  // any order; no two at one origin, no runs (materializeRuns)
  std::string gridPrefix;
  MetaEntries gridMetadata;
  /// Write the colour grid even when no voxel has a colour (a level of a
  /// coloured scene whose coloured voxels all dropped out).
  bool colorGrid = false;
};

/// Writes the grids of every part, in order, into one file whose metadata is
/// fileMetadata(the parts' summaries), called before anything is written
/// (fileBytes is 0 there; in the result it is the file's size). The blocks are
/// neither validated nor released: the caller made them (a reduction of a
/// checked scene). Same bytes as openvdb::io::File would write for the same
/// grids and metadata, except the UUID; they do not depend on `threads`.
/// Throws vox::Error (Io) when the file cannot be written, naming it `what`
/// ("pyramid").
std::vector<DirectWriteSummary> writeScenesVdbDirect(
    const std::vector<DirectScenePart>& parts,
    const std::function<MetaEntries(const std::vector<DirectWriteSummary>&)>& fileMetadata, const std::string& path,
    unsigned threads, const std::string& what);

}  // namespace vox
