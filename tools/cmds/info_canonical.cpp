#include "tools/cmds/info_canonical.h"

#include <cstdlib>
#include <iostream>
#include <nlohmann/json.hpp>

#include "formats/core/file_util.h"
#include "libvox/core/error.h"
#include "tools/cli/cli.h"
#include "tools/cmds/render_input.h"

namespace voxcli {

int infoCanonical(const std::string& path, const vox::Image& img, const std::string& pixel, const std::string& scenePath,
                  bool json) {
  nlohmann::json meta;
  try {
    meta = nlohmann::json::parse(img.textValue("vox:canonical"));
  } catch (const nlohmann::json::parse_error&) {
    vox::throwBadInput(path + ": its \"vox:canonical\" entry is not valid JSON");
  }
  nlohmann::json j = {{"file", path},
                      {"kind", "render"},
                      {"mode", meta.value("mode", "")},
                      {"image", {{"width", img.width}, {"height", img.height}, {"channels", img.channels},
                                 {"sample", vox::sampleTypeName(img.type)}}},
                      {"file_bytes", vox::fileSizeOrMinusOne(path)},
                      {"render", meta}};
  const std::string mode = meta.value("mode", "");
  if (!pixel.empty()) {
    const size_t comma = pixel.find(',');
    char* end = nullptr;
    const unsigned long x = std::strtoul(pixel.c_str(), &end, 10);
    const unsigned long y = comma == std::string::npos ? 0 : std::strtoul(pixel.c_str() + comma + 1, &end, 10);
    if (comma == std::string::npos || *end != '\0' || x >= img.width || y >= img.height)
      vox::throwUsage("--pixel " + pixel + ": expected x,y inside the " + std::to_string(img.width) + " x " +
                      std::to_string(img.height) + " image (row 0 at the top)");
    if (mode != "canonical")
      vox::throwUsage("--pixel: " + path + " is a '" + mode +
                      "' render; picking decodes canonical renders (render with --mode canonical)");
    const size_t base = (size_t(y) * img.width + x) * 4;
    uint64_t v[4];
    for (int c = 0; c < 4; ++c) {
      switch (img.type) {
        case vox::SampleType::U8: v[c] = img.pixels[base + size_t(c)]; break;
        case vox::SampleType::U16: v[c] = reinterpret_cast<const uint16_t*>(img.pixels.data())[base + size_t(c)]; break;
        default: v[c] = reinterpret_cast<const uint32_t*>(img.pixels.data())[base + size_t(c)]; break;
      }
    }
    nlohmann::json p = {{"pixel", {x, y}}, {"values", {v[0], v[1], v[2], v[3]}}, {"hit", v[3] != 0}};
    if (v[3] != 0) {
      p["voxel"] = {v[0], v[1], v[2]};
      if (meta.contains("origin") && meta.contains("voxel_size")) {
        const double s = meta["voxel_size"].get<double>();
        nlohmann::json lo = nlohmann::json::array(), hi = nlohmann::json::array();
        for (int a = 0; a < 3; ++a) {
          lo.push_back(meta["origin"][size_t(a)].get<double>() + double(v[a]) * s);
          hi.push_back(meta["origin"][size_t(a)].get<double>() + double(v[a] + 1) * s);
        }
        p["world_box"] = {{"min", lo}, {"max", hi}};
      }
      if (!scenePath.empty()) {
        const RenderInput in = loadRenderInput(scenePath, meta.value("level", 0), /*needSummaries=*/true);
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
  if (meta.contains("scene")) std::cout << "  rendered from " << meta["scene"].get<std::string>() << "\n";
  if (meta.contains("dims")) std::cout << "  scene dims    " << meta["dims"].dump() << "\n";
  if (meta.contains("camera")) {
    const auto& v = meta["camera"]["viewMatrix"];
    std::cout << "  camera        view matrix " << v.dump() << "\n";
  }
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
