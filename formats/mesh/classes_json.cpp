#include "formats/mesh/classes_json.h"

#include <nlohmann/json.hpp>

#include "formats/core/file_util.h"
#include "formats/core/json_fields.h"
#include "formats/core/json_input.h"
#include "formats/scene/class_table_json.h"
#include "libvox/core/error.h"

namespace vox {

namespace {
using nlohmann::json;
}  // namespace

ClassMapping parseClassMapping(const std::string& text, const std::string& path) {
  json doc;
  try {
    doc = parseJsonInput(text, path);
  } catch (const json::parse_error& e) {
    throwBadInput(path + ": not valid JSON (byte " + std::to_string(e.byte) + ")");
  } catch (const json::exception& e) {  // a number past double's range (out_of_range.406) is not a parse_error
    throwBadInput(path + ": not valid JSON: " + e.what());
  }
  if (!doc.is_object() || !doc.contains("classes") || !doc["classes"].is_array())
    throwBadInput(path + ": expected an object with a \"classes\" array");
  // Every key is read: a misspelt "match" or "default" would leave the
  // materials unmapped without a word, so other keys are refused by name.
  jsonOnlyKeys(doc, {"classes", "default"}, path, "the rules file");
  ClassMapping m;
  const json& classes = doc["classes"];
  const std::string arrayWhere = path + ": classes";
  for (size_t i = 0; i < classes.size(); ++i) {
    const json& c = classes[i];
    const std::string where = arrayWhere + "[" + std::to_string(i) + "]";
    const ClassInfo info = classInfoFromJson(c, i, ClassJsonForm::HandWritten, arrayWhere);
    jsonOnlyKeys(c, {"id", "name", "color", "top", "bottom", "side", "match"}, path, "classes[" + std::to_string(i) + "]");
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
