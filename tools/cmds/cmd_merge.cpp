// vox merge PART.vdb... -o WORLD.vdb: joins the parts of a region bake
// (vox voxelize --region I/N or --region-box) into the world scene, byte for
// byte what the single-process bake writes (libvox/scene/scene_parts.h,
// docs/scale.md "Merging scenes").
#include <CLI/CLI.hpp>
#include <algorithm>
#include <memory>

#include "formats/core/file_kinds.h"
#include "formats/core/file_util.h"
#include "formats/scene/scene_vdb_direct.h"
#include "formats/vdb/pyramid_vdb.h"
#include "formats/vdb/scene_vdb.h"
#include "formats/vdb/vdb_memory.h"
#include "formats/vdb/vdb_structure.h"
#include "libvox/core/flat_map64.h"
#include "libvox/mesh/voxel_blocks.h"
#include "libvox/core/error.h"
#include "libvox/core/regions.h"
#include "libvox/scene/scene_parts.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"

namespace voxcli {

namespace {

struct MergeOptions {
  std::vector<std::string> parts;
  std::string output;
  CommonOptions common;
};

int runMerge(const MergeOptions& o) {
  if (!vox::hasExtension(o.output, ".vdb"))
    vox::throwUsage("-o " + o.output + ": the merged scene is written as OpenVDB; name it *.vdb");
  Run run("merge", o.common);
  const std::string outTemp = run.output(o.output);  // checks the destination before the work

  // Each part is read, checked and added to the world's blocks, then
  // released: the peak is the world's blocks plus one part as OpenVDB trees,
  // or the world's blocks and the direct writer's leaf lists and batches.
  // Counted from each part's topology (leaf counts and active voxels per
  // grid, no leaf decompressed). It was 7 bytes per byte of all the parts'
  // files plus 7 per byte of the largest, which held the writer's buffers
  // grown by doubling: 2.0-2.4x the peak once the writer wrote a batch at a
  // time (docs/reliability.md "Memory").
  // The topology walks are kept and finished by the reads below, so each
  // part is mapped and walked once (docs/scale.md "Merge cost"); a part
  // keeps its topology's pages and its leaves' origins until it is read.
  std::vector<std::unique_ptr<vox::VdbTopologyWalk>> walked(o.parts.size());
  {
    const double residentBefore = double(vox::residentBytesNow());
    double blocks = 0, voteLeaves = 0, colorLeaves = 0, blockBytes = 0, largestTrees = 0, maxPerLeaf = 0;
    for (size_t i = 0; i < o.parts.size(); ++i) {
      const std::string& path = o.parts[i];
      vox::requireRegularFile(path);
      if (!vox::looksLikeVdb(path)) continue;  // refused with its message when read
      walked[i] = std::make_unique<vox::VdbTopologyWalk>(path);
      const vox::VdbFrame& frame = walked[i]->frame();
      largestTrees = std::max(largestTrees, vox::sceneGridBytes(frame, false, vox::SceneReadForm::Trees));
      for (const vox::VdbGridFrame& g : frame.grids) {
        if (!g.checked || !g.instanceParent.empty() || g.leafCount == 0) continue;
        const double leaves = double(g.leafCount), active = double(g.activeLeafVoxels);
        const double perLeaf = active / leaves;
        if (g.uniqueName == vox::kOccupancyGridName) {
          blocks += leaves;
        } else if (g.type.find("_int32_") != std::string::npos) {
          // A class block, its counts grown by doubling from 16 (1.4x the
          // counts on average), dense (2 KB) past 128: 5.6 bytes a voted
          // voxel bounds both, capped at the dense block.
          voteLeaves += leaves;
          blockBytes += leaves * (sizeof(vox::ClassBlock) + 2 * vox::kMallocBlockBytes + sizeof(void*)) +
                        std::min(leaves * vox::kBlockVoxels * 4.0, std::max(leaves * 64.0, active * 4 * 1.4));
          maxPerLeaf = std::max(maxPerLeaf, 4 * perLeaf);
        } else {
          // Colours, appended in voxel order to a vector grown by doubling.
          colorLeaves += leaves;
          blockBytes += leaves * vox::kMallocBlockBytes + active * 12 * 1.4;
          maxPerLeaf = std::max(maxPerLeaf, 12 * perLeaf);
        }
      }
    }
    // A block, its malloc header and its entry in the block map (the old
    // array too while the map grows).
    constexpr double kMapEntry = double(vox::FlatMap64<std::unique_ptr<vox::VoxelBlock>, vox::PackedCoordHome>::slotBytesPerKey());
    blockBytes += blocks * (sizeof(vox::VoxelBlock) + vox::kMallocBlockBytes + kMapEntry);
    const double writer = vox::directWriteBytes(blocks, voteLeaves, colorLeaves, 89 + maxPerLeaf, run.threads());
    vox::MemoryEstimate e;
    // Measured before the walks: what they hold is released part by part as
    // the world's blocks grow, so it is not part of the peak counted here.
    e.add("resident before the merge", residentBefore);
    e.add("world blocks", blockBytes);
    e.add("one part read, or the scene writer", std::max(largestTrees, writer));
    run.checkMemory(e, "merging " + std::to_string(o.parts.size()) + " parts");
  }
  run.phase("read");
  std::vector<vox::SceneHeader> headers;
  vox::VoxelBlocks blocks;
  uint64_t partVoxels = 0;
  for (size_t i = 0; i < o.parts.size(); ++i) {
    const std::string& path = o.parts[i];
    run.input(path);
    // The estimate checked every part as a file and walked each OpenVDB one.
    if (!walked[i])
      vox::throwBadInput(path + ": not an OpenVDB file; vox merge joins the parts vox voxelize --region wrote");
    if (vox::isPyramidFrame(walked[i]->frame()))
      vox::throwBadInput(path + ": a pyramid (vox mip output); vox merge joins level-0 parts: merge them, then run "
                                "vox mip on the world");
    const vox::Scene part = vox::readSceneVdb(*walked[i]);
    walked[i].reset();
    if (!part.header().region)
      vox::throwBadInput(path + ": not a part of a region bake (no region record); merge the files that vox "
                                "voxelize --region wrote");
    if (!headers.empty()) {
      // Check the set so far before the work of adding this part.
      std::vector<vox::SceneHeader> sofar = headers;
      sofar.push_back(part.header());
      std::vector<vox::RegionPart> rp;
      for (size_t i = 0; i < sofar.size(); ++i) rp.push_back({o.parts[i], &sofar[i]});
      const vox::SceneRegion& a = sofar.front().region.value();
      const vox::SceneRegion& b = sofar.back().region.value();
      // A full check (missing tiles included) waits for the last part; here
      // only what two parts can already show.
      if (a.worldKey != b.worldKey || !(sofar.front().dims == sofar.back().dims) || a.count != b.count)
        (void)vox::checkRegionParts({rp.front(), rp.back()});
    }
    partVoxels += part.occupiedCount();
    vox::addPartBlocks(part, path, blocks);
    headers.push_back(part.header());
  }
  run.phase("check");
  vox::SceneHeader world = vox::mergedHeader(headers, o.parts);
  run.phase("write");
  const vox::DirectWriteSummary s = vox::writeSceneVdbDirect(world, blocks, outTemp, run.threads());
  const vox::Dims d = world.dims;
  const vox::SceneRegion& r = headers.front().region.value();
  run.counts()["dims"] = {d.x, d.y, d.z};
  run.counts()["parts"] = o.parts.size();
  run.counts()["tiles"] = r.count;
  run.counts()["part_voxels"] = partVoxels;
  run.counts()["occupied_voxels"] = s.occupied;
  run.counts()["surface_voxels"] = s.surface;
  run.counts()["classes_present"] = s.classesPresent.size();
  run.counts()["file_bytes"] = s.fileBytes;
  run.counts()["world_key"] = r.worldKey;
  run.noteWhenDone("wrote " + o.output + ": " + vox::toString(d) + ", " + counted(s.occupied, "occupied voxel", "occupied voxels") +
           " from " + counted(o.parts.size(), "part", "parts"));
  return run.finish();
}

}  // namespace

Command registerMerge(CLI::App& root) {
  auto o = std::make_shared<MergeOptions>();
  CLI::App* cmd = root.add_subcommand("merge", "Join the parts of a region bake into the world scene (.vdb)");
  cmd->footer(
      "The parts are what vox voxelize --region I/N (all N tiles) or --region-box (disjoint boxes) wrote for\n"
      "one world; the merged file is byte-identical to the single-process bake. A missing, repeated,\n"
      "overlapping or foreign part (another input, resolution or setting) is refused naming it (exit 3),\n"
      "and nothing is written.\n"
      "Example: vox merge part0.vdb part1.vdb part2.vdb -o world.vdb");
  cmd->add_option("parts", o->parts, "The parts (.vdb), in any order")->required();
  cmd->add_option("-o,--output", o->output, "Scene file to write (*.vdb)")->required();
  addCommonOptions(*cmd, o->common);
  return {cmd, [o] { return runMerge(*o); }};
}

}  // namespace voxcli
