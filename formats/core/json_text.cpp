#include "formats/core/json_text.h"

#include "libvox/core/utf8.h"

namespace vox {

namespace {

nlohmann::json withUtf8Strings(const nlohmann::json& j) {
  if (j.is_string()) return utf8FromLegacy(j.get_ref<const std::string&>());
  if (j.is_array()) {
    nlohmann::json out = nlohmann::json::array();
    for (const nlohmann::json& e : j) out.push_back(withUtf8Strings(e));
    return out;
  }
  if (j.is_object()) {
    nlohmann::json out = nlohmann::json::object();
    for (auto it = j.begin(); it != j.end(); ++it) out[utf8FromLegacy(it.key())] = withUtf8Strings(it.value());
    return out;
  }
  return j;
}

}  // namespace

std::string jsonText(const nlohmann::json& j, int indent) {
  try {
    return j.dump(indent);
  } catch (const nlohmann::json::type_error& e) {
    if (e.id != 316) throw;  // 316: a string is not UTF-8
    return withUtf8Strings(j).dump(indent);
  }
}

}  // namespace vox
