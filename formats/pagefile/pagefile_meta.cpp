#include "formats/pagefile/pagefile_meta.h"

#include <bit>

#include <nlohmann/json.hpp>

#include "formats/core/json_input.h"
#include "formats/core/json_text.h"
#include "formats/pagefile/pagefile.h"
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
  if (meta.regionAlign) {
    if (*meta.regionAlign) j["region_align"] = *meta.regionAlign;
    else j["region_align"] = "auto";
  }
  if (meta.regionMips) {
    // One array per voxel: u, v, w, surface (0/1), [class, votes, ...], then
    // r, g, b (linear floats; each float prints exactly) when it has colour.
    json voxels = json::array();
    for (const SeamVoxel& v : meta.regionMips->voxels) {
      json votes = json::array();
      for (const ClassVotes& c : v.votes) votes.push_back(c.classId), votes.push_back(c.votes);
      json a = {v.at[0], v.at[1], v.at[2], v.surface ? 1 : 0, std::move(votes)};
      if (v.color)
        for (float f : *v.color) a.push_back(f);
      voxels.push_back(std::move(a));
    }
    j["region_mips"] = {{"levels_asked", meta.regionMips->levelsAsked},
                        {"seam_level", meta.regionMips->seamLevel},
                        {"voxels", std::move(voxels)}};
  }
  return jsonText(j);
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

  // Shapes and ranges only; whether the voxels fit the world is the merge's check.
  RegionMips regionMips(const json& o) const {
    if (!o.is_object()) fail("'region_mips' must be an object");
    RegionMips r;
    r.levelsAsked = o.at("levels_asked").get<uint32_t>();
    r.seamLevel = o.at("seam_level").get<uint32_t>();
    const json& arr = o.at("voxels");
    if (!arr.is_array()) fail("'region_mips.voxels' must be an array");
    r.voxels.reserve(arr.size());
    for (size_t i = 0; i < arr.size(); ++i) {
      const json& a = arr[i];
      auto bad = [&](const std::string& what) { fail("'region_mips.voxels[" + std::to_string(i) + "]': " + what); };
      if (!a.is_array() || (a.size() != 5 && a.size() != 8)) bad("expected [u, v, w, surface, votes] or with r, g, b");
      SeamVoxel v;
      for (int k = 0; k < 3; ++k) v.at[size_t(k)] = a[size_t(k)].get<uint32_t>();
      v.surface = a[3].get<int>() != 0;
      const json& votes = a[4];
      if (!votes.is_array() || votes.empty() || votes.size() % 2) bad("votes must be [class, count, ...]");
      for (size_t q = 0; q < votes.size(); q += 2) {
        const uint32_t id = votes[q].get<uint32_t>(), n = votes[q + 1].get<uint32_t>();
        if (id < 1 || id > 255 || n < 1 || n > kMaxVotesPerClass) bad("a class id 1..255 with 1..2^31-1 votes");
        v.votes.push_back({uint8_t(id), n});
      }
      if (a.size() == 8) v.color = std::array<float, 3>{a[5].get<float>(), a[6].get<float>(), a[7].get<float>()};
      r.voxels.push_back(std::move(v));
    }
    return r;
  }
};

}  // namespace

PageMeta readPageMeta(const std::string& text, const std::string& fileName) {
  const MetaParser parse{fileName};
  json j;
  try {
    j = parseJsonInput(text, fileName + ": metadata");
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
    if (j.contains("region_mips")) meta.regionMips = parse.regionMips(j["region_mips"]);
    if (j.contains("region_align")) {
      const json& a = j["region_align"];
      if (a.is_string() && a.get<std::string>() == "auto") meta.regionAlign = 0;
      else if (a.is_number_unsigned() && a.get<uint64_t>() >= (1u << kMinAlignLog2) &&
               a.get<uint64_t>() <= (1u << kMaxAlignLog2) && std::has_single_bit(a.get<uint64_t>()))
        meta.regionAlign = a.get<uint32_t>();
      else parse.fail("'region_align': " + a.dump() + ", expected \"auto\" or a power of two from 8 to 65536");
    }
  } catch (const json::exception& e) {
    parse.fail(std::string("is malformed: ") + e.what());
  }
  return meta;
}

}  // namespace vox::pagefile
