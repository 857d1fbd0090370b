#include "tools/cmds/mip_light.h"

#include <algorithm>
#include <filesystem>
#include <chrono>

#include "formats/core/file_kinds.h"
#include "formats/core/file_util.h"
#include "formats/scene/scene_meta.h"
#include "formats/scene/scene_vdb_direct.h"
#include "formats/vdb/pyramid_direct.h"
#include "libvox/core/error.h"
#include "tools/cli/alloc_tuning.h"
#include "tools/cli/enum_option.h"
#include "tools/cmds/option_names.h"

namespace voxcli {

std::string splitStem(const std::string& output) {
  return vox::hasExtension(output, ".vdb") ? output.substr(0, output.size() - 4) : output;
}

std::string splitName(const std::string& stem, int level) { return stem + ".mip" + std::to_string(level) + ".vdb"; }

CLI::App* addMipOptions(CLI::App& root, MipOptions& opts) {
  CLI::App* cmd = root.add_subcommand("mip", "Build the LOD pyramid of a scene (levels of voxel size 2^n)");
  cmd->footer(
      "Level n has voxels 2^n wide, reduced from level n-1 by 2x2x2 blocks: occupancy any or\n"
      "majority (ties keep the voxel), votes summed exactly (saturating at 2^31-1), colour the\n"
      "average of the coloured children, surface flag OR-ed.\n"
      "Output: one .vdb holding level 0 and every level (grids mipN.occupancy, mipN.votes.ID,\n"
      "mipN.color; "
      "formats/scene/SCENE.md \"Pyramids\"), or with --split one scene per level: OUT.mip1.vdb, ...\n"
      "--source demo:hamlet | MESH | SCENE.vdb (repeatable): with --report, the error of each level\n"
      "(occupancy IoU, class disagreement) against the source voxelized directly at its placement.\n"
      "Example: vox mip hamlet.vdb -o hamlet_mips.vdb --source demo:hamlet --report mip.json");
  cmd->add_option("input", opts.input, "Scene (.vdb)")->required();
  cmd->add_option("-o,--output", opts.output, "Pyramid file (*.vdb), or with --split the stem OUT (or OUT.vdb)")->required();
  cmd->add_option("--levels", opts.levels,
                  "Levels to build (default 0 = until one voxel, or until a level holds at most one voxel)");
  addEnumOption(*cmd, "--occupancy", opts.occupancy, mipOccupancyNames(), "any (conservative) or majority (for display)");
  cmd->add_flag("--split", opts.split, "One scene file per level (OUT.mip1.vdb, OUT.mip2.vdb, ...)");
  cmd->add_option("--source", opts.sources, "Reference for the error report: demo:hamlet, a mesh or scene .vdb files");
  addEnumOption(*cmd, "--source-fill", opts.sourceFill, fillModeNames(), "Mesh source: surface or solid");
  addCommonOptions(*cmd, opts.common);
  return cmd;
}

std::string startMipRun(const MipOptions& o, Run& run) {
  std::string outTemp;
  // A pyramid over its scene keeps the scene whole as its level 0 (its level
  // files with --split do not: those may not replace it).
  if (!o.split) run.mayReplace(o.input);
  if (!o.split) outTemp = run.output(o.output);
  run.phase("read");
  run.input(o.input);
  vox::requireRegularFile(o.input);
  return outTemp;
}

void checkMipInput(const MipOptions& o, int mipLevel, Run& run, const vox::MemoryEstimate* work) {
  if (mipLevel != 0)
    run.note("note: " + o.input + " is already mip level " + std::to_string(mipLevel) +
             "; the pyramid continues from there");
  if (work) {
    vox::MemoryEstimate e;
    e.add("resident after reading", vox::residentBytesNow());
    for (const vox::MemoryPart& p : work->parts) e.parts.push_back(p);
    run.checkMemory(e, "the pyramid of " + o.input);
    return;
  }
  // Levels above 0 hold about a third of level 0 again (surfaces shrink 4x
  // per level), built as trees and written by OpenVDB (measured).
  run.checkWorkMemory("the pyramid of " + o.input, 1.0);
}

void reportMip(const MipOptions& o, const nlohmann::json& perLevel, size_t levelCount, uint64_t baseOccupied, Run& run) {
  run.counts()["levels"] = perLevel;
  run.counts()["level_count"] = levelCount;
  run.counts()["occupancy"] = vox::mipOccupancyName(o.occupancy);
  run.counts()["base_occupied"] = baseOccupied;
  const std::string stem = o.split ? splitStem(o.output) : std::string();
  // Say what the levels are: how many coarser ones, down to which size, and
  // the occupancy rule in words.
  std::string what;
  if (levelCount == 0) {
    // Without --levels the pyramid stops at a level of one occupied voxel.
    what = std::string("no coarser level: the scene has ") + (baseOccupied == 0 ? "no occupied voxel" : "one occupied voxel");
  } else {
    const nlohmann::json& last = perLevel.back()["dims"];
    what = std::to_string(levelCount) + (levelCount == 1 ? " level" : " levels") + " coarser than the input, down to " +
           vox::toString(vox::Dims{last[0].get<uint32_t>(), last[1].get<uint32_t>(), last[2].get<uint32_t>()}) +
           "; a coarse voxel is occupied where " +
           (o.occupancy == vox::MipOccupancy::Majority ? "most of its children are" : "any of its children is");
  }
  run.noteWhenDone("wrote " + (o.split ? std::to_string(levelCount) + " level files " + (levelCount == 0 ? std::string() : splitName(stem, 1) + "...")
                               : o.output) +
           ": " + what);
  if (o.split) {
    // Level files past this pyramid's last, from an earlier run with more
    // levels, would be read as part of it by a glob: say so (they are not
    // this run's to delete).
    std::vector<std::string> stale;
    for (int level = int(levelCount) + 1; level <= 32; ++level) {
      std::error_code ec;
      if (std::filesystem::exists(splitName(stem, level), ec)) stale.push_back(splitName(stem, level));
    }
    if (!stale.empty()) {
      const std::string w = counted(stale.size(), "level file", "level files") + " of an earlier run remain" +
                            (stale.size() == 1 ? "s" : "") + " beside this pyramid of " +
                            counted(levelCount, "level", "levels") + ": " + stale.front() +
                            (stale.size() > 1 ? " .. " + stale.back() : "") + "; remove them before globbing " + stem +
                            ".mip*.vdb";
      run.note("warning: " + w);
      run.counts()["stale_level_files"] = stale;
    }
  }
}

namespace {

/// The report's entry of one level (cmd_mip.cpp's, from the blocks).
nlohmann::json levelJson(const vox::MipBlocksLevel& level, double secs) {
  uint64_t occupied = 0, surface = 0;
  std::array<bool, 256> classes{};
  for (const auto& b : level.blocks) {
    for (int k = 0; k < vox::kBlockWords; ++k) {
      occupied += uint64_t(vox::bitCount(b->occupied[size_t(k)]));
      surface += uint64_t(vox::bitCount(b->occupied[size_t(k)] & b->surface[size_t(k)]));
    }
    for (const auto& cb : b->classes) classes[cb->classId] = true;
  }
  const vox::Dims d = level.header.dims;
  return {{"level", level.header.mipLevel},
          {"dims", {d.x, d.y, d.z}},
          {"voxel_size", level.header.voxelSize},
          {"occupied", occupied},
          {"surface", surface},
          {"classes_present", size_t(std::count(classes.begin(), classes.end(), true))},
          {"seconds", secs}};
}

/// What building the levels of `base` and writing them with the direct
/// writer add to the resident memory (base's blocks are in it): the coarse
/// levels' blocks, counted exactly from base's block origins (a coarse block
/// per distinct origin / 2^n), each at base's average bytes a block; and the
/// writer's leaf lists (every level's at once for a pyramid, the largest
/// level's with --split) with a batch per thread. It was once the bytes of
/// the grids read, which held the writer's buffers grown by doubling before
/// it wrote a batch at a time: 1.3-1.5x the peak after (docs/reliability.md
/// "Memory"). The freed leaves the read left on the heap are not counted
/// against it, so the estimate errs high by about the levels.
vox::MemoryEstimate mipWorkEstimate(const vox::MipBlocksLevel& base, int levels, bool split, unsigned threads) {
  constexpr double kMalloc = vox::kMallocBlockBytes;
  double bytes = 0, classBlocks = 0, colorBlocks = 0, voxels = 0;
  std::vector<uint64_t> keys;
  keys.reserve(base.blocks.size());
  for (const auto& b : base.blocks) {
    bytes += double(sizeof(vox::VoxelBlock) + kMalloc + sizeof(void*));
    for (const auto& cb : b->classes) bytes += double(vox::classBlockHeapBytes(*cb));
    if (b->colors.capacity()) bytes += double(b->colors.capacity() * sizeof(b->colors[0]) + kMalloc);
    classBlocks += double(b->classes.size() + (b->hasRuns() && b->runVotes ? 1 : 0));
    colorBlocks += b->colors.empty() ? 0 : 1;
    for (uint64_t w : b->occupied) voxels += vox::bitCount(w);
    const auto& o = b->origin;
    keys.push_back(uint64_t(uint32_t(o[0]) >> 3) << 42 | uint64_t(uint32_t(o[1]) >> 3) << 21 | uint64_t(uint32_t(o[2]) >> 3));
  }
  const double n0 = std::max<double>(1, double(base.blocks.size()));
  // Coarse block counts: origins / 2 each level (21 bits per axis in the key).
  double coarseBlocks = 0, largestLevel = split ? 0 : n0, allLevels = n0;
  for (int n = 1; n <= levels && keys.size() > 1; ++n) {
    for (uint64_t& k : keys) k = (k >> 43) << 42 | ((k >> 22) & 0xfffff) << 21 | ((k & 0x1fffff) >> 1);
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    coarseBlocks += double(keys.size());
    largestLevel = std::max(largestLevel, double(keys.size()));
    allLevels += double(keys.size());
  }
  const double written = split ? largestLevel : allLevels;
  vox::MemoryEstimate e;
  e.add("pyramid levels", coarseBlocks * bytes / n0);
  e.add("scene writer", vox::directWriteBytes(written, written * classBlocks / n0, written * colorBlocks / n0,
                                              89 + voxels / n0 * (colorBlocks > 0 ? 12 : 4), threads));
  return e;
}

}  // namespace

std::optional<int> runMipFromLeaves(const MipOptions& o) {
  // Usage errors and --source are the full command's.
  if (!o.sources.empty() || o.levels < 0 || o.input.empty() || o.output.empty()) return std::nullopt;
  if (!o.split && !vox::hasExtension(o.output, ".vdb")) return std::nullopt;
  const std::string stem = o.split ? splitStem(o.output) : std::string();
  if (o.split && (stem.empty() || stem.back() == '/')) return std::nullopt;

  // A few hundred MB of fresh heap at most; a file that turns out not to be of
  // the form (rare) is then read by vox-cmds.so with the same tuning.
  tuneAllocatorForShortRun();
  Run run("mip", o.common);
  const std::string outTemp = startMipRun(o, run);
  std::optional<vox::SceneLeaves> leaves = vox::readSceneLeaves(o.input);
  // Pyramids (level 0 and its levels) and level counts beyond the dims: the
  // full command's (the temporary output goes with `run`).
  if (!leaves || leaves->metadata.count(vox::kPyramidKey) || o.levels > vox::maxMipLevels(leaves->header.dims))
    return std::nullopt;
  std::optional<vox::MipBlocksLevel> base = vox::mipBlocksFromLeaves(std::move(*leaves), run.threads());
  if (!base) return std::nullopt;
  {
    const int want = o.levels ? o.levels : vox::maxMipLevels(base->header.dims);
    const vox::MemoryEstimate work = mipWorkEstimate(*base, want, o.split, run.threads());
    checkMipInput(o, base->header.mipLevel, run, &work);
  }

  // Levels as vox::buildMipPyramid builds them (the same automatic stop).
  run.phase("reduce");
  nlohmann::json perLevel = nlohmann::json::array();
  std::vector<vox::MipBlocksLevel> levels;
  const uint64_t baseOccupied = base->occupiedCount();
  if (o.levels != 0 || baseOccupied > 1) {
    const int want = o.levels ? o.levels : vox::maxMipLevels(base->header.dims);
    for (int n = 1; n <= want; ++n) {
      const auto t0 = std::chrono::steady_clock::now();
      levels.push_back(vox::reduceBlocks(levels.empty() ? *base : levels.back(), o.occupancy, run.threads()));
      const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      perLevel.push_back(levelJson(levels.back(), secs));
      if (o.levels == 0 && levels.back().occupiedCount() <= 1) break;
    }
  }

  run.phase("write");
  if (o.split) {
    for (const vox::MipBlocksLevel& level : levels)
      vox::writeMipLevelVdbDirect(level, run.output(splitName(stem, level.header.mipLevel)), run.threads());
  } else {
    std::vector<const vox::MipBlocksLevel*> all{&*base};
    for (const vox::MipBlocksLevel& l : levels) all.push_back(&l);
    vox::writePyramidVdbDirect(all, o.occupancy, outTemp, run.threads());
  }
  reportMip(o, perLevel, levels.size(), baseOccupied, run);
  return run.finish();
}

}  // namespace voxcli
