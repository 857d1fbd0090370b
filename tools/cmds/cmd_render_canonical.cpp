// `vox render-canonical` in vox-cmds.so: every input, scenes read with OpenVDB.
// The light render module (render_main.cpp) runs the inputs it can read
// without OpenVDB first and defers the rest here.
#include <memory>

#include "tools/cli/commands.h"
#include "tools/cmds/render_canonical.h"

namespace voxcli {

Command registerRenderCanonical(CLI::App& root) {
  auto o = std::make_shared<RenderCanonicalOptions>();
  CLI::App* cmd = addRenderCanonicalOptions(root, *o);
  return {cmd, [o] {
            return runRenderCanonical(*o, [](const std::string& path, int level, bool needSummaries) {
              return std::optional<RenderInput>(loadRenderInput(path, level, needSummaries));
            });
          }};
}

}  // namespace voxcli
