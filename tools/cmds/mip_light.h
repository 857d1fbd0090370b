// `vox mip`: its options, and the pyramid of a scene voxbake wrote built from
// its leaves, which needs no OpenVDB. Both command modules link this: the
// light module vox-pack.so (pack_main.cpp) runs that case and defers the
// rest, vox-cmds.so (cmd_mip.cpp) runs every case.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "libvox/mesh/voxelize.h"
#include "libvox/scene/mip_blocks.h"
#include "tools/cli/cli.h"

namespace voxcli {

/// The command line of `vox mip`.
struct MipOptions {
  std::string input;
  std::string output;
  int levels = 0;  // 0: automatic (vox::MipSettings::levels)
  vox::MipOccupancy occupancy = vox::MipOccupancy::Any;
  bool split = false;
  std::vector<std::string> sources;
  vox::FillMode sourceFill = vox::FillMode::Surface;
  CommonOptions common;
};

/// Adds the mip subcommand and its options, which fill `opts`.
CLI::App* addMipOptions(CLI::App& root, MipOptions& opts);

/// --split: "-o OUT" or "-o OUT.vdb" both name the stem OUT.
std::string splitStem(const std::string& output);
/// STEM -> STEM.mipN.vdb
std::string splitName(const std::string& stem, int level);

/// The start both modules' runs share: the pyramid's temporary output (none
/// with --split), phase "read", the input recorded and checked to be a file.
/// Returns the temporary path.
std::string startMipRun(const MipOptions& o, Run& run);
/// The note when the input already is mip level `mipLevel` (> 0), then the
/// memory check before the levels are built: resident memory plus `work`
/// (the levels and the writer), or without it, of a scene read as OpenVDB
/// trees and written by OpenVDB, once the bytes of the grids read.
void checkMipInput(const MipOptions& o, int mipLevel, Run& run, const vox::MemoryEstimate* work = nullptr);
/// The report's counts and the summary line, once the levels are written.
void reportMip(const MipOptions& o, const nlohmann::json& perLevel, size_t levelCount, uint64_t baseOccupied, Run& run);

/// The whole command (read, reduce, write, report) for a pyramid or --split
/// levels of a scene of the form voxbake writes, read as leaves
/// (formats/vdb/pyramid_direct.h). std::nullopt, having written nothing, for
/// everything else: --source, usage errors, pyramid inputs, more --levels
/// than the dims allow, other files and scenes a check refuses (the full
/// command reads those the usual way and says why).
std::optional<int> runMipFromLeaves(const MipOptions& o);

}  // namespace voxcli
