// `vox diff A B` (docs/diff.md): the options every kind of comparison shares
// and one function per kind of file. Each compares, prints its report (text
// or --json) on stdout and returns the exit code: 0 same (or within the
// tolerances), 1 differs. Usage errors (2) and unreadable inputs (3) are
// thrown as vox::Error.
#pragma once

#include <array>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "libvox/core/types.h"

namespace voxcli {

struct DiffOptions {
  std::string a, b;
  bool json = false;
  bool ignoreSources = false;
  unsigned threads = 0;
  // Scenes, pyramids, page files.
  std::optional<uint32_t> level;  // pyramids: compare this level only (a plain scene is taken as it is)
  uint32_t votesTolerance = 0;
  double colorTolerance = 0;
  // Images (idiff's thresholds; unset = idiff's defaults, see docs/diff.md).
  std::optional<double> fail, warn;
  double failPercent = 0, warnPercent = 0;
  double hardFail = std::numeric_limits<double>::infinity();
  double hardWarn = std::numeric_limits<double>::infinity();
  std::string diffImage;  // --diff-image OUT.png
  double diffScale = 1.0;
  std::string background;  // --background R,G,B
  std::optional<int> view;  // render against metadata.json
  // JSON.
  double relTolerance = 0;
  std::vector<std::string> ignoreKeys;
  bool noDefaultIgnores = false;
};

class Run;

int diffSceneFiles(const DiffOptions& o);
int diffPageFiles(const DiffOptions& o);
int diffImageFiles(const DiffOptions& o, Run& run);
int diffRenderReference(const DiffOptions& o, Run& run);
int diffJsonFiles(const DiffOptions& o);

/// A JSON pointer for people: "" (the whole document) is "the top level".
inline std::string pointerText(const std::string& pointer) { return pointer.empty() ? "the top level" : pointer; }

/// "(u, v, w)" as a JSON array.
inline nlohmann::json coordJson(const vox::Coord3& c) { return {c.u, c.v, c.w}; }

}  // namespace voxcli
