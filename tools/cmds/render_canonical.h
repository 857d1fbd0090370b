// `vox render-canonical`: its options and the whole command, given the loader
// of its input. Both command modules link this: vox-cmds.so runs it with
// loadRenderInput (OpenVDB), the light render module (render_main.cpp) with
// loadRenderInputLight and defers what that cannot read.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "formats/pagefile/pack_chunks.h"
#include "libvox/render/render.h"
#include "libvox/render/render_modes.h"
#include "tools/cli/camera_options.h"
#include "tools/cli/cli.h"
#include "tools/cmds/render_input.h"

namespace voxcli {

/// The caster --check compares the render with.
enum class CheckReference { Walk, BruteForce };

/// The command line of `vox render-canonical`.
struct RenderCanonicalOptions {
  std::string input, output;
  std::vector<std::string> modeLists;  // each --mode as given (comma lists); none: canonical. See renderModes().
  CameraOptions camera;
  std::string touched, touchedBitmap;
  uint32_t chunk = vox::PackSettings{}.chunkSide;  // the page files' default, so the chunks are theirs
  vox::ShadeColor shadeColor = vox::ShadeColor::Class;
  std::string cameraOut;
  bool check = false;
  CheckReference checkReference = CheckReference::Walk;
  double checkSeconds = 10;  // 0: every pixel
  double checkBudget = vox::kDefaultCheckBudget;
  int level = 0;
  int compression = 4;  // measured on a 1080p RGBA16 render: 2.7x faster than 6 for 25 % more bytes
  CommonOptions common;
  const CLI::App* app = nullptr;  // to tell an option given from its default
};

/// The modes --mode names, in the order given, each once (canonical when
/// --mode is not given). Throws vox::Error (Usage) on an empty entry
/// (tools/cli/comma_list.h) or a name that is not a mode.
std::vector<vox::RenderMode> renderModes(const RenderCanonicalOptions& o);

/// Adds the render-canonical subcommand and its options, which fill `opts`.
CLI::App* addRenderCanonicalOptions(CLI::App& root, RenderCanonicalOptions& opts);

/// Reads the input (path, --level, whether summaries are needed);
/// std::nullopt: this module cannot read it.
using RenderLoader = std::function<std::optional<RenderInput>(const std::string& path, int level, bool needSummaries)>;

/// The whole command. kDeferToFullModule (tools/cli/commands.h), having
/// written nothing, when `load` gives std::nullopt; usage errors found before
/// the input is read are thrown as usual.
int runRenderCanonical(const RenderCanonicalOptions& o, const RenderLoader& load);

}  // namespace voxcli
