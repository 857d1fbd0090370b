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
#include "formats/vdb/pyramid_vdb.h"
#include "formats/vdb/scene_vdb.h"
#include "formats/vdb/vdb_scene_leaves.h"
#include "libvox/core/error.h"
#include "libvox/scene/mip.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"
#include "tools/cli/enum_option.h"
#include "tools/cmds/option_names.h"

namespace voxcli {

namespace {

struct PackOptions {
  std::string input;
  std::string output;
  std::string verify;
  std::vector<std::string> merge;  // --merge PART.vpk...
  vox::PackSettings pack;  // --chunk, --align, --layout; defaults from the library
  bool mips = false;
  int levels = 0;
  vox::MipOccupancy occupancy = vox::MipSettings{}.occupancy;
  CommonOptions common;
};

// --layout's names, from the layout table.
EnumNames<vox::pagefile::Layout> layoutNames() {
  EnumNames<vox::pagefile::Layout> out;
  for (const vox::pagefile::LayoutCodec& l : vox::pagefile::layoutTable()) out.push_back({l.name, l.id});
  return out;
}

// The help's list of layouts, from the layout table: name, then its summary
// wrapped under it.
std::string layoutHelp() {
  std::string out;
  const vox::pagefile::Layout byDefault = vox::PackSettings{}.layout;
  for (const vox::pagefile::LayoutCodec& l : vox::pagefile::layoutTable()) {
    std::string line = "  " + std::string(l.name);
    line.resize(11, ' ');
    std::string text = std::string(l.summary) + (l.id == byDefault ? " (default)" : "");
    size_t at = 0;
    while (at < text.size()) {
      size_t take = text.size() - at;
      if (take > 86) {  // break at the last space that fits
        const size_t space = text.rfind(' ', at + 86);
        take = space != std::string::npos && space > at ? space - at : 86;
      }
      out += line + text.substr(at, take) + "\n";
      at += take + 1;
      line = std::string(11, ' ');
    }
  }
  return out;
}

int runVerify(const PackOptions& o) {
  Run run("pack-chunks", o.common);
  run.input(o.verify);
  run.phase("open");
  vox::pagefile::Reader r = vox::pagefile::Reader::open(o.verify);  // header/index errors: exit 3
  run.phase("verify");
  uint64_t voxels = 0;
  try {
    voxels = r.verify();
  } catch (const vox::Error& e) {
    std::cerr << "vox pack-chunks: verify failed: " << e.what() << "\n";
    run.counts()["verified"] = false;
    return run.finish(kExitCheckFailed);
  }
  run.counts()["verified"] = true;
  run.counts()["chunks"] = r.entries().size();
  run.counts()["voxels"] = voxels;
  run.note(o.verify + ": ok, " + std::to_string(r.entries().size()) + " chunks, " + std::to_string(voxels) +
           " voxels, every CRC32C and bound checked");
  return run.finish();
}

// The levels to pack: the scene, or the pyramid `vox mip` stored, or the scene
// and the mips built here. Sets `pack.mipOccupancy` to what the metadata records.
std::vector<vox::Scene> readLevels(const PackOptions& o, Run& run, vox::PackSettings& pack) {
  run.phase("read");
  run.input(o.input);
  vox::requireRegularFile(o.input);
  std::vector<vox::Scene> levels;
  if (o.mips && vox::isPyramidVdb(o.input) && o.levels == 0) {
    pack.mipOccupancy = "from " + o.input;
    return vox::readPyramidVdb(o.input);  // the levels `vox mip` stored
  }
  levels.push_back(vox::readSceneVdb(o.input));
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
  try {
    return vox::packChunks(ptrs, pack);
  } catch (const vox::Error& e) {
    if (e.kind != vox::ErrorKind::Usage) throw;
    throw vox::Error(e.kind, input + ": " + e.what(), e.setting);
  }
}

// packChunks of a scene read as leaves, naming the input as packLevels does.
vox::PackResult packLeaves(const vox::SceneLeaves& leaves, const vox::PackSettings& pack, const std::string& input) {
  try {
    return vox::packChunks(leaves, pack);
  } catch (const vox::Error& e) {
    if (e.kind != vox::ErrorKind::Usage) throw;
    throw vox::Error(e.kind, input + ": " + e.what(), e.setting);
  }
}

void writeBytes(const std::vector<uint8_t>& bytes, const std::string& temp, const std::string& output) {
  vox::writeFileBytes(temp, bytes.data(), bytes.size(), output);
}

// The report's per-level counts (a pack's or a merge's levels) and their totals.
template <typename Levels>
nlohmann::json levelsJson(const Levels& levels, uint64_t& voxels, uint64_t& chunks) {
  nlohmann::json lv = nlohmann::json::array();
  for (const auto& l : levels) {
    voxels += l.voxels;
    chunks += l.chunks;
    lv.push_back({{"level", l.level}, {"chunks", l.chunks}, {"full_chunks", l.fullChunks}, {"voxels", l.voxels},
                  {"payload_bytes", l.payloadBytes}});
  }
  return lv;
}

// The report's counts and the summary line.
void reportPack(const PackOptions& o, const vox::PackSettings& pack, const vox::PackResult& res, double packSecs,
                Run& run) {
  uint64_t voxels = 0, chunks = 0;
  const nlohmann::json lv = levelsJson(res.levels, voxels, chunks);
  const double bytesPerVoxel = voxels ? double(res.bytes.size()) / double(voxels) : 0.0;
  run.counts() = {{"layout", vox::pagefile::layoutName(pack.layout)},
                  {"chunk", pack.chunkSide},
                  {"align", pack.alignment},
                  {"levels", lv},
                  {"chunks", chunks},
                  {"voxels", voxels},
                  {"file_bytes", res.bytes.size()},
                  {"scene_file_bytes", vox::fileSizeOrMinusOne(o.input)},
                  {"bytes_per_voxel", bytesPerVoxel},
                  {"pack_seconds", packSecs},
                  {"pack_mb_per_s", packSecs > 0 ? double(res.bytes.size()) / 1e6 / packSecs : 0.0}};
  char bpv[32];
  std::snprintf(bpv, sizeof bpv, "%.2f", bytesPerVoxel);
  run.note("wrote " + o.output + ": " + std::to_string(res.levels.size()) + " level(s), " + std::to_string(chunks) +
           " chunks of " + std::to_string(pack.chunkSide) + "^3, " + std::to_string(voxels) + " voxels, " +
           std::to_string(res.bytes.size()) + " bytes (" + bpv + " per voxel)");
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
  run.note("merged " + std::to_string(o.merge.size()) + " parts into " + o.output + ": " +
           std::to_string(res.levels.size()) + " level(s), " + std::to_string(chunks) + " chunks (" +
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
  if (!o.mips && o.levels) vox::throwUsage("--levels needs --mips");
  if (!vox::hasExtension(o.output, ".vpk"))
    vox::throwUsage("-o " + o.output + ": a page file is written; name it *.vpk (vox info and render-canonical tell "
                    "files apart by that extension)");

  Run run("pack-chunks", o.common);
  const std::string temp = run.output(o.output);
  vox::PackSettings pack = o.pack;
  pack.threads = run.threads();
  // A scene of the form voxbake writes is packed from its leaves, without
  // OpenVDB trees (formats/vdb/vdb_scene_leaves.h); others, and mips, from the scene.
  std::optional<vox::SceneLeaves> leaves;
  if (!o.mips) {
    run.phase("read");
    run.input(o.input);
    vox::requireRegularFile(o.input);
    leaves = vox::readSceneLeaves(o.input);
  }
  std::vector<vox::Scene> levels;
  if (!leaves) levels = readLevels(o, run, pack);
  // The page file is assembled in memory before it is written: payloads of
  // a few bytes per voxel, chunk by chunk (measured).
  run.checkWorkMemory("packing " + o.input, 1.0);
  run.phase("pack");
  const auto t0 = std::chrono::steady_clock::now();
  const vox::PackResult res = leaves ? packLeaves(*leaves, pack, o.input) : packLevels(levels, pack, o.input);
  const double packSecs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  run.phase("write");
  writeBytes(res.bytes, temp, o.output);
  reportPack(o, pack, res, packSecs, run);
  return run.finish();
}

}  // namespace

Command registerPackChunks(CLI::App& root) {
  auto opts = std::make_shared<PackOptions>();
  CLI::App* cmd = root.add_subcommand("pack-chunks", "Cut a scene (and its mips) into C^3 chunks in one page file (.vpk)");
  cmd->footer(
      "Page file format: formats/pagefile/PAGEFILE.md (little-endian header with CRC32C, index sorted by\n"
      "(level, Morton key), payloads at aligned offsets, no empty chunks). Layouts of a payload:\n" +
      layoutHelp() +
      "--mips: add levels 1..n (stored ones when the input is a `vox mip` pyramid, else built\n"
      "with --occupancy/--levels). --verify FILE.vpk: every CRC, bound and bitmap; exit 1 if bad.\n"
      "--merge PART.vpk... -o WORLD.vpk: the parts of a region bake (packed with the same settings)\n"
      "joined into exactly the file the single-process bake gives (PAGEFILE.md, \"Merging\").\n"
      "Example: vox pack-chunks hamlet.vdb -o hamlet.vpk --mips && vox info hamlet.vpk");
  cmd->add_option("input", opts->input, "Scene or pyramid (.vdb)");
  cmd->add_option("-o,--output", opts->output, "Page file to write (.vpk)");
  cmd->add_option("--verify", opts->verify, "Check a page file instead of writing one");
  CLI::Option* merge = cmd->add_option("--merge", opts->merge,
                                       "Join the page files of a region bake's parts (PART.vpk...) into the world's");
  cmd->add_option("--chunk", opts->pack.chunkSide, "Chunk side C: 8, 16 or 32")->capture_default_str();
  cmd->add_option("--align", opts->pack.alignment, "Payload alignment in bytes (power of two, 8..65536)")
      ->capture_default_str();
  addEnumOption(*cmd, "--layout", opts->pack.layout, layoutNames(), "Payload layout (below)");
  cmd->add_flag("--mips", opts->mips, "Also pack the mip levels");
  cmd->add_option("--levels", opts->levels, "With --mips: levels to build (default: automatic)");
  addEnumOption(*cmd, "--occupancy", opts->occupancy, mipOccupancyNames(), "With --mips: how a coarser voxel is occupied");
  addCommonOptions(*cmd, opts->common);
  // The parts carry their settings: a merge takes none of the packing options.
  for (const char* name : {"--chunk", "--align", "--layout", "--mips", "--levels", "--occupancy"})
    merge->excludes(cmd->get_option(name));
  return {cmd, [opts] { return runPack(*opts); }};
}

}  // namespace voxcli
