#include "formats/scene/scene_meta.h"

#include <nlohmann/json.hpp>

namespace vox {

namespace {
nlohmann::json rgbJson(Rgb8 c) { return nlohmann::json::array({c.r, c.g, c.b}); }
}  // namespace

std::string classTableJson(const ClassTable& t) {
  nlohmann::json arr = nlohmann::json::array();
  for (const ClassInfo& c : t.classes()) {
    nlohmann::json j = {{"id", c.id}, {"name", c.name}, {"color", rgbJson(c.color)}};
    if (c.faces) {
      j["top"] = rgbJson(c.faces->top);
      j["bottom"] = rgbJson(c.faces->bottom);
      j["side"] = rgbJson(c.faces->side);
    }
    arr.push_back(std::move(j));
  }
  return arr.dump();
}

std::string sourcesJson(const std::vector<SceneSource>& sources) {
  nlohmann::json arr = nlohmann::json::array();
  for (const SceneSource& s : sources)
    arr.push_back({{"path", s.path}, {"kind", s.kind}, {"sha256", s.sha256}, {"bytes", s.bytes}});
  return arr.dump();
}

std::string blockWorldJson(const BlockWorldPlacement& p) {
  const nlohmann::json bw = {{"worldScale", p.worldScale}, {"gridSize", {p.gridSize[0], p.gridSize[1], p.gridSize[2]}}};
  return bw.dump();
}

}  // namespace vox
