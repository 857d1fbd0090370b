// The JSON texts a scene file carries in its metadata (formats/scene/SCENE.md):
// shared by the OpenVDB writer (scene_vdb.cpp) and the direct writer
// (scene_vdb_direct.cpp), so both write the same bytes.
#pragma once

#include <string>
#include <vector>

#include "libvox/core/scene_header.h"

namespace vox {

/// `vox:classes`: the class table as a JSON array sorted by id.
std::string classTableJson(const ClassTable& table);
/// `vox:sources`: [{"path", "kind", "sha256", "bytes"}].
std::string sourcesJson(const std::vector<SceneSource>& sources);
/// `vox:block_world`: {"worldScale", "gridSize"}.
std::string blockWorldJson(const BlockWorldPlacement& placement);

}  // namespace vox
