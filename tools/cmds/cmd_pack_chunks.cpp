// vox pack-chunks SCENE.vdb -o PAGES.vpk: the scene (and its mips) cut into C^3
// chunks in one page file (formats/pagefile/PAGEFILE.md); --verify FILE.vpk checks one.
#include <CLI/CLI.hpp>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "formats/core/file_kinds.h"
#include "formats/core/file_util.h"
#include "formats/pagefile/layouts.h"
#include "formats/pagefile/pack_chunks.h"
#include "formats/pagefile/page_merge.h"
#include "formats/pagefile/pagefile.h"
#include "formats/pagefile/pagefile_verify.h"
#include "formats/vdb/pyramid_vdb.h"
#include "formats/vdb/scene_vdb.h"
#include "libvox/core/error.h"
#include "libvox/scene/mip.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"
#include "tools/cli/enum_option.h"
#include "tools/cmds/option_names.h"
#include "tools/cmds/pack_chunks_light.h"

namespace voxcli {

namespace {

int runVerify(const PackOptions& o) {
  Run run("pack-chunks", o.common);
  run.input(o.verify);
  run.phase("open");
  vox::pagefile::Reader r = vox::pagefile::Reader::open(o.verify);  // header/index errors: exit 3
  run.phase("verify");
  uint64_t voxels = 0;
  try {
    voxels = vox::pagefile::verifyPageFile(r, run.threads());
  } catch (const vox::Error& e) {
    std::cerr << "vox pack-chunks: verify failed: " << e.what() << "\n";
    run.counts()["verified"] = false;
    return run.finish(kExitCheckFailed);
  }
  run.counts()["verified"] = true;
  run.counts()["chunks"] = r.entries().size();
  run.counts()["voxels"] = voxels;
  run.note(o.verify + ": ok, " + counted(r.entries().size(), "chunk", "chunks") + ", " + counted(voxels, "voxel", "voxels") +
           ", every CRC32C, bound, class and padding byte checked");
  return run.finish();
}

// --mips of a `vox mip` pyramid packs its stored levels, which were built
// with their own occupancy and count: --occupancy and --levels may select
// them, never change them silently. A usage error (nothing written) when they
// ask for levels the file does not hold.
void checkStoredLevels(const PackOptions& o, const vox::PyramidLevels& stored) {
  const std::string pyramid = o.input + " is a vox mip pyramid";
  if (o.levels < 0)
    vox::throwUsage("--levels " + std::to_string(o.levels) + ": expected 1.." + std::to_string(stored.levels) +
                    " (the first levels of the vox mip pyramid " + o.input + "), or 0 for all of them");
  if (o.occupancyOption && o.occupancyOption->count() > 0 && o.occupancy != stored.occupancy)
    vox::throwUsage(std::string("--occupancy ") + vox::mipOccupancyName(o.occupancy) + ": " + pyramid +
                    " whose stored levels have occupancy '" + vox::mipOccupancyName(stored.occupancy) +
                    "', which pack-chunks packs as they are: omit --occupancy, or run vox mip again with --occupancy " +
                    vox::mipOccupancyName(o.occupancy));
  if (o.levels > stored.levels)
    vox::throwUsage("--levels " + std::to_string(o.levels) + ": " + pyramid + " with " +
                    counted(uint64_t(stored.levels), "stored level", "stored levels") +
                    " above level 0: ask for at most " + std::to_string(stored.levels) +
                    " (or omit --levels for all of them), or run vox mip again with --levels " + std::to_string(o.levels));
}

// The levels to pack: the scene, or the pyramid `vox mip` stored (the first
// --levels of them), or the scene and the mips built here. Sets
// `pack.mipOccupancy` to what the metadata records.
std::vector<vox::Scene> readLevels(const PackOptions& o, Run& run, vox::PackSettings& pack) {
  run.phase("read");
  run.input(o.input);
  vox::requireRegularFile(o.input);
  std::vector<vox::Scene> levels;
  if (const std::optional<vox::PyramidLevels> stored = o.mips ? vox::readPyramidLevels(o.input) : std::nullopt) {
    checkStoredLevels(o, *stored);
    pack.mipOccupancy = "from " + o.input;
    levels = vox::readPyramidVdb(o.input);  // the levels `vox mip` stored
    checkPageFileDims(o.input, levels.at(0).header().dims);
    if (o.levels > 0) levels.resize(size_t(o.levels) + 1);
    return levels;
  }
  levels.push_back(vox::readSceneVdb(o.input));
  checkPageFileDims(o.input, levels[0].header().dims);  // before the mips
  if (!o.mips) return levels;
  run.phase("mip");
  vox::MipSettings ms;
  ms.occupancy = o.occupancy;
  ms.levels = o.levels;
  // A region part gets its levels up to the seam level whatever it holds;
  // the merge decides the world's levels and rebuilds the coarser ones.
  ms.levels = vox::mipLevelsToBuild(levels[0].header(), o.levels);
  pack.mipLevelsAsked = uint32_t(o.levels);
  ms.threads = run.threads();
  for (vox::Scene& l : vox::buildMipPyramid(levels[0], ms)) levels.push_back(std::move(l));
  pack.mipOccupancy = vox::mipOccupancyName(o.occupancy);
  return levels;
}

// packChunks, naming the input when the layout cannot hold the scene.
vox::PackResult packLevels(const std::vector<vox::Scene>& levels, const vox::PackSettings& pack,
                           const std::string& input) {
  std::vector<const vox::Scene*> ptrs;
  for (const vox::Scene& l : levels) ptrs.push_back(&l);
  return packNamingInput(input, [&] { return vox::packChunks(ptrs, pack); });
}

void writeBytes(const std::vector<uint8_t>& bytes, const std::string& temp, const std::string& output) {
  vox::writeFileBytes(temp, bytes.data(), bytes.size(), output);
}

// --merge PART.vpk... -o WORLD.vpk: the parts' page files joined into the
// world's (formats/pagefile/page_merge.h).
int runMerge(const PackOptions& o) {
  if (o.output.empty()) vox::throwUsage("--merge PART.vpk... needs -o WORLD.vpk");
  if (!vox::hasExtension(o.output, ".vpk"))
    vox::throwUsage("-o " + o.output + ": a page file is written; name it *.vpk");
  Run run("pack-chunks", o.common);
  const std::string temp = run.output(o.output);
  const auto start = std::chrono::steady_clock::now();
  run.phase("read");
  std::vector<vox::pagefile::Reader> readers;
  readers.reserve(o.merge.size());
  for (const std::string& path : o.merge) {
    run.input(path);
    vox::requireRegularFile(path);
    readers.push_back(vox::pagefile::Reader::open(path));  // header, index, metadata checked
  }
  const double readSecs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::vector<const vox::pagefile::Reader*> ptrs;
  for (const auto& r : readers) ptrs.push_back(&r);
  run.checkWorkMemory("merging " + std::to_string(o.merge.size()) + " parts", 1.0);
  run.phase("merge");  // checks, re-encoding, mips, then the file written in place
  vox::MergeSettings ms;
  ms.threads = run.threads();
  const vox::MergeResult res = vox::mergePageFiles(ptrs, ms, temp);
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  uint64_t voxels = 0, chunks = 0;
  const nlohmann::json lv = levelsJson(res.levels, voxels, chunks);
  const vox::MergeStats& st = res.stats;
  run.counts() = {{"parts", o.merge.size()},
                  {"part_file_bytes", st.partFileBytes},
                  {"align", res.alignment},
                  {"levels", lv},
                  {"chunks", chunks},
                  {"voxels", voxels},
                  {"copied_chunks", st.copiedChunks},
                  {"copied_bytes", st.copiedBytes},
                  {"reencoded_chunks", st.reencodedChunks},
                  {"reencoded_bytes", st.reencodedBytes},
                  {"joined_chunks", st.joinedChunks},
                  {"rebuilt_chunks", st.rebuiltChunks},
                  {"rebuilt_bytes", st.rebuiltBytes},
                  {"seam_voxels", st.seamVoxels},
                  {"file_bytes", res.fileBytes},
                  // copy: every payload written at its offset (copied ones CRC-checked);
                  // write: layout, index, metadata; the final fsync and rename come after
                  {"seconds",
                   {{"read", readSecs},
                    {"check", st.checkSeconds},
                    {"reencode", st.reencodeSeconds},
                    {"mips", st.mipsSeconds},
                    {"write", st.writeSeconds},
                    {"copy", st.copySeconds},
                    {"total", total}}},
                  {"merge_mb_per_s", total > 0 ? double(res.fileBytes) / 1e6 / total : 0.0}};
  run.noteWhenDone("merged " + counted(o.merge.size(), "part", "parts") + " into " + o.output + ": " +
           counted(res.levels.size(), "level", "levels") + ", " + counted(chunks, "chunk", "chunks") + " (" +
           std::to_string(st.copiedChunks) + " copied, " + std::to_string(st.reencodedChunks) + " re-encoded, " +
           std::to_string(st.rebuiltChunks) + " rebuilt from the seam level), " +
           std::to_string(res.fileBytes) + " bytes");
  return run.finish();
}

int runPack(const PackOptions& o) {
  if (!o.merge.empty()) {
    if (!o.input.empty() || !o.verify.empty())
      vox::throwUsage("--merge PART.vpk... takes no scene and no --verify: give the parts' page files after --merge");
    return runMerge(o);
  }
  if (!o.verify.empty()) {
    if (!o.input.empty() || !o.output.empty()) vox::throwUsage("--verify FILE takes no scene and no -o");
    return runVerify(o);
  }
  if (o.input.empty() || o.output.empty()) vox::throwUsage("give a scene and -o PAGES.vpk (or --verify FILE.vpk)");
  if (!vox::hasExtension(o.output, ".vpk"))
    vox::throwUsage("-o " + o.output + ": a page file is written; name it *.vpk (vox info and render-canonical tell "
                    "files apart by that extension)");

  // A scene voxbake wrote: from its leaves, without OpenVDB trees.
  if (const std::optional<int> code = runPackFromLeaves(o)) return *code;
  Run run("pack-chunks", o.common);
  const std::string temp = run.output(o.output);
  vox::PackSettings pack = o.pack;
  pack.threads = run.threads();
  const std::vector<vox::Scene> levels = readLevels(o, run, pack);
  // The page file is assembled in memory before it is written: payloads of
  // a few bytes per voxel, chunk by chunk (measured).
  run.checkWorkMemory("packing " + o.input, 1.0);
  run.phase("pack");
  const auto t0 = std::chrono::steady_clock::now();
  const vox::PackResult res = packLevels(levels, pack, o.input);
  const double packSecs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  run.phase("write");
  writeBytes(res.bytes, temp, o.output);
  reportPack(o, pack, res.levels, res.bytes.size(),
             1u << res.bytes.at(vox::pagefile::header_field::kAlignLog2), packSecs, run);
  return run.finish();
}

}  // namespace

Command registerPackChunks(CLI::App& root) {
  auto opts = std::make_shared<PackOptions>();
  CLI::App* cmd = addPackChunksOptions(root, *opts);
  return {cmd, [opts] { return runPack(*opts); }};
}

}  // namespace voxcli
