#include "formats/scene/scene_meta.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "formats/core/json_input.h"
#include "formats/core/json_text.h"
#include "formats/scene/class_table_json.h"
#include "libvox/core/error.h"
#include "libvox/core/version.h"

namespace vox {

namespace {

using nlohmann::json;

constexpr const char* kFormatName = "voxbake-scene";
constexpr const char* kVotesPrefix = "votes.";

[[noreturn]] void bad(const std::string& path, const std::string& what) { throwBadInput(path + ": " + what); }

/// The value of `key` as a T, or nullopt when the key is absent; throws when
/// it has another type.
template <typename T>
std::optional<T> optionalMeta(const MetaEntries& meta, const std::string& path, const std::string& key) {
  const auto it = meta.find(key);
  if (it == meta.end()) return std::nullopt;
  if (const T* v = std::get_if<T>(&it->second)) return *v;
  bad(path, "metadata key '" + key + "' has type " + metaTypeName(it->second) + ", expected " +
                metaTypeName(MetaValue(T{})));
}

template <typename T>
T requiredMeta(const MetaEntries& meta, const std::string& path, const std::string& key) {
  if (auto v = optionalMeta<T>(meta, path, key)) return *v;
  bad(path, "metadata key '" + key + "' is missing; this file is not a voxbake scene (write one with `vox voxelize`)");
}

json parseJsonMeta(const std::string& text, const std::string& path, const std::string& key) {
  try {
    return parseJsonInput(text, path + ": metadata '" + key + "'");
  } catch (const json::exception& e) {
    bad(path, "metadata '" + key + "' is not valid JSON: " + e.what());
  }
}

}  // namespace

std::string metaTypeName(const MetaValue& value) {
  struct Name {
    std::string operator()(const std::string&) const { return "string"; }
    std::string operator()(int32_t) const { return "int32"; }
    std::string operator()(double) const { return "double"; }
    std::string operator()(const std::array<int32_t, 3>&) const { return "vec3i"; }
    std::string operator()(const std::array<double, 3>&) const { return "vec3d"; }
    std::string operator()(const ForeignMetaValue& f) const { return f.typeName; }
  };
  return std::visit(Name{}, value);
}

std::string classTableJson(const ClassTable& table) { return jsonText(classTableToJson(table)); }

std::string sourcesJson(const std::vector<SceneSource>& sources) {
  json arr = json::array();
  for (const SceneSource& s : sources)
    arr.push_back({{"path", s.path}, {"kind", s.kind}, {"sha256", s.sha256}, {"bytes", s.bytes}});
  return jsonText(arr);
}

std::string blockWorldJson(const BlockWorldPlacement& p) {
  const json bw = {{"worldScale", p.worldScale}, {"gridSize", {p.gridSize[0], p.gridSize[1], p.gridSize[2]}}};
  return jsonText(bw);
}

std::vector<SceneSource> sourcesFromJson(const json& arr, const std::string& where) {
  if (!arr.is_array()) throwBadInput(where + " must be a JSON array");
  std::vector<SceneSource> sources;
  for (size_t i = 0; i < arr.size(); ++i) {
    const std::string entry = where + "[" + std::to_string(i) + "]";
    const json& s = arr[i];
    if (!s.is_object()) throwBadInput(entry + " must be an object with \"path\", \"kind\", \"sha256\" and \"bytes\"");
    SceneSource source;
    for (auto [key, field] : {std::pair{"path", &source.path}, std::pair{"kind", &source.kind},
                              std::pair{"sha256", &source.sha256}}) {
      if (!s.contains(key) || !s[key].is_string()) throwBadInput(entry + " needs a string \"" + key + "\"");
      *field = s[key].get<std::string>();
    }
    if (!s.contains("bytes") || !s["bytes"].is_number_unsigned())
      throwBadInput(entry + " needs a non-negative integer \"bytes\"");
    source.bytes = s["bytes"].get<uint64_t>();
    sources.push_back(std::move(source));
  }
  return sources;
}

BlockWorldPlacement blockWorldFromJson(const json& bw, const std::string& where) {
  if (!bw.is_object() || !bw.contains("worldScale") || !bw["worldScale"].is_number())
    throwBadInput(where + " needs a number \"worldScale\"");
  const json& grid = bw.contains("gridSize") ? bw["gridSize"] : json();
  if (!grid.is_array() || grid.size() != 3) throwBadInput(where + " needs \"gridSize\": [X, Y, Z]");
  BlockWorldPlacement p;
  p.worldScale = bw["worldScale"].get<double>();
  for (size_t i = 0; i < 3; ++i) {
    if (!grid[i].is_number_unsigned() || grid[i].get<uint64_t>() > UINT32_MAX)
      throwBadInput(where + " \"gridSize\" must hold three integers 0..2^32-1");
    p.gridSize[i] = grid[i].get<uint32_t>();
  }
  return p;
}

std::string regionJson(const SceneRegion& r) {
  json box = nullptr;
  if (!r.box.empty()) box = {r.box.min.u, r.box.min.v, r.box.min.w, r.box.max.u, r.box.max.v, r.box.max.w};
  const json j = {{"index", r.index}, {"count", r.count}, {"box", box}, {"world_key", r.worldKey}};
  return jsonText(j);
}

SceneRegion regionFromJson(const json& j, const Dims& dims, const std::string& where) {
  if (!j.is_object()) throwBadInput(where + " must be an object with \"index\", \"count\", \"box\", \"world_key\"");
  auto count = [&](const char* key) {
    if (!j.contains(key) || !j[key].is_number_unsigned() || j[key].get<uint64_t>() > UINT32_MAX)
      throwBadInput(where + " needs an integer \"" + key + "\" in 0..2^32-1");
    return j[key].get<uint32_t>();
  };
  SceneRegion r;
  r.index = count("index");
  r.count = count("count");
  if (r.count == 0 || r.index >= r.count) throwBadInput(where + ": \"index\" must be below \"count\"");
  if (!j.contains("world_key") || !j["world_key"].is_string() || j["world_key"].get<std::string>().empty())
    throwBadInput(where + " needs a non-empty string \"world_key\"");
  r.worldKey = j["world_key"].get<std::string>();
  const json& box = j.contains("box") ? j["box"] : json();
  if (box.is_null()) return r;
  if (!box.is_array() || box.size() != 6) throwBadInput(where + " \"box\" must be null or [umin,vmin,wmin,umax,vmax,wmax]");
  int64_t v[6];
  for (size_t i = 0; i < 6; ++i) {
    if (!box[i].is_number_integer()) throwBadInput(where + " \"box\" must hold six integers");
    v[i] = box[i].get<int64_t>();
  }
  const uint32_t n[3] = {dims.x, dims.y, dims.z};
  for (int a = 0; a < 3; ++a)
    if (v[a] < 0 || v[a] > v[a + 3] || v[a + 3] >= int64_t(n[a]))
      throwBadInput(where + " \"box\" must lie inside the dims " + toString(dims) + " with each min <= its max");
  r.box.min = {int32_t(v[0]), int32_t(v[1]), int32_t(v[2])};
  r.box.max = {int32_t(v[3]), int32_t(v[4]), int32_t(v[5])};
  return r;
}

std::string voteGridName(uint8_t classId) { return kVotesPrefix + std::to_string(classId); }

bool looksLikeVoteGridName(const std::string& name) { return name.rfind(kVotesPrefix, 0) == 0; }

std::optional<uint8_t> classIdOfVoteGridName(const std::string& name) {
  if (!looksLikeVoteGridName(name)) return std::nullopt;
  const std::string digits = name.substr(std::string(kVotesPrefix).size());
  if (digits.empty() || digits.size() > 3 || digits[0] == '0') return std::nullopt;
  int id = 0;
  for (char c : digits) {
    if (c < '0' || c > '9') return std::nullopt;
    id = id * 10 + (c - '0');
  }
  if (id < 1 || id > kMaxClassId) return std::nullopt;
  return uint8_t(id);
}

MetaEntries sceneFileMetadata(const SceneHeader& h) {
  MetaEntries meta;
  meta["vox:format"] = std::string(kFormatName);
  meta["vox:format_version"] = int32_t(kSceneFormatVersion);
  meta["vox:tool_version"] = std::string(kToolVersion);
  meta["vox:dims"] = std::array<int32_t, 3>{int32_t(h.dims.x), int32_t(h.dims.y), int32_t(h.dims.z)};
  meta["vox:voxel_size"] = h.voxelSize;
  meta["vox:origin"] = h.origin;
  meta["vox:mip_level"] = int32_t(h.mipLevel);
  meta["vox:classes"] = classTableJson(h.classes);
  meta["vox:sources"] = sourcesJson(h.sources);
  if (h.blockWorld) meta["vox:block_world"] = blockWorldJson(*h.blockWorld);
  if (h.region) meta["vox:region"] = regionJson(*h.region);
  return meta;
}

MetaEntries voteGridMetadata(const ClassTable& classes, uint8_t classId) {
  const ClassInfo* info = classes.find(classId);
  return {{"vox:class_id", int32_t(classId)}, {"vox:class_name", info ? info->name : std::string()}};
}

MetaEntries colorGridMetadata() { return {{"vox:color_space", std::string("linear")}}; }

MetaEntries pyramidLevelGridMetadata(int mipLevel) { return {{"vox:mip_level", int32_t(mipLevel)}}; }

std::string pyramidGridPrefix(size_t level) { return level == 0 ? "" : "mip" + std::to_string(level) + "."; }

bool hasPyramidLevelPrefix(const std::string& gridName) {
  if (gridName.rfind("mip", 0) != 0) return false;
  size_t i = 3;
  while (i < gridName.size() && gridName[i] >= '0' && gridName[i] <= '9') ++i;
  return i > 3 && i < gridName.size() && gridName[i] == '.';
}

std::string pyramidMetadata(const std::string& occupancy, const std::vector<PyramidLevelEntry>& levels) {
  nlohmann::json table = nlohmann::json::array();
  for (const PyramidLevelEntry& l : levels)
    table.push_back({{"level", l.level},
                     {"dims", {l.dims.x, l.dims.y, l.dims.z}},
                     {"voxel_size", l.voxelSize},
                     {"occupied", l.occupied}});
  return nlohmann::json{{"occupancy", occupancy}, {"levels", table}}.dump();
}

SceneHeader sceneHeaderFromMetadata(const MetaEntries& meta, const std::string& path) {
  SceneHeader h;
  const std::string format = requiredMeta<std::string>(meta, path, "vox:format");
  if (format != kFormatName) bad(path, "metadata 'vox:format' is '" + format + "', expected '" + kFormatName + "'");
  const int version = requiredMeta<int32_t>(meta, path, "vox:format_version");
  if (version < 1 || version > kSceneFormatVersion)
    bad(path, "scene format version " + std::to_string(version) + " is not supported (this vox reads 1.." +
                  std::to_string(kSceneFormatVersion) + "); upgrade vox");
  const auto dims = requiredMeta<std::array<int32_t, 3>>(meta, path, "vox:dims");
  if (dims[0] < 1 || dims[1] < 1 || dims[2] < 1) bad(path, "metadata 'vox:dims' must be >= 1 on every axis");
  h.dims = {uint32_t(dims[0]), uint32_t(dims[1]), uint32_t(dims[2])};
  h.voxelSize = requiredMeta<double>(meta, path, "vox:voxel_size");
  if (!(h.voxelSize > 0) || !std::isfinite(h.voxelSize)) bad(path, "metadata 'vox:voxel_size' must be finite and > 0");
  h.origin = requiredMeta<std::array<double, 3>>(meta, path, "vox:origin");
  if (const std::string problem = placementProblem(h.voxelSize, h.origin, h.dims); !problem.empty())
    bad(path, "metadata 'vox:voxel_size' and 'vox:origin': " + problem);
  h.mipLevel = requiredMeta<int32_t>(meta, path, "vox:mip_level");
  h.classes = classTableFromJson(parseJsonMeta(requiredMeta<std::string>(meta, path, "vox:classes"), path, "vox:classes"),
                                 ClassJsonForm::Stored, path + ": metadata 'vox:classes'");
  if (auto text = optionalMeta<std::string>(meta, path, "vox:sources"))
    h.sources = sourcesFromJson(parseJsonMeta(*text, path, "vox:sources"), path + ": metadata 'vox:sources'");
  if (auto text = optionalMeta<std::string>(meta, path, "vox:block_world"))
    h.blockWorld =
        blockWorldFromJson(parseJsonMeta(*text, path, "vox:block_world"), path + ": metadata 'vox:block_world'");
  if (auto text = optionalMeta<std::string>(meta, path, "vox:region"))
    h.region = regionFromJson(parseJsonMeta(*text, path, "vox:region"), h.dims, path + ": metadata 'vox:region'");
  return h;
}

}  // namespace vox
