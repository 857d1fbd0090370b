// vox merge PART.vdb... -o WORLD.vdb: joins the parts of a region bake
// (vox voxelize --region I/N or --region-box) into the world scene, byte for
// byte what the single-process bake writes (libvox/scene/scene_parts.h,
// docs/scale.md "Merging scenes").
#include <CLI/CLI.hpp>
#include <algorithm>

#include "formats/core/file_kinds.h"
#include "formats/core/file_util.h"
#include "formats/scene/scene_vdb_direct.h"
#include "formats/vdb/pyramid_vdb.h"
#include "formats/vdb/scene_vdb.h"
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
  // released: the peak is the world's blocks plus one part. The guard: the
  // blocks hold about kBlockBytesPerFileByte bytes per byte of the parts'
  // (compressed) files, measured on the hamlet and the city (docs/scale.md).
  {
    constexpr double kBlockBytesPerFileByte = 7.0;
    uint64_t fileBytes = 0, largest = 0;
    for (const std::string& path : o.parts) {
      const int64_t size = std::max<int64_t>(0, vox::fileSizeOrMinusOne(path));
      fileBytes += uint64_t(size);
      largest = std::max<uint64_t>(largest, uint64_t(size));
    }
    vox::MemoryEstimate e;
    e.add("resident before the merge", vox::residentBytesNow());
    e.add("world blocks", double(fileBytes) * kBlockBytesPerFileByte);
    e.add("one part read", double(largest) * kBlockBytesPerFileByte);
    run.checkMemory(e, "merging " + std::to_string(o.parts.size()) + " parts");
  }
  run.phase("read");
  std::vector<vox::SceneHeader> headers;
  vox::VoxelBlocks blocks;
  uint64_t partVoxels = 0;
  for (const std::string& path : o.parts) {
    run.input(path);
    vox::requireRegularFile(path);
    if (!vox::looksLikeVdb(path))
      vox::throwBadInput(path + ": not an OpenVDB file; vox merge joins the parts vox voxelize --region wrote");
    if (vox::isPyramidVdb(path))
      vox::throwBadInput(path + ": a pyramid (vox mip output); vox merge joins level-0 parts: merge them, then run "
                                "vox mip on the world");
    const vox::Scene part = vox::readSceneVdb(path);
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
