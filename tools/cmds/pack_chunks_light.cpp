#include "tools/cmds/pack_chunks_light.h"

#include <chrono>
#include <cstdio>

#include "formats/core/file_kinds.h"
#include "formats/core/file_util.h"
#include "formats/pagefile/layouts.h"
#include "formats/vdb/vdb_scene_leaves.h"
#include "libvox/core/error.h"
#include "tools/cli/alloc_tuning.h"
#include "tools/cli/enum_option.h"
#include "tools/cmds/option_names.h"

namespace voxcli {

namespace {

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

}  // namespace

void reportPack(const PackOptions& o, const vox::PackSettings& pack, const std::vector<vox::PackResult::Level>& levels,
                uint64_t fileBytes, uint32_t alignment, double packSecs, Run& run) {
  uint64_t voxels = 0, chunks = 0;
  const nlohmann::json lv = levelsJson(levels, voxels, chunks);
  const double bytesPerVoxel = voxels ? double(fileBytes) / double(voxels) : 0.0;
  run.counts() = {{"layout", vox::pagefile::layoutName(pack.layout)},
                  {"chunk", pack.chunkSide},
                  {"align", alignment},
                  {"levels", lv},
                  {"chunks", chunks},
                  {"voxels", voxels},
                  {"file_bytes", fileBytes},
                  {"scene_file_bytes", vox::fileSizeOrMinusOne(o.input)},
                  {"bytes_per_voxel", bytesPerVoxel},
                  {"pack_seconds", packSecs},
                  {"pack_mb_per_s", packSecs > 0 ? double(fileBytes) / 1e6 / packSecs : 0.0}};
  char bpv[32];
  std::snprintf(bpv, sizeof bpv, "%.2f", bytesPerVoxel);
  run.noteWhenDone("wrote " + o.output + ": " + counted(levels.size(), "level", "levels") + ", " + counted(chunks, "chunk", "chunks") +
           " of " + std::to_string(pack.chunkSide) + "^3, " + counted(voxels, "voxel", "voxels") + ", " +
           std::to_string(fileBytes) + " bytes (" + bpv + " per voxel)");
}

CLI::App* addPackChunksOptions(CLI::App& root, PackOptions& opts) {
  CLI::App* cmd = root.add_subcommand("pack-chunks", "Cut a scene (and its mips) into C^3 chunks in one page file (.vpk)");
  cmd->footer(
      "Page file format: formats/pagefile/PAGEFILE.md (little-endian header with CRC32C, index sorted by\n"
      "(level, Morton key), payloads at aligned offsets, no empty chunks). Layouts of a payload:\n" +
      layoutHelp() +
      "--mips: add levels 1..n, built with --occupancy/--levels; of a `vox mip` pyramid, its stored\n"
      "levels (--levels N: the first N; --occupancy must be the pyramid's, else a usage error).\n"
      "--verify FILE.vpk: every CRC, bound, bitmap, class, padding byte and the metadata; exit 1 if bad.\n"
      "--merge PART.vpk... -o WORLD.vpk: the parts of a region bake (packed with the same settings)\n"
      "joined into exactly the file the single-process bake gives (PAGEFILE.md, \"Merging\").\n"
      "Example: vox pack-chunks hamlet.vdb -o hamlet.vpk --mips && vox info hamlet.vpk");
  cmd->add_option("input", opts.input, "Scene or pyramid (.vdb)");
  cmd->add_option("-o,--output", opts.output, "Page file to write (.vpk)");
  CLI::Option* verify = cmd->add_option("--verify", opts.verify, "Check a page file instead of writing one");
  CLI::Option* merge = cmd->add_option("--merge", opts.merge,
                                       "Join the page files of a region bake's parts (PART.vpk...) into the world's");
  // Checked on the text: CLI11 would say "Could not convert" of -8, without the choices.
  cmd->add_option("--chunk", opts.pack.chunkSide, "Chunk side C: 8, 16 or 32")
      ->check(CLI::Validator(
          [](std::string& v) { return v == "8" || v == "16" || v == "32" ? std::string() : v + ": expected 8, 16 or 32"; },
          "", ""))
      ->type_name("8|16|32")
      ->capture_default_str();
  cmd->add_option_function<std::string>(
         "--align",
         [&opts](const std::string& v) {
           if (v == "auto") {
             opts.pack.alignment = 0;
             return;
           }
           // The packer checks the range and names the setting; here only the form.
           size_t used = 0;
           unsigned long bytes = 0;
           try {
             bytes = std::stoul(v, &used);
           } catch (const std::exception&) {
             used = 0;
           }
           if (used != v.size() || bytes == 0 || bytes > 0xFFFFFFFFul)
             throw CLI::ValidationError("--align", v + ": expected auto or a power of two from 8 to 65536");
           opts.pack.alignment = uint32_t(bytes);
         },
         "Payload alignment: auto (4 KiB when that pads the payloads by at most 1/8 more than 64 bytes would, "
         "else 64 bytes) or bytes, a power of two 8..65536")
      ->default_str("auto");
  addEnumOption(*cmd, "--layout", opts.pack.layout, layoutNames(), "Payload layout (below)");
  CLI::Option* mips = cmd->add_flag("--mips", opts.mips, "Also pack the mip levels");
  cmd->add_option("--levels", opts.levels,
                  "With --mips: levels to build (default: automatic); of a pyramid, the stored levels to pack (default: all)")
      ->needs(mips);
  opts.occupancyOption = addEnumOption(*cmd, "--occupancy", opts.occupancy, mipOccupancyNames(),
                                       "With --mips: how a coarser voxel is occupied")
                             ->needs(mips);
  addCommonOptions(*cmd, opts.common);
  // The parts carry their settings: a merge takes none of the packing options;
  // --verify reads a file whose settings are in it.
  for (const char* name : {"--chunk", "--align", "--layout", "--mips", "--levels", "--occupancy"}) {
    merge->excludes(cmd->get_option(name));
    verify->excludes(cmd->get_option(name));
  }
  return cmd;
}

std::optional<int> runPackFromLeaves(const PackOptions& o) {
  if (!o.merge.empty() || !o.verify.empty() || o.mips || o.levels || o.input.empty() || o.output.empty() ||
      !vox::hasExtension(o.output, ".vpk"))
    return std::nullopt;
  // A few hundred MB of fresh heap at most; a file that turns out not to be of
  // the form (rare) is then read by vox-cmds.so with the same tuning.
  tuneAllocatorForShortRun();
  Run run("pack-chunks", o.common);
  const std::string temp = run.output(o.output);
  vox::PackSettings pack = o.pack;
  pack.threads = run.threads();
  run.phase("read");
  run.input(o.input);
  vox::requireRegularFile(o.input);
  const std::optional<vox::SceneLeaves> leaves = vox::readSceneLeaves(o.input);
  if (!leaves) return std::nullopt;  // the temporary output goes with `run`
  checkPageFileDims(o.input, leaves->header.dims);
  // The page file is assembled in memory before it is written: payloads of
  // a few bytes per voxel, chunk by chunk (measured).
  run.checkWorkMemory("packing " + o.input, 1.0);
  run.phase("pack");
  const auto t0 = std::chrono::steady_clock::now();
  const vox::PlannedPack res = packNamingInput(o.input, [&] { return vox::packChunks(*leaves, pack); });
  const double packSecs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  run.phase("write");
  vox::pagefile::writePlannedFile(temp, res.plan, res.chunks, o.output);
  reportPack(o, pack, res.levels, res.plan.header.fileBytes, 1u << res.plan.header.alignLog2, packSecs, run);
  return run.finish();
}

}  // namespace voxcli
