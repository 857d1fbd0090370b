#include "tools/cmds/info_canonical.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "formats/core/file_util.h"
#include "formats/core/json_text.h"
#include "formats/image/render_meta.h"
#include "libvox/core/error.h"
#include "libvox/scene/scene.h"
#include "tools/cli/cli.h"
#include "tools/cmds/info_atlas.h"
#include "tools/cmds/info_text.h"
#include "tools/cmds/render_input.h"

namespace voxcli {

namespace {

// A world position or length with every digit that tells two apart.
std::string worldText(double v) { return nlohmann::json(v).dump(); }
std::string worldText(const std::array<double, 3>& v) {
  return "(" + worldText(v[0]) + ", " + worldText(v[1]) + ", " + worldText(v[2]) + ")";
}

}  // namespace

int infoCanonical(const std::string& path, const vox::Image& img, const std::optional<PixelXY>& pixel,
                  const std::string& scenePath, bool json) {
  const vox::RenderMeta meta = *vox::readRenderMeta(img, path);
  const std::string mode = vox::renderModeName(meta.mode);
  nlohmann::json j = {{"file", path},
                      {"kind", "render"},
                      {"mode", mode},
                      {"image", {{"width", img.width}, {"height", img.height}, {"channels", img.channels},
                                 {"sample", vox::sampleTypeName(img.type)}}},
                      {"file_bytes", vox::fileSizeOrMinusOne(path)},
                      {"render", nlohmann::json::parse(vox::renderMetaJson(meta))}};
  if (!pixel && !scenePath.empty())
    vox::throwUsage("--scene with a render goes with --pixel x,y: the scene the picked voxel is looked up in");
  if (pixel) {
    const uint32_t x = pixel->x, y = pixel->y;
    if (x >= img.width || y >= img.height)
      vox::throwUsage("--pixel " + pixel->text() + ": outside the " + std::to_string(img.width) + " x " +
                      std::to_string(img.height) + " image (x 0.." + std::to_string(img.width - 1) + ", y 0.." +
                      std::to_string(img.height - 1) + ", row 0 at the top)");
    if (meta.mode != vox::RenderMode::Canonical)
      vox::throwUsage("--pixel: " + path + " is a '" + mode +
                      "' render; picking decodes canonical renders (render with --mode canonical)");
    vox::requireCanonicalImage(img, path);
    // The scene must be the render's: the same grid, placed the same, else
    // the voxel would be looked up in another scene.
    std::optional<RenderInput> in;
    if (!scenePath.empty()) {
      in.emplace(loadRenderInput(scenePath, meta.level.value_or(0), /*needSummaries=*/true));
      if (!(in->dims == meta.dims))
        vox::throwBadInput(path + ": rendered from a grid of " + vox::toString(meta.dims) + " but " + scenePath +
                           " has " + vox::toString(in->dims) + "; give --scene the scene (or page file) rendered");
      if (in->frame.origin != meta.origin || in->frame.voxelSize != meta.voxelSize)
        vox::throwBadInput(path + ": rendered from a grid at origin " + worldText(meta.origin) + " with voxel size " +
                           worldText(meta.voxelSize) + " but " + scenePath + " is at " + worldText(in->frame.origin) +
                           " with voxel size " + worldText(in->frame.voxelSize) +
                           "; give --scene the scene (or page file) rendered");
    }
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
      if (in) {
        const vox::Coord3 c{int32_t(v[0]), int32_t(v[1]), int32_t(v[2])};
        const bool inside = v[0] < in->dims.x && v[1] < in->dims.y && v[2] < in->dims.z;
        if (!inside || !in->grid->occupied(c.u, c.v, c.w)) {
          p["scene_voxel"] = nullptr;
          p["note"] = "the voxel is empty in " + scenePath + ": the image was not rendered from it";
        } else {
          const vox::SummaryTexel s = in->summaries(std::span<const vox::Coord3>(&c, 1))[0];
          nlohmann::json sv = {{"summary", {{"cls", s.cls}, {"conf", s.conf}, {"obs", s.obs}, {"mrg", s.mrg}}}};
          if (const vox::ClassInfo* ci = in->classes.find(s.cls)) sv["class_name"] = ci->name;
          if (in->scene) {
            std::vector<vox::ClassVotes> storage;
            if (const auto vv = in->scene->voxel(c, storage)) {
              nlohmann::json votes = nlohmann::json::object();
              for (const vox::ClassVotes& cv : vv->votes) {
                const vox::ClassInfo* ci = in->classes.find(cv.classId);
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
  // Pixels that hit a voxel: alpha != 0 (every mode writes alpha 0 where the ray misses).
  if (img.channels == 4) {
    const size_t n = size_t(img.width) * img.height, sb = vox::sampleBytes(img.type);
    uint64_t hits = 0;
    for (size_t i = 0; i < n; ++i) {
      const uint8_t* a = img.pixels.data() + (i * 4 + 3) * sb;
      bool nonzero = false;
      for (size_t k = 0; k < sb; ++k) nonzero |= a[k] != 0;
      hits += nonzero;
    }
    j["hit_pixels"] = hits;
  }
  if (json) {
    std::cout << vox::jsonText(j, 2) << "\n";
    return kExitOk;
  }
  using namespace infotext;
  std::ostringstream o;
  o << heading(path, mode + " render, " + std::to_string(img.width) + " x " + std::to_string(img.height) + " x " +
                          std::to_string(img.channels) + " " + vox::sampleTypeName(img.type));
  o << line("rendered from", meta.scene + (meta.level ? " (level " + std::to_string(*meta.level) + ")" : ""));
  o << line("scene dims", std::to_string(meta.dims.x) + " x " + std::to_string(meta.dims.y) + " x " +
                              std::to_string(meta.dims.z) + " voxels of " +
                              measured(meta.voxelSize, 6, "world unit", "world units"));
  // The camera in words: the eye is -R^T t of the view matrix (column-major),
  // it looks along -z of the camera frame; the vertical field of view comes
  // from the projection's y scale.
  const vox::Mat4d& V = meta.viewMatrix;
  double eye[3], fwd[3];
  for (int a = 0; a < 3; ++a) {
    eye[a] = -(V[size_t(a * 4 + 0)] * V[12] + V[size_t(a * 4 + 1)] * V[13] + V[size_t(a * 4 + 2)] * V[14]);
    fwd[a] = -V[size_t(a * 4 + 2)];
  }
  // Rounding noise of the matrix product (1.8e-15 for an eye at x = 0) is 0 to a person.
  const double scale = std::max({std::fabs(eye[0]), std::fabs(eye[1]), std::fabs(eye[2]), 1.0});
  for (double& e : eye)
    if (std::fabs(e) < 1e-12 * scale) e = 0;
  o << line("camera", "eye " + triple(eye[0], eye[1], eye[2], 5) + ", looking along " + triple(fwd[0], fwd[1], fwd[2], 3));
  const double p11 = meta.projectionMatrix[5];
  if (p11 > 0) o << line("", "vertical field of view " + real(2.0 * std::atan(1.0 / p11) * 180.0 / M_PI, 4) + " degrees, view " +
                                 std::to_string(meta.view));
  if (j.contains("hit_pixels"))
    o << line("hits", count(j["hit_pixels"].get<uint64_t>()) + " of " +
                          countOf(uint64_t(img.width) * img.height, "pixel", "pixels") +
                          (j["hit_pixels"].get<uint64_t>() == 1 ? " shows" : " show") + " a voxel (" +
                          percent(double(j["hit_pixels"].get<uint64_t>()) / double(uint64_t(img.width) * img.height)) + ")");
  if (meta.mode == vox::RenderMode::Canonical)
    o << line("channels", "RGB = (u, v, w) of the first voxel a pixel's ray enters,")
      << line("", "A = full scale on a hit; --pixel x,y [--scene S] decodes one");
  if (j.contains("pixel")) {
    const nlohmann::json& p = j["pixel"];
    const std::string at = "(" + p["pixel"][0].dump() + ", " + p["pixel"][1].dump() + ")";
    if (!p["hit"].get<bool>()) {
      o << line("pixel", at + ": no voxel (alpha 0)");
    } else {
      o << line("pixel", at + " is voxel (" + p["voxel"][0].dump() + ", " + p["voxel"][1].dump() + ", " +
                             p["voxel"][2].dump() + ")");
      const auto& wb = p["world_box"];
      o << line("world box", triple(wb["min"][0].get<double>(), wb["min"][1].get<double>(), wb["min"][2].get<double>(), 6) +
                                 " .. " +
                                 triple(wb["max"][0].get<double>(), wb["max"][1].get<double>(), wb["max"][2].get<double>(), 6));
      if (p.contains("scene_voxel")) {
        const auto& sv = p["scene_voxel"];
        if (sv.is_null()) {
          o << line("in the scene", p.value("note", std::string("empty")));
        } else {
          const auto& s = sv["summary"];
          vox::ClassTable names;  // the one class the summary names
          if (sv.contains("class_name"))
            names.add({uint8_t(s["cls"].get<int>()), sv["class_name"].get<std::string>(), {}, std::nullopt});
          const auto lines = explainSummary(s["cls"].get<int>(), s["conf"].get<int>(), s["obs"].get<int>(),
                                            s["mrg"].get<int>(), &names);
          for (size_t i = 0; i < lines.size(); ++i) o << line(i ? "" : "summary", lines[i]);
          if (sv.contains("votes")) {
            std::string v;
            for (const auto& [name, n] : sv["votes"].items()) v += (v.empty() ? "" : ", ") + name + " " + n.dump();
            o << line("votes", v + (sv.value("surface", false) ? " (surface voxel)" : " (interior voxel)"));
          }
        }
      }
    }
  }
  std::cout << o.str();
  return kExitOk;
}

}  // namespace voxcli
