// Tool and format versions. Bump a format version whenever a reader of the
// previous version would misread the new files.
#pragma once

namespace vox {

inline constexpr const char* kToolVersion = "0.1.0";
/// Scene .vdb layout (formats/scene/SCENE.md): grid names, types and metadata keys.
inline constexpr int kSceneFormatVersion = 1;
/// Page file layout (formats/pagefile/PAGEFILE.md): the header's version field.
inline constexpr int kPageFileFormatVersion = 1;

}  // namespace vox

#include <string>

namespace vox {
/// "vox 0.1.0 (scene format 1)": the tool's version as outputs record it (the
/// PNG "Software" entry, glTF generator). Changing it changes output bytes.
inline std::string versionString() {
  return std::string("vox ") + kToolVersion + " (scene format " + std::to_string(kSceneFormatVersion) + ")";
}

/// What `vox --version` prints: versionString(), then every file format the
/// tool writes with its version.
inline std::string versionReport() {
  return versionString() + "\nformats: scene .vdb " + std::to_string(kSceneFormatVersion) +
         " (OpenVDB file format 224), page file .vpk " + std::to_string(kPageFileFormatVersion) +
         ", atlas and render metadata in PNG/EXR text entries (vox:atlas, vox:canonical), touched sets voxbake-touched";
}
}  // namespace vox
