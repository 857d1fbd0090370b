#include "formats/image/atlas_meta.h"

#include <nlohmann/json.hpp>

#include "formats/core/json_text.h"
#include "libvox/core/error.h"
#include "libvox/core/version.h"

namespace vox {

namespace {

using nlohmann::json;

bool isBitmap(AtlasContent c) { return c == AtlasContent::Occupancy || c == AtlasContent::Occupancy2; }

/// An image's info from a `vox:atlas` object (the sidecar's entries are
/// completed with its layout and scene first).
AtlasImageInfo infoFromObject(const json& j, const std::string& context) {
  AtlasImageInfo info;
  try {
    info.layout = AtlasLayout::fromJson(j.at("layout").dump(), context);
    const auto content = parseAtlasContent(j.at("content").get<std::string>());
    if (!content) throwBadInput(context + ": unknown atlas content " + j.at("content").dump());
    info.content = *content;
    info.format = j.at("format").get<std::string>();
    const json& layer = j.at("layer");
    if (!layer.is_number_unsigned() || layer.get<uint64_t>() > UINT32_MAX)
      throwBadInput(context + ": \"layer\" must be an integer 0..2^32-1");
    info.layer = layer.get<uint32_t>();
    const int64_t classId = j.value("class_id", int64_t(0));
    if (classId < 0 || classId > kMaxClassId) throwBadInput(context + ": \"class_id\" must be 0..255");
    info.classId = uint8_t(classId);
    info.scene = j.value("scene", "");
  } catch (const json::exception& e) {
    throwBadInput(context + ": malformed \"" + kAtlasTextKey + "\" metadata: " + e.what());
  }
  if (info.layer >= info.layout.layers)
    throwBadInput(context + ": layer " + std::to_string(info.layer) + " is past the layout's " +
                  std::to_string(info.layout.layers) + " layers");
  return info;
}

json parseJson(const std::string& text, const std::string& context) {
  try {
    return json::parse(text);
  } catch (const json::exception& e) {
    throwBadInput(context + ": malformed \"" + kAtlasTextKey + "\" metadata: " + e.what());
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

Image readAtlasImage(const std::string& path, AtlasImageInfo& info) {
  Image img;
  if (isPngFile(path)) img = readPng(path);
  else if (isExrFile(path)) img = readExr(path);
  else throwBadInput(path + ": not a PNG or EXR file (or unreadable)");
  const std::string text = img.textValue(kAtlasTextKey);
  if (text.empty())
    throwBadInput(path + ": no \"" + kAtlasTextKey + "\" metadata; this image was not written by vox build-atlas");
  info = atlasInfoFromJson(text, path);
  const uint32_t perByte = info.content == AtlasContent::Occupancy ? 8 : 4;
  const uint32_t wantW = isBitmap(info.content) ? (info.layout.width + perByte - 1) / perByte : info.layout.width;
  if (img.width != wantW || img.height != info.layout.height)
    throwBadInput(path + ": image is " + std::to_string(img.width) + " x " + std::to_string(img.height) +
                  " but its layout says " + std::to_string(wantW) + " x " + std::to_string(info.layout.height));
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
