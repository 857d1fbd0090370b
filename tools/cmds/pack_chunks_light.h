// `vox pack-chunks`: its options, and the packing of a scene voxbake wrote
// from its leaves, which needs no OpenVDB. Both command modules link this:
// the light pack module (pack_main.cpp) runs that case and defers the rest,
// vox-cmds.so (cmd_pack_chunks.cpp) runs every case.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "formats/pagefile/pack_chunks.h"
#include "libvox/core/error.h"
#include "libvox/scene/mip.h"
#include "tools/cli/cli.h"

namespace voxcli {

/// The command line of `vox pack-chunks`.
struct PackOptions {
  std::string input;
  std::string output;
  std::string verify;
  std::vector<std::string> merge;  // --merge PART.vpk...
  vox::PackSettings pack;  // --chunk, --align, --layout; defaults from the library
  bool mips = false;
  int levels = 0;
  vox::MipOccupancy occupancy = vox::MipSettings{}.occupancy;
  const CLI::Option* occupancyOption = nullptr;  // given: packing a pyramid checks it against the stored levels
  CommonOptions common;
};

/// Adds the pack-chunks subcommand and its options, which fill `opts`.
CLI::App* addPackChunksOptions(CLI::App& root, PackOptions& opts);

/// The whole command (read, pack, write, report) for a plain pack of a scene
/// of the form voxbake writes, read as leaves (formats/vdb/vdb_scene_leaves.h).
/// std::nullopt, having written nothing, for everything else: --merge,
/// --verify, --mips, usage errors, other files and scenes a check refuses
/// (the full command reads those the usual way and says why).
std::optional<int> runPackFromLeaves(const PackOptions& o);

/// The report's per-level counts (a pack's or a merge's levels) and their totals.
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

/// The report's counts and the summary line of a pack; `alignment` is the
/// written file's (what --align auto chose).
void reportPack(const PackOptions& o, const vox::PackSettings& pack, const std::vector<vox::PackResult::Level>& levels,
                uint64_t fileBytes, uint32_t alignment, double packSecs, Run& run);

/// Refuses (BadInput, exit 3) a scene too wide for a page file, naming the
/// input: before the work, so that nothing is packed or written.
inline void checkPageFileDims(const std::string& input, const vox::Dims& dims) {
  if (const std::string problem = vox::pageFileDimsProblem(dims); !problem.empty())
    vox::throwBadInput(input + ": " + problem);
}

/// Runs the packer, naming the input when the layout cannot hold the scene.
template <typename Pack>
auto packNamingInput(const std::string& input, const Pack& pack) {
  try {
    return pack();
  } catch (const vox::Error& e) {
    if (e.kind != vox::ErrorKind::Usage) throw;
    throw vox::Error(e.kind, input + ": " + e.what(), e.setting);
  }
}

}  // namespace voxcli
