// Reading the elements of a JSON document with errors that say where: every
// function throws vox::Error (BadInput) "CONTEXT: ELEMENT must be ..." (or
// "CONTEXT: no "KEY"" for a missing member), where CONTEXT names the file (and
// the entry inside it) and ELEMENT the path to the value ("chunks[3].morton").
//
// Thread safety: pure functions.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "libvox/core/types.h"

namespace vox {

/// object[key]; `object` must be a JSON object.
const nlohmann::json& jsonMember(const nlohmann::json& object, const char* key, const std::string& context);
std::string jsonString(const nlohmann::json& j, const std::string& context, const std::string& element);
/// Any JSON number (integers included).
double jsonNumber(const nlohmann::json& j, const std::string& context, const std::string& element);
int64_t jsonInteger(const nlohmann::json& j, const std::string& context, const std::string& element);
uint64_t jsonUnsigned(const nlohmann::json& j, const std::string& context, const std::string& element);
/// A grid's extent [X, Y, Z], each 1..2^32-1.
Dims jsonDims(const nlohmann::json& j, const std::string& context, const std::string& element);
/// The keys of `object` (a JSON object) that are not in `known`, in the
/// object's order: for readers that warn about them rather than refuse.
std::vector<std::string> jsonUnknownKeys(const nlohmann::json& object, const std::vector<std::string>& known);
/// "A, B, C": a key list for messages.
std::string jsonKeyList(const std::vector<std::string>& keys);
/// Refuses a key of `object` (a JSON object) that is not in `known`:
/// "CONTEXT: ELEMENT has no key "K" (its keys: A, B, C)". For objects where a
/// key nothing reads would change the result silently: a misspelt "fov" of a
/// camera renders at the default field of view.
void jsonOnlyKeys(const nlohmann::json& object, std::initializer_list<const char*> known, const std::string& context,
                  const std::string& element);

}  // namespace vox
