#include "tools/cmds/render_input.h"

#include <chrono>
#include <nlohmann/json.hpp>

#include "formats/vdb/scene_vdb.h"
#include "libvox/core/error.h"

namespace voxcli {

namespace {

vox::Rgb8 rgb(const nlohmann::json& j, const std::string& where, const std::string& path) {
  if (!j.is_array() || j.size() != 3) vox::throwBadInput(path + ": metadata " + where + " must be [r, g, b]");
  vox::Rgb8 c;
  uint8_t* out[3] = {&c.r, &c.g, &c.b};
  for (size_t i = 0; i < 3; ++i) {
    if (!j[i].is_number_integer() || j[i].get<int64_t>() < 0 || j[i].get<int64_t>() > 255)
      vox::throwBadInput(path + ": metadata " + where + " must hold integers 0..255");
    *out[i] = uint8_t(j[i].get<int64_t>());
  }
  return c;
}

}  // namespace

vox::ClassTable pageClasses(const vox::pagefile::Reader& r) {
  vox::ClassTable t;
  nlohmann::json meta;
  try {
    meta = nlohmann::json::parse(r.metaJson());
  } catch (const nlohmann::json::parse_error&) {
    vox::throwBadInput(r.name() + ": the metadata is not valid JSON");
  }
  if (!meta.contains("classes")) return t;
  const nlohmann::json& arr = meta["classes"];
  if (!arr.is_array()) vox::throwBadInput(r.name() + ": metadata 'classes' must be an array");
  for (size_t i = 0; i < arr.size(); ++i) {
    const std::string where = "'classes' entry " + std::to_string(i);
    const nlohmann::json& c = arr[i];
    if (!c.is_object() || !c.contains("id") || !c["id"].is_number_integer() || !c.contains("name") ||
        !c["name"].is_string() || !c.contains("color"))
      vox::throwBadInput(r.name() + ": metadata " + where + " needs id, name and color");
    const int64_t id = c["id"].get<int64_t>();
    if (id < 1 || id > 255) vox::throwBadInput(r.name() + ": metadata " + where + ": id must be 1..255");
    vox::ClassInfo info;
    info.id = uint8_t(id);
    info.name = c["name"].get<std::string>();
    info.color = rgb(c["color"], where + ".color", r.name());
    if (c.contains("top") && c.contains("bottom") && c.contains("side"))
      info.faces = vox::FacePalette{rgb(c["top"], where + ".top", r.name()), rgb(c["bottom"], where + ".bottom", r.name()),
                                    rgb(c["side"], where + ".side", r.name())};
    t.add(std::move(info), r.name() + ": metadata 'classes'");
  }
  return t;
}

std::vector<vox::SummaryTexel> RenderInput::summaries(std::span<const vox::Coord3> voxels) const {
  if (scene) return vox::sceneSummaries(*scene, voxels);
  return vox::pageSummaries(*pages, level, voxels);
}

RenderInput loadRenderInput(const std::string& path, int level, bool needSummaries) {
  RenderInput in;
  const auto t0 = std::chrono::steady_clock::now();
  auto seconds = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
  in.path = path;
  in.level = level;
  if (vox::pagefile::looksLikePageFile(path)) {
    in.kind = "pages";
    in.pages.emplace(vox::pagefile::Reader::open(path));
    const vox::pagefile::Header& h = in.pages->header();
    if (level < 0 || level >= int(h.levelCount))
      vox::throwUsage("--level " + std::to_string(level) + ": " + path + " holds levels 0.." +
                      std::to_string(h.levelCount - 1));
    const auto d = h.levelDims(level);
    in.dims = {d[0], d[1], d[2]};
    in.frame.origin = h.origin;
    in.frame.voxelSize = h.voxelSize * double(uint64_t(1) << level);
    in.classes = pageClasses(*in.pages);
    const auto t1 = std::chrono::steady_clock::now();
    in.grid = std::make_unique<vox::RayGrid>(vox::rayGridFromPages(*in.pages, level));
    in.readSeconds = seconds(t0, t1);
    in.gridSeconds = seconds(t1, std::chrono::steady_clock::now());
    return in;
  }
  if (level != 0) vox::throwUsage("--level " + std::to_string(level) + ": only page files (.vpk) hold levels; " + path + " is a scene");
  in.kind = "scene";
  in.scene.emplace(vox::readSceneVdb(path, needSummaries ? vox::SceneParts::All : vox::SceneParts::OccupancyOnly));
  const vox::SceneHeader& h = in.scene->header();
  in.dims = h.dims;
  in.frame.origin = h.origin;
  in.frame.voxelSize = h.voxelSize;  // already the level's voxel size for mip scenes
  in.classes = h.classes;
  const auto t1 = std::chrono::steady_clock::now();
  in.grid = std::make_unique<vox::RayGrid>(vox::rayGridFromScene(*in.scene));
  in.readSeconds = seconds(t0, t1);
  in.gridSeconds = seconds(t1, std::chrono::steady_clock::now());
  return in;
}

}  // namespace voxcli
