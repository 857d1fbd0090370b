#include "formats/vdb/pyramid_vdb.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "formats/core/json_input.h"
#include "formats/vdb/scene_vdb.h"
#include "formats/vdb/vdb_checked_file.h"
#include "formats/vdb/vdb_scene_grids.h"
#include "formats/vdb/vdb_structure.h"
#include "libvox/core/error.h"
#include "libvox/scene/scene_grids.h"

namespace vox {

namespace {

using nlohmann::json;

[[noreturn]] void bad(const std::string& path, const std::string& what) { throwBadInput(path + ": " + what); }

/// The level a grid named "mip<n>.<name>" belongs to (0 for other names);
/// throws when n is not one of the `levels` levels.
size_t levelOfGridName(const std::string& path, const std::string& name, size_t levels) {
  if (name.rfind("mip", 0) != 0) return 0;
  const size_t dot = name.find('.');
  const std::string num = name.substr(3, dot == std::string::npos ? std::string::npos : dot - 3);
  int n = -1;
  try {
    n = std::stoi(num);
  } catch (...) {
  }
  if (dot == std::string::npos || n < 1 || size_t(n) > levels || num != std::to_string(n))
    bad(path, "grid '" + name + "' is not mip<level>.<grid> with a level of '" + kPyramidKey + "' (1.." +
                  std::to_string(levels) + ")");
  return size_t(n);
}

/// The number of levels above 0 that `vox:pyramid` lists.
size_t pyramidLevelCount(const std::string& path, const std::string& text, Dims baseDims) {
  json pyramid;
  try {
    pyramid = parseJsonInput(text, path + ": metadata '" + kPyramidKey + "'");
  } catch (const json::exception& e) {
    bad(path, std::string("metadata '") + kPyramidKey + "' is not valid JSON: " + e.what());
  }
  if (!pyramid.is_object() || !pyramid.contains("levels") || !pyramid["levels"].is_array())
    bad(path, std::string("metadata '") + kPyramidKey + "' needs a 'levels' array");
  const size_t levels = pyramid["levels"].size();
  const int maxLevel = maxMipLevels(baseDims);
  if (levels > size_t(maxLevel))
    bad(path, std::string("metadata '") + kPyramidKey + "' lists " + std::to_string(levels) + " levels; a " +
                  toString(baseDims) + " grid has at most " + std::to_string(maxLevel));
  return levels;
}

}  // namespace

void writePyramidVdb(const std::vector<const Scene*>& levels, MipOccupancy occupancy, const std::string& path) {
  ensureOpenVdbInitialized();
  if (levels.empty()) throw Error(ErrorKind::Internal, "writePyramidVdb: no levels");
  openvdb::GridPtrVec grids;
  std::vector<PyramidLevelEntry> levelTable;
  for (size_t n = 0; n < levels.size(); ++n) {
    const Scene& scene = *levels[n];
    const SceneHeader& h = scene.header();
    if (h.mipLevel != int(n) + levels[0]->header().mipLevel)
      throw Error(ErrorKind::Internal, "writePyramidVdb: level " + std::to_string(n) + " has mipLevel " +
                                           std::to_string(h.mipLevel));
    appendSceneGrids(scene, pyramidGridPrefix(n), n > 0 ? pyramidLevelGridMetadata(h.mipLevel) : MetaEntries{}, grids);
    if (n > 0) levelTable.push_back({h.mipLevel, h.dims, h.voxelSize, scene.occupiedCount()});
  }
  MetaEntries fileMeta = sceneFileMetadata(levels[0]->header());
  fileMeta[kPyramidKey] = pyramidMetadata(mipOccupancyName(occupancy), levelTable);
  openvdb::MetaMap meta;
  insertVdbMetadata(meta, fileMeta);
  writeVdbFile(path, grids, meta, "pyramid");
}

bool isPyramidVdb(const std::string& path) {
  if (!looksLikeVdb(path)) return false;
  return isPyramidFrame(checkVdbStructure(path, VdbCheck::Framing));
}

bool isPyramidFrame(const VdbFrame& frame) {
  return std::find(frame.metadataNames.begin(), frame.metadataNames.end(), kPyramidKey) != frame.metadataNames.end();
}

std::string readPyramidMetadata(const std::string& path) {
  if (!isPyramidVdb(path)) return {};
  CheckedVdbFile file(path, VdbCheck::Framing);  // the file metadata only
  const openvdb::MetaMap::Ptr meta = file.metadata();
  auto m = openvdb::DynamicPtrCast<const openvdb::StringMetadata>((*meta)[kPyramidKey]);
  if (!m) bad(path, std::string("metadata '") + kPyramidKey + "' must be a string");
  return m->value();
}

std::optional<PyramidLevels> readPyramidLevels(const std::string& path) {
  const std::string text = readPyramidMetadata(path);
  if (text.empty()) return std::nullopt;
  const std::string key = std::string("metadata '") + kPyramidKey + "'";
  json pyramid;
  try {
    pyramid = parseJsonInput(text, path + ": metadata '" + kPyramidKey + "'");
  } catch (const json::exception& e) {
    bad(path, key + " is not valid JSON: " + e.what());
  }
  if (!pyramid.is_object() || !pyramid.contains("levels") || !pyramid["levels"].is_array())
    bad(path, key + " needs a 'levels' array");
  PyramidLevels out;
  out.levels = int(pyramid["levels"].size());
  const json occupancy = pyramid.value("occupancy", json());
  if (occupancy == mipOccupancyName(MipOccupancy::Majority)) out.occupancy = MipOccupancy::Majority;
  else if (occupancy != mipOccupancyName(MipOccupancy::Any))
    bad(path, key + " 'occupancy': " + occupancy.dump() + ", expected \"any\" or \"majority\"");
  return out;
}

std::vector<Scene> readPyramidVdb(const std::string& path) {
  VdbSceneFile file = readVdbSceneFile(path, /*occupancyOnly=*/false);
  const SceneHeader& base = file.header;
  std::vector<Scene> levels;
  levels.emplace_back();
  levels[0].header() = base;
  levels[0].grids() = levelGridsFromVdb(file.grids, "", base, path, /*checkTopology=*/true);

  const auto entry = file.metadata.find(kPyramidKey);
  if (entry == file.metadata.end()) return levels;  // a plain scene
  const std::string* text = std::get_if<std::string>(&entry->second);
  if (!text) bad(path, std::string("metadata '") + kPyramidKey + "' must be a string");
  const size_t levelCount = pyramidLevelCount(path, *text, base.dims);
  for (const openvdb::GridBase::Ptr& g : file.grids) levelOfGridName(path, g->getName(), levelCount);
  for (size_t n = 1; n <= levelCount; ++n) {
    Scene scene;
    SceneHeader& h = scene.header();
    h = base;
    h.mipLevel = base.mipLevel + int(n);
    h.dims = mipDims(base.dims, int(n));
    h.voxelSize = base.voxelSize * double(uint64_t(1) << n);
    scene.grids() = levelGridsFromVdb(file.grids, pyramidGridPrefix(n), h, path + ": level " + std::to_string(n),
                                      /*checkTopology=*/true);
    levels.push_back(std::move(scene));
  }
  return levels;
}

}  // namespace vox
