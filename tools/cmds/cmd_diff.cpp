// vox diff A B: compares two artefacts semantically (for scenes: header and
// every voxel, ignoring OpenVDB's random file UUID). Exit 0 when they are the
// same, 1 when they differ (like idiff), 3 when an input cannot be read.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>

#include "formats/vdb/scene_vdb.h"
#include "libvox/core/error.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"

namespace voxcli {

namespace {

struct DiffOptions {
  std::string a, b;
  bool json = false;
  bool ignoreSources = false;
};

int runDiff(const DiffOptions& o) {
  for (const std::string* p : {&o.a, &o.b})
    if (!vox::looksLikeVdb(*p) && std::filesystem::exists(*p))
      throw vox::Error(vox::ErrorKind::BadInput, *p + ": vox diff compares scenes (.vdb) in this version");
  const vox::Scene a = vox::readSceneVdb(o.a);
  const vox::Scene b = vox::readSceneVdb(o.b);
  const vox::SceneDifference d = vox::compareScenes(a, b, o.ignoreSources);
  if (o.json) {
    nlohmann::json j = {{"a", o.a},
                        {"b", o.b},
                        {"same", d.same()},
                        {"header_differs", d.headerDiffers},
                        {"header_note", d.headerNote},
                        {"voxels_compared", d.voxelsCompared},
                        {"voxels_differing", d.voxelsDiffering}};
    if (d.firstDifference)
      j["first_difference"] = {{"voxel", {d.firstDifference->u, d.firstDifference->v, d.firstDifference->w}},
                               {"values", d.firstNote}};
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << (d.same() ? "same" : "DIFFERENT") << ": " << d.voxelsCompared << " voxels compared, "
              << d.voxelsDiffering << " differ";
    if (d.headerDiffers) std::cout << "; header: " << d.headerNote;
    std::cout << "\n";
    if (d.firstDifference)
      std::cout << "  first difference at voxel " << vox::toString(*d.firstDifference) << " (smallest w, v, u): "
                << d.firstNote << "\n";
  }
  return d.same() ? kExitOk : kExitCheckFailed;
}

}  // namespace

Command registerDiff(CLI::App& root) {
  auto opts = std::make_shared<DiffOptions>();
  CLI::App* cmd = root.add_subcommand("diff", "Compare two scenes voxel for voxel (exit 1 if they differ)");
  cmd->add_option("a", opts->a, "First file")->required();
  cmd->add_option("b", opts->b, "Second file")->required();
  cmd->add_flag("--json", opts->json, "Print the comparison as JSON on stdout");
  cmd->add_flag("--ignore-sources", opts->ignoreSources, "Do not compare the recorded source files");
  return {cmd, [opts] { return runDiff(*opts); }};
}

}  // namespace voxcli
