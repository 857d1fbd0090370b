#include "tools/cmds/info_canonical.h"

#include <cstdlib>
#include <iostream>
#include <nlohmann/json.hpp>

#include "formats/core/file_util.h"
#include "formats/image/render_meta.h"
#include "libvox/core/error.h"
#include "tools/cli/cli.h"
#include "tools/cmds/render_input.h"

namespace voxcli {

int infoCanonical(const std::string& path, const vox::Image& img, const std::string& pixel, const std::string& scenePath,
                  bool json) {
  const vox::RenderMeta meta = *vox::readRenderMeta(img, path);
  const std::string mode = vox::renderModeName(meta.mode);
  nlohmann::json j = {{"file", path},
                      {"kind", "render"},
                      {"mode", mode},
                      {"image", {{"width", img.width}, {"height", img.height}, {"channels", img.channels},
                                 {"sample", vox::sampleTypeName(img.type)}}},
                      {"file_bytes", vox::fileSizeOrMinusOne(path)},
                      {"render", nlohmann::json::parse(vox::renderMetaJson(meta))}};
  if (!pixel.empty()) {
    const size_t comma = pixel.find(',');
    char* end = nullptr;
    const unsigned long x = std::strtoul(pixel.c_str(), &end, 10);
    const unsigned long y = comma == std::string::npos ? 0 : std::strtoul(pixel.c_str() + comma + 1, &end, 10);
    if (comma == std::string::npos || *end != '\0' || x >= img.width || y >= img.height)
      vox::throwUsage("--pixel " + pixel + ": expected x,y inside the " + std::to_string(img.width) + " x " +
                      std::to_string(img.height) + " image (row 0 at the top)");
    if (meta.mode != vox::RenderMode::Canonical)
      vox::throwUsage("--pixel: " + path + " is a '" + mode +
                      "' render; picking decodes canonical renders (render with --mode canonical)");
    vox::requireCanonicalImage(img, path);
    const std::array<uint64_t, 4> v = vox::canonicalSamples(img, size_t(y) * img.width + x);
    nlohmann::json p = {{"pixel", {x, y}}, {"values", {v[0], v[1], v[2], v[3]}}, {"hit", v[3] != 0}};
    if (v[3] != 0) {
      p["voxel"] = {v[0], v[1], v[2]};
      // The voxel's box in world space: grid point g is origin + g * voxelSize.
      nlohmann::json worldMin = nlohmann::json::array(), worldMax = nlohmann::json::array();
      for (size_t a = 0; a < 3; ++a) {
        worldMin.push_back(meta.origin[a] + double(v[a]) * meta.voxelSize);
        worldMax.push_back(meta.origin[a] + double(v[a] + 1) * meta.voxelSize);
      }
      p["world_box"] = {{"min", worldMin}, {"max", worldMax}};
      if (!scenePath.empty()) {
        const RenderInput in = loadRenderInput(scenePath, meta.level.value_or(0), /*needSummaries=*/true);
        const vox::Coord3 c{int32_t(v[0]), int32_t(v[1]), int32_t(v[2])};
        const bool inside = v[0] < in.dims.x && v[1] < in.dims.y && v[2] < in.dims.z;
        if (!inside || !in.grid->occupied(c.u, c.v, c.w)) {
          p["scene_voxel"] = nullptr;
          p["note"] = "the voxel is empty in " + scenePath + ": the image was not rendered from it";
        } else {
          const vox::SummaryTexel s = in.summaries(std::span<const vox::Coord3>(&c, 1))[0];
          nlohmann::json sv = {{"summary", {{"cls", s.cls}, {"conf", s.conf}, {"obs", s.obs}, {"mrg", s.mrg}}}};
          if (const vox::ClassInfo* ci = in.classes.find(s.cls)) sv["class_name"] = ci->name;
          if (in.scene) {
            std::vector<vox::ClassVotes> storage;
            if (const auto vv = in.scene->voxel(c, storage)) {
              nlohmann::json votes = nlohmann::json::object();
              for (const vox::ClassVotes& cv : vv->votes) {
                const vox::ClassInfo* ci = in.classes.find(cv.classId);
                votes[ci ? ci->name : std::to_string(cv.classId)] = cv.votes;
              }
              sv["votes"] = votes;
              sv["surface"] = vv->surface;
            }
          }
          p["scene_voxel"] = sv;
        }
      }
    }
    j["pixel"] = p;
  }
  if (json) {
    std::cout << j.dump(2) << "\n";
    return kExitOk;
  }
  std::cout << path << ": " << mode << " render, " << img.width << " x " << img.height << " x " << img.channels << " "
            << vox::sampleTypeName(img.type) << "\n";
  const nlohmann::json& render = j["render"];
  std::cout << "  rendered from " << meta.scene << "\n";
  std::cout << "  scene dims    " << render["dims"].dump() << "\n";
  std::cout << "  camera        view matrix " << render["camera"]["viewMatrix"].dump() << "\n";
  if (j.contains("pixel")) {
    const nlohmann::json& p = j["pixel"];
    if (!p["hit"].get<bool>()) {
      std::cout << "  pixel (" << p["pixel"][0] << ", " << p["pixel"][1] << "): no voxel (alpha 0)\n";
    } else {
      std::cout << "  pixel (" << p["pixel"][0] << ", " << p["pixel"][1] << "): voxel (" << p["voxel"][0] << ", "
                << p["voxel"][1] << ", " << p["voxel"][2] << ")\n";
      if (p.contains("world_box")) std::cout << "  world box     " << p["world_box"].dump() << "\n";
      if (p.contains("scene_voxel")) std::cout << "  in the scene  " << p["scene_voxel"].dump() << "\n";
    }
  }
  return kExitOk;
}

}  // namespace voxcli
