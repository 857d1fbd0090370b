// Tool and format versions. Bump a format version whenever a reader of the
// previous version would misread the new files.
#pragma once

namespace vox {

inline constexpr const char* kToolVersion = "0.1.0";
/// Scene .vdb layout (formats/scene/SCENE.md): grid names, types and metadata keys.
inline constexpr int kSceneFormatVersion = 1;

}  // namespace vox

#include <string>

namespace vox {
/// "vox 0.1.0 (scene format 1)": what `vox --version` prints.
inline std::string versionString() {
  return std::string("vox ") + kToolVersion + " (scene format " + std::to_string(kSceneFormatVersion) + ")";
}
}  // namespace vox
