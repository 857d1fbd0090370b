#include "formats/mesh/classes_json.h"

#include <nlohmann/json.hpp>

#include "formats/core/file_util.h"
#include "libvox/core/error.h"

namespace vox {

namespace {
using nlohmann::json;

Rgb8 parseColor(const json& j, const std::string& where) {
  if (j.is_string()) {
    const std::string s = j.get<std::string>();
    unsigned r, g, b;
    if (s.size() == 7 && s[0] == '#' && std::sscanf(s.c_str() + 1, "%2x%2x%2x", &r, &g, &b) == 3)
      return {uint8_t(r), uint8_t(g), uint8_t(b)};
  } else if (j.is_array() && j.size() == 3) {
    Rgb8 c;
    uint8_t* o[3] = {&c.r, &c.g, &c.b};
    bool ok = true;
    for (int i = 0; i < 3; ++i) {
      ok = ok && j[i].is_number_integer() && j[i].get<int64_t>() >= 0 && j[i].get<int64_t>() <= 255;
      if (ok) *o[i] = uint8_t(j[i].get<int>());
    }
    if (ok) return c;
  }
  throwBadInput(where + " must be [r, g, b] with integers 0..255 or \"#rrggbb\"");
}
}  // namespace

ClassMapping parseClassMapping(const std::string& text, const std::string& path) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::parse_error& e) {
    throwBadInput(path + ": not valid JSON (byte " + std::to_string(e.byte) + ")");
  }
  if (!doc.is_object() || !doc.contains("classes") || !doc["classes"].is_array())
    throwBadInput(path + ": expected an object with a \"classes\" array");
  ClassMapping m;
  const json& classes = doc["classes"];
  for (size_t i = 0; i < classes.size(); ++i) {
    const json& c = classes[i];
    const std::string where = path + ": classes[" + std::to_string(i) + "]";
    if (!c.is_object() || !c.contains("name") || !c["name"].is_string())
      throwBadInput(where + " needs a string \"name\"");
    ClassInfo info;
    info.name = c["name"].get<std::string>();
    int64_t id = int64_t(i) + 1;
    if (c.contains("id")) {
      if (!c["id"].is_number_integer()) throwBadInput(where + " \"id\" must be an integer 1..255");
      id = c["id"].get<int64_t>();
    }
    if (id < 1 || id > kMaxClassId) throwBadInput(where + " has id " + std::to_string(id) + "; ids are 1..255");
    info.id = uint8_t(id);
    info.color = c.contains("color") ? parseColor(c["color"], where + " \"color\"") : Rgb8{128, 128, 128};
    if (c.contains("top") || c.contains("bottom") || c.contains("side")) {
      if (!c.contains("top") || !c.contains("bottom") || !c.contains("side"))
        throwBadInput(where + " needs all of \"top\", \"bottom\", \"side\" or none");
      info.faces = FacePalette{parseColor(c["top"], where + " \"top\""), parseColor(c["bottom"], where + " \"bottom\""),
                               parseColor(c["side"], where + " \"side\"")};
    }
    m.table.add(info, where);
    if (c.contains("match")) {
      const json& match = c["match"];
      if (!match.is_array()) throwBadInput(where + " \"match\" must be an array of glob patterns");
      for (size_t k = 0; k < match.size(); ++k) {
        if (!match[k].is_string()) throwBadInput(where + " match[" + std::to_string(k) + "] must be a string");
        std::string p = match[k].get<std::string>();
        ClassRule r;
        r.classId = info.id;
        for (auto [prefix, field] : {std::pair{"material:", ClassRule::Field::Material},
                                     std::pair{"mesh:", ClassRule::Field::Mesh}, std::pair{"node:", ClassRule::Field::Node}})
          if (p.rfind(prefix, 0) == 0) {
            r.field = field;
            p = p.substr(std::string(prefix).size());
          }
        r.pattern = p;
        m.rules.push_back(r);
      }
    }
  }
  if (doc.contains("default")) {
    if (!doc["default"].is_string()) throwBadInput(path + ": \"default\" must be a class name");
    const ClassInfo* d = m.table.findByName(doc["default"].get<std::string>());
    if (!d) throwBadInput(path + ": \"default\" names class '" + doc["default"].get<std::string>() + "', which is not in \"classes\"");
    m.defaultClass = d->id;
  }
  if (m.table.size() == 0) throwBadInput(path + ": \"classes\" is empty");
  return m;
}

ClassMapping readClassMapping(const std::string& path) { return parseClassMapping(readFileBytes(path), path); }

}  // namespace vox
