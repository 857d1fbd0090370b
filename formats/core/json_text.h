// The text of every JSON document vox writes (reports, scene, image and page
// file metadata, glTF, camera files, `info --json`): nlohmann::json's dump,
// except that a string that is not UTF-8 (a name or path that came from a
// file or a command line as Windows-1252 or Latin-1 bytes) is written
// transcoded (libvox/core/utf8.h) instead of ending the run with an internal
// error. Documents of valid text are dumped as they are, byte for byte.
// Thread-safety: pure functions.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace vox {

/// j.dump(indent), every string and object key made valid UTF-8 first when
/// one is not.
std::string jsonText(const nlohmann::json& j, int indent = -1);

}  // namespace vox
