#include "formats/image/atlas_meta.h"

#include <nlohmann/json.hpp>

#include "formats/core/file_util.h"
#include "formats/core/json_input.h"
#include "formats/core/json_text.h"
#include "libvox/core/error.h"
#include "libvox/core/version.h"

namespace vox {

namespace {

using nlohmann::json;

/// "CONTEXT: malformed "vox:atlas" metadata: WHAT": every fault of an entry.
[[noreturn]] void malformed(const std::string& context, const std::string& what) {
  throwBadInput(context + ": malformed \"" + kAtlasTextKey + "\" metadata: " + what);
}

/// nlohmann's message without its "[json.exception.parse_error.101] " tag.
std::string withoutTag(const std::string& message) {
  if (message.rfind("[json.exception.", 0) == 0)
    if (const size_t end = message.find("] "); end != std::string::npos) return message.substr(end + 2);
  return message;
}

/// An image's info from a `vox:atlas` object (the sidecar's entries are
/// completed with its layout and scene first). Every key is checked here, so
/// that a fault is named in words ("no "content" key"), not by the JSON
/// library's exception text.
AtlasImageInfo infoFromObject(const json& j, const std::string& context) {
  if (!j.is_object()) malformed(context, "not a JSON object");
  auto member = [&](const char* key) -> const json& {
    if (!j.contains(key)) malformed(context, std::string("no \"") + key + "\" key");
    return j[key];
  };
  auto string = [&](const char* key) {
    const json& v = member(key);
    if (!v.is_string()) malformed(context, std::string("\"") + key + "\" must be a string, not " + v.dump());
    return v.get<std::string>();
  };
  AtlasImageInfo info;
  const json& layout = member("layout");
  if (!layout.is_object()) malformed(context, "\"layout\" must be an object, not " + layout.dump());
  info.layout = AtlasLayout::fromJson(layout.dump(), context);
  const std::string contentName = string("content");
  const auto content = parseAtlasContent(contentName);
  if (!content) throwBadInput(context + ": unknown atlas content \"" + contentName + "\"");
  info.content = *content;
  info.format = string("format");
  const json& layer = member("layer");
  if (!layer.is_number_unsigned() || layer.get<uint64_t>() > UINT32_MAX)
    throwBadInput(context + ": \"layer\" must be an integer 0..2^32-1");
  info.layer = layer.get<uint32_t>();
  if (j.contains("class_id")) {
    const json& id = j["class_id"];
    if (!id.is_number_integer() || id.get<int64_t>() < 0 || id.get<int64_t>() > kMaxClassId)
      throwBadInput(context + ": \"class_id\" must be 0..255");
    info.classId = uint8_t(id.get<int64_t>());
  }
  if (j.contains("scene")) info.scene = string("scene");
  if (info.layer >= info.layout.layers)
    throwBadInput(context + ": layer " + std::to_string(info.layer) + " is past the layout's " +
                  std::to_string(info.layout.layers) + (info.layout.layers == 1 ? " layer" : " layers"));
  return info;
}

json parseJson(const std::string& text, const std::string& context) {
  try {
    return parseJsonInput(text, context);
  } catch (const json::exception& e) {  // parse_error, and out_of_range.406 for a number past double's range
    malformed(context, withoutTag(e.what()));
  }
}

}  // namespace

json atlasInfoJson(const AtlasImageInfo& i) {
  json j = {{"layout", json::parse(i.layout.toJson())},
            {"content", atlasContentName(i.content)},
            {"format", i.format},
            {"layer", i.layer},
            {"scene", i.scene}};
  if (i.content == AtlasContent::Votes) j["class_id"] = i.classId;
  if (i.content == AtlasContent::Occupancy) j["bits_per_voxel"] = 1;
  if (i.content == AtlasContent::Occupancy2) j["bits_per_voxel"] = 2;
  return j;
}

std::vector<std::pair<std::string, std::string>> atlasImageText(const AtlasImageInfo& info) {
  return {{kAtlasTextKey, jsonText(atlasInfoJson(info))}, {"Software", versionString()}};
}

AtlasImageInfo atlasInfoFromJson(const std::string& text, const std::string& context) {
  return infoFromObject(parseJson(text, context), context);
}

AtlasImageShape atlasImageShape(const AtlasImageInfo& info, const std::string& context) {
  AtlasImageShape shape{info.layout.width, info.layout.height, 4, SampleType::U8};
  std::vector<std::pair<const char*, SampleType>> formats;  // the formats the content is written in
  switch (info.content) {
    case AtlasContent::Summary:
    case AtlasContent::Color: formats = {{"rgba8", SampleType::U8}}; break;
    case AtlasContent::Identity:
      formats = {{"rgba8", SampleType::U8},
                 {"rgba16", SampleType::U16},
                 {"rgba32ui", SampleType::U32},
                 {"rgba16f", SampleType::F16},
                 {"rgba32f", SampleType::F32}};
      break;
    case AtlasContent::Votes:
      shape.channels = 1;
      formats = {{"r8", SampleType::U8}, {"r16", SampleType::U16}, {"r32ui", SampleType::U32}};
      break;
    case AtlasContent::Occupancy:
    case AtlasContent::Occupancy2: {
      const uint32_t perByte = info.content == AtlasContent::Occupancy ? 8 : 4;
      shape.width = (info.layout.width + perByte - 1) / perByte;
      shape.channels = 1;
      formats = {{"bitmap", SampleType::U8}};
      break;
    }
  }
  std::string names;
  for (const auto& [name, type] : formats) {
    if (info.format == name) {
      shape.type = type;
      return shape;
    }
    names += (names.empty() ? "" : ", ") + std::string(name);
  }
  throwBadInput(context + ": format \"" + info.format + "\" is not one a " + atlasContentName(info.content) +
                " atlas is written in (" + names + ")");
}

std::optional<AtlasImageInfo> atlasInfoOfImage(const Image& img, const std::string& path) {
  const std::string text = img.textValue(kAtlasTextKey);
  if (text.empty()) return std::nullopt;
  AtlasImageInfo info = atlasInfoFromJson(text, path);
  const AtlasImageShape want = atlasImageShape(info, path);
  auto shapeText = [](uint32_t w, uint32_t h, uint32_t c, SampleType t) {
    return std::to_string(w) + " x " + std::to_string(h) + " x " + std::to_string(c) + " " + sampleTypeName(t);
  };
  if (img.width != want.width || img.height != want.height || img.channels != want.channels || img.type != want.type)
    throwBadInput(path + ": the image is " + shapeText(img.width, img.height, img.channels, img.type) + " but its \"" +
                  kAtlasTextKey + "\" entry (" + atlasContentName(info.content) + ", " + info.format + ") says " +
                  shapeText(want.width, want.height, want.channels, want.type) +
                  "; the file was changed after vox wrote it");
  return info;
}

Image readAtlasImage(const std::string& path, AtlasImageInfo& info) {
  requireRegularFile(path);  // "no such file", "is a directory": not "not a PNG or EXR file"
  Image img;
  if (isPngFile(path)) img = readPng(path);
  else if (isExrFile(path)) img = readExr(path);
  else throwBadInput(path + ": not a PNG or EXR file (or unreadable)");
  const std::optional<AtlasImageInfo> found = atlasInfoOfImage(img, path);
  if (!found)
    throwBadInput(path + ": no \"" + kAtlasTextKey + "\" metadata; this image was not written by vox build-atlas");
  info = *found;
  return img;
}

std::string atlasSidecarJson(const std::string& scene, const AtlasLayout& layout,
                             const std::vector<AtlasSidecarEntry>& files) {
  json side = {{"scene", scene}, {"layout", json::parse(layout.toJson())}, {"files", json::array()}};
  for (const AtlasSidecarEntry& f : files) {
    json entry = atlasInfoJson(f.info);
    entry.erase("layout");
    entry.erase("scene");
    entry["file"] = f.file;
    side["files"].push_back(entry);
  }
  return jsonText(side, 2) + "\n";
}

std::vector<AtlasSidecarEntry> atlasSidecarFromJson(const std::string& text, const std::string& context) {
  const json side = parseJson(text, context);
  if (!side.is_object() || !side.contains("layout") || !side.contains("files") || !side["files"].is_array())
    throwBadInput(context + ": an atlas sidecar needs \"layout\" and a \"files\" array");
  std::vector<AtlasSidecarEntry> files;
  for (size_t i = 0; i < side["files"].size(); ++i) {
    const std::string where = context + ": files[" + std::to_string(i) + "]";
    json entry = side["files"][i];
    if (!entry.is_object() || !entry.contains("file") || !entry["file"].is_string())
      throwBadInput(where + " needs a string \"file\"");
    entry["layout"] = side["layout"];
    entry["scene"] = side.contains("scene") ? side["scene"] : json("");
    files.push_back({infoFromObject(entry, where), entry["file"].get<std::string>()});
  }
  return files;
}

}  // namespace vox
