#include "formats/core/json_fields.h"

#include <algorithm>

#include "libvox/core/error.h"

namespace vox {

namespace {
[[noreturn]] void bad(const std::string& context, const std::string& element, const std::string& what) {
  throwBadInput(context + ": " + element + " must be " + what);
}
}  // namespace

const nlohmann::json& jsonMember(const nlohmann::json& object, const char* key, const std::string& context) {
  if (!object.contains(key)) throwBadInput(context + ": no \"" + key + "\"");
  return object[key];
}

std::string jsonString(const nlohmann::json& j, const std::string& context, const std::string& element) {
  if (!j.is_string()) bad(context, element, "a string");
  return j.get<std::string>();
}

double jsonNumber(const nlohmann::json& j, const std::string& context, const std::string& element) {
  if (!j.is_number()) bad(context, element, "a number");
  return j.get<double>();
}

int64_t jsonInteger(const nlohmann::json& j, const std::string& context, const std::string& element) {
  if (!j.is_number_integer()) bad(context, element, "an integer");
  return j.get<int64_t>();
}

uint64_t jsonUnsigned(const nlohmann::json& j, const std::string& context, const std::string& element) {
  if (!j.is_number_unsigned()) bad(context, element, "a non-negative integer");
  return j.get<uint64_t>();
}

Dims jsonDims(const nlohmann::json& j, const std::string& context, const std::string& element) {
  if (!j.is_array() || j.size() != 3) bad(context, element, "[X, Y, Z], three integers 1..2^32-1");
  uint32_t extent[3];
  for (size_t a = 0; a < 3; ++a) {
    const uint64_t v = j[a].is_number_unsigned() ? j[a].get<uint64_t>() : 0;
    if (v < 1 || v > UINT32_MAX) bad(context, element, "[X, Y, Z], three integers 1..2^32-1");
    extent[a] = uint32_t(v);
  }
  return {extent[0], extent[1], extent[2]};
}

std::vector<std::string> jsonUnknownKeys(const nlohmann::json& object, const std::vector<std::string>& known) {
  std::vector<std::string> out;
  for (const auto& [key, value] : object.items())
    if (std::find(known.begin(), known.end(), key) == known.end()) out.push_back(key);
  return out;
}

std::string jsonKeyList(const std::vector<std::string>& keys) {
  std::string list;
  for (const std::string& k : keys) list += (list.empty() ? "" : ", ") + k;
  return list;
}

void jsonOnlyKeys(const nlohmann::json& object, std::initializer_list<const char*> known, const std::string& context,
                  const std::string& element) {
  const std::vector<std::string> keys(known.begin(), known.end());
  const std::vector<std::string> unknown = jsonUnknownKeys(object, keys);
  if (!unknown.empty())
    throwBadInput(context + ": " + element + " has no key \"" + unknown.front() + "\" (its keys: " + jsonKeyList(keys) + ")");
}

}  // namespace vox
