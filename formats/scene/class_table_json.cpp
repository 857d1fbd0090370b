#include "formats/scene/class_table_json.h"

#include <algorithm>
#include <cctype>
#include <nlohmann/json.hpp>

#include "libvox/core/error.h"

namespace vox {

namespace {

using nlohmann::json;

constexpr Rgb8 kHandWrittenDefaultColor{128, 128, 128};
constexpr const char* kFaceKeys[3] = {"top", "bottom", "side"};

json rgbJson(Rgb8 c) { return json::array({c.r, c.g, c.b}); }

std::optional<Rgb8> rgbFromArray(const json& j) {
  if (!j.is_array() || j.size() != 3) return std::nullopt;
  Rgb8 c;
  uint8_t* out[3] = {&c.r, &c.g, &c.b};
  for (size_t i = 0; i < 3; ++i) {
    if (!j[i].is_number_integer() || j[i].get<int64_t>() < 0 || j[i].get<int64_t>() > 255) return std::nullopt;
    *out[i] = uint8_t(j[i].get<int64_t>());
  }
  return c;
}

std::optional<Rgb8> rgbFromHex(const json& j) {
  if (!j.is_string()) return std::nullopt;
  const std::string s = j.get<std::string>();
  if (s.size() != 7 || s[0] != '#' || !std::all_of(s.begin() + 1, s.end(), [](char c) { return std::isxdigit(uint8_t(c)); }))
    return std::nullopt;
  auto byte = [&](size_t at) { return uint8_t(std::stoul(s.substr(at, 2), nullptr, 16)); };
  return Rgb8{byte(1), byte(3), byte(5)};
}

Rgb8 colorFromJson(const json& j, ClassJsonForm form, const std::string& where) {
  if (auto c = rgbFromArray(j)) return *c;
  if (form == ClassJsonForm::HandWritten) {
    if (auto c = rgbFromHex(j)) return *c;
    throwBadInput(where + " must be [r, g, b] with integers 0..255 or \"#rrggbb\"");
  }
  throwBadInput(where + " must be [r, g, b] with integers 0..255");
}

}  // namespace

json classInfoToJson(const ClassInfo& c) {
  json j = {{"id", c.id}, {"name", c.name}, {"color", rgbJson(c.color)}};
  if (c.faces) {
    j["top"] = rgbJson(c.faces->top);
    j["bottom"] = rgbJson(c.faces->bottom);
    j["side"] = rgbJson(c.faces->side);
  }
  return j;
}

json classTableToJson(const ClassTable& t) {
  json arr = json::array();
  for (const ClassInfo& c : t.classes()) arr.push_back(classInfoToJson(c));
  return arr;
}

ClassInfo classInfoFromJson(const json& c, size_t index, ClassJsonForm form, const std::string& arrayWhere) {
  const std::string where = arrayWhere + "[" + std::to_string(index) + "]";
  const bool handWritten = form == ClassJsonForm::HandWritten;
  if (!c.is_object()) throwBadInput(where + " must be an object with \"id\", \"name\" and \"color\"");
  ClassInfo info;
  int64_t id = int64_t(index) + 1;
  if (c.contains("id")) {
    if (!c["id"].is_number_integer()) throwBadInput(where + " \"id\" must be an integer 1..255");
    id = c["id"].get<int64_t>();
  } else if (!handWritten) {
    throwBadInput(where + " needs an integer \"id\" 1..255");
  }
  if (id < 1 || id > kMaxClassId) throwBadInput(where + " has id " + std::to_string(id) + "; ids are 1..255");
  info.id = uint8_t(id);
  if (!c.contains("name") || !c["name"].is_string()) throwBadInput(where + " needs a string \"name\"");
  info.name = c["name"].get<std::string>();
  if (c.contains("color")) info.color = colorFromJson(c["color"], form, where + " \"color\"");
  else if (handWritten) info.color = kHandWrittenDefaultColor;
  else throwBadInput(where + " needs a \"color\" [r, g, b]");
  int faceKeys = 0;
  for (const char* key : kFaceKeys) faceKeys += c.contains(key) ? 1 : 0;
  if (faceKeys != 0 && faceKeys != 3) throwBadInput(where + " needs all of \"top\", \"bottom\" and \"side\" or none");
  if (faceKeys == 3)
    info.faces = FacePalette{colorFromJson(c["top"], form, where + " \"top\""),
                             colorFromJson(c["bottom"], form, where + " \"bottom\""),
                             colorFromJson(c["side"], form, where + " \"side\"")};
  return info;
}

ClassTable classTableFromJson(const json& arr, ClassJsonForm form, const std::string& where) {
  if (!arr.is_array()) throwBadInput(where + " must be a JSON array of classes");
  ClassTable table;
  for (size_t i = 0; i < arr.size(); ++i)
    table.add(classInfoFromJson(arr[i], i, form, where), where + "[" + std::to_string(i) + "]");
  return table;
}

}  // namespace vox
