#include "formats/pagefile/pagefile_meta.h"

#include <nlohmann/json.hpp>

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
  return j.dump();
}

namespace {

// Parsing with the file's name in every message.
struct MetaParser {
  const std::string& file;

  [[noreturn]] void fail(const std::string& what) const { throwBadInput(file + ": metadata " + what); }

  Rgb8 rgb(const json& j, const std::string& where) const {
    if (!j.is_array() || j.size() != 3) fail(where + " must be [r, g, b]");
    uint8_t c[3];
    for (size_t i = 0; i < 3; ++i) {
      if (!j[i].is_number_integer() || j[i].get<int64_t>() < 0 || j[i].get<int64_t>() > 255)
        fail(where + " must hold integers 0..255");
      c[i] = uint8_t(j[i].get<int64_t>());
    }
    return {c[0], c[1], c[2]};
  }

  ClassTable classes(const json& arr) const {
    ClassTable t;
    if (!arr.is_array()) fail("'classes' must be an array");
    for (size_t i = 0; i < arr.size(); ++i) {
      const std::string where = "'classes' entry " + std::to_string(i);
      const json& c = arr[i];
      if (!c.is_object() || !c.contains("id") || !c["id"].is_number_integer() || !c.contains("name") ||
          !c["name"].is_string() || !c.contains("color"))
        fail(where + " needs id, name and color");
      const int64_t id = c["id"].get<int64_t>();
      if (id < 1 || id > kMaxClassId) fail(where + ": id must be 1.." + std::to_string(kMaxClassId));
      ClassInfo info;
      info.id = uint8_t(id);
      info.name = c["name"].get<std::string>();
      info.color = rgb(c["color"], where + ".color");
      const int faces = int(c.contains("top")) + int(c.contains("bottom")) + int(c.contains("side"));
      if (faces != 0 && faces != 3) fail(where + " needs all of top, bottom and side or none");
      if (faces == 3)
        info.faces = FacePalette{rgb(c["top"], where + ".top"), rgb(c["bottom"], where + ".bottom"),
                                 rgb(c["side"], where + ".side")};
      t.add(std::move(info), file + ": metadata 'classes'");
    }
    return t;
  }

  std::vector<SceneSource> sources(const json& arr) const {
    if (!arr.is_array()) fail("'sources' must be an array");
    std::vector<SceneSource> out;
    for (const json& s : arr)
      out.push_back({s.at("path").get<std::string>(), s.at("kind").get<std::string>(), s.at("sha256").get<std::string>(),
                     s.at("bytes").get<uint64_t>()});
    return out;
  }

  std::vector<LevelMeta> levels(const json& arr) const {
    if (!arr.is_array()) fail("'levels' must be an array");
    std::vector<LevelMeta> out;
    for (const json& l : arr)
      out.push_back({l.at("level").get<uint32_t>(), l.at("dims").get<std::array<uint32_t, 3>>(),
                     l.at("voxel_size").get<double>(), l.at("chunks").get<uint64_t>(), l.at("voxels").get<uint64_t>()});
    return out;
  }

  BlockWorldPlacement blockWorld(const json& j) const {
    BlockWorldPlacement p;
    p.worldScale = j.at("worldScale").get<double>();
    p.gridSize = j.at("gridSize").get<std::array<uint32_t, 3>>();
    return p;
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
    if (j.contains("classes")) meta.classes = parse.classes(j["classes"]);
    if (j.contains("sources")) meta.sources = parse.sources(j["sources"]);
    if (j.contains("levels")) meta.levels = parse.levels(j["levels"]);
    meta.mipOccupancy = j.value("mip_occupancy", std::string());
    if (j.contains("block_world")) meta.blockWorld = parse.blockWorld(j["block_world"]);
  } catch (const json::exception& e) {
    parse.fail(std::string("is malformed: ") + e.what());
  }
  return meta;
}

}  // namespace vox::pagefile
