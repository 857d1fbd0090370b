#include "tools/cmds/atlas_files.h"

#include "libvox/core/error.h"

namespace voxcli {

nlohmann::json atlasInfoJson(const AtlasImageInfo& i) {
  nlohmann::json j = {{"layout", nlohmann::json::parse(i.layout.toJson())},
                      {"content", vox::atlasContentName(i.content)},
                      {"format", i.format},
                      {"layer", i.layer},
                      {"scene", i.scene}};
  if (i.content == vox::AtlasContent::Votes) j["class_id"] = i.classId;
  if (i.content == vox::AtlasContent::Occupancy) j["bits_per_voxel"] = 1;
  if (i.content == vox::AtlasContent::Occupancy2) j["bits_per_voxel"] = 2;
  return j;
}

vox::Image readAtlasImage(const std::string& path, AtlasImageInfo& info) {
  vox::Image img;
  if (vox::isPngFile(path)) img = vox::readPng(path);
  else if (vox::isExrFile(path)) img = vox::readExr(path);
  else throw vox::Error(vox::ErrorKind::BadInput, path + ": not a PNG or EXR file (or unreadable)");
  const std::string text = img.textValue(kAtlasTextKey);
  if (text.empty())
    throw vox::Error(vox::ErrorKind::BadInput, path + ": no \"vox:atlas\" metadata; this image was not written by vox build-atlas");
  try {
    const nlohmann::json j = nlohmann::json::parse(text);
    info.layout = vox::AtlasLayout::fromJson(j.at("layout").dump(), path);
    const auto content = vox::parseAtlasContent(j.at("content").get<std::string>());
    if (!content) throw vox::Error(vox::ErrorKind::BadInput, path + ": unknown atlas content '" + j.at("content").dump() + "'");
    info.content = *content;
    info.format = j.at("format").get<std::string>();
    info.layer = j.at("layer").get<uint32_t>();
    info.classId = uint8_t(j.value("class_id", 0));
    info.scene = j.value("scene", "");
  } catch (const nlohmann::json::exception& e) {
    throw vox::Error(vox::ErrorKind::BadInput, path + ": malformed \"vox:atlas\" metadata: " + e.what());
  }
  if (info.layer >= info.layout.layers)
    throw vox::Error(vox::ErrorKind::BadInput, path + ": layer " + std::to_string(info.layer) + " is past the layout's " +
                                                   std::to_string(info.layout.layers) + " layers");
  const bool bitmap = info.content == vox::AtlasContent::Occupancy || info.content == vox::AtlasContent::Occupancy2;
  const uint32_t perByte = info.content == vox::AtlasContent::Occupancy ? 8 : 4;
  const uint32_t wantW = bitmap ? (info.layout.width + perByte - 1) / perByte : info.layout.width;
  if (img.width != wantW || img.height != info.layout.height)
    throw vox::Error(vox::ErrorKind::BadInput, path + ": image is " + std::to_string(img.width) + " x " +
                                                   std::to_string(img.height) + " but its layout says " +
                                                   std::to_string(wantW) + " x " + std::to_string(info.layout.height));
  return img;
}

}  // namespace voxcli
