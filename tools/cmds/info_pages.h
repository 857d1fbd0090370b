// `vox info` for the files of `vox mip` and `vox pack-chunks`: page files
// (.vpk) and pyramid .vdb files (tools/cmds/cmd_info.cpp calls these).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace voxcli {

/// Describes a page file on stdout (text or --json). Returns the exit code.
int infoPageFile(const std::string& path, bool json);

/// The levels of a pyramid .vdb (null JSON for a plain scene).
nlohmann::json pyramidInfoJson(const std::string& path);

/// The text lines for pyramidInfoJson's result.
std::string pyramidInfoText(const nlohmann::json& pyramid);

}  // namespace voxcli
