#include "formats/pagefile/pagefile_meta.h"

#include <nlohmann/json.hpp>

#include "formats/scene/class_table_json.h"
#include "formats/scene/scene_meta.h"
#include "libvox/core/error.h"

namespace vox::pagefile {

using nlohmann::json;

std::string writePageMeta(const PageMeta& meta) {
  json levels = json::array();
  for (const LevelMeta& l : meta.levels)
    levels.push_back({{"level", l.level},
                      {"dims", {l.dims[0], l.dims[1], l.dims[2]}},
                      {"voxel_size", l.voxelSize},
                      {"chunks", l.chunks},
                      {"voxels", l.voxels}});
  // The class table, sources and block world are written as in a scene file.
  json j = {{"format", kMetaFormat},
            {"tool_version", meta.toolVersion},
            {"classes", json::parse(classTableJson(meta.classes))},
            {"levels", std::move(levels)},
            {"sources", json::parse(sourcesJson(meta.sources))}};
  if (!meta.mipOccupancy.empty()) j["mip_occupancy"] = meta.mipOccupancy;
  if (meta.blockWorld) j["block_world"] = json::parse(blockWorldJson(*meta.blockWorld));
  if (meta.region) j["region"] = json::parse(regionJson(*meta.region));
  return j.dump();
}

namespace {

// Parsing with the file's name in every message.
struct MetaParser {
  const std::string& file;

  [[noreturn]] void fail(const std::string& what) const { throwBadInput(file + ": metadata " + what); }

  std::vector<LevelMeta> levels(const json& arr) const {
    if (!arr.is_array()) fail("'levels' must be an array");
    std::vector<LevelMeta> out;
    for (const json& l : arr)
      out.push_back({l.at("level").get<uint32_t>(), l.at("dims").get<std::array<uint32_t, 3>>(),
                     l.at("voxel_size").get<double>(), l.at("chunks").get<uint64_t>(), l.at("voxels").get<uint64_t>()});
    return out;
  }
};

}  // namespace

PageMeta readPageMeta(const std::string& text, const std::string& fileName) {
  const MetaParser parse{fileName};
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {
    parse.fail(std::string("is not valid JSON: ") + e.what());
  }
  if (!j.is_object()) parse.fail("must be a JSON object");
  PageMeta meta;
  try {
    if (j.contains("format") && j["format"] != kMetaFormat)
      parse.fail("'format': " + j["format"].dump() + ", expected \"" + kMetaFormat + "\"");
    meta.toolVersion = j.value("tool_version", std::string());
    // The class table, sources and block world are read as in a scene file.
    const std::string where = fileName + ": metadata";
    if (j.contains("classes")) meta.classes = classTableFromJson(j["classes"], ClassJsonForm::Stored, where + " 'classes'");
    if (j.contains("sources")) meta.sources = sourcesFromJson(j["sources"], where + " 'sources'");
    if (j.contains("levels")) meta.levels = parse.levels(j["levels"]);
    meta.mipOccupancy = j.value("mip_occupancy", std::string());
    if (j.contains("block_world")) meta.blockWorld = blockWorldFromJson(j["block_world"], where + " 'block_world'");
    if (j.contains("region")) {
      // The region's box is checked against level 0's dims.
      if (meta.levels.empty()) parse.fail("'region' needs 'levels' (the dims of level 0)");
      const auto& d = meta.levels.front().dims;
      meta.region = regionFromJson(j["region"], Dims{d[0], d[1], d[2]}, where + " 'region'");
    }
  } catch (const json::exception& e) {
    parse.fail(std::string("is malformed: ") + e.what());
  }
  return meta;
}

}  // namespace vox::pagefile
