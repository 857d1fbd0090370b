#include "tools/cmds/info_atlas.h"

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "formats/core/file_util.h"
#include "formats/core/json_text.h"
#include "formats/image/atlas_meta.h"
#include "formats/pagefile/pagefile.h"
#include "formats/pagefile/pagefile_meta.h"
#include "formats/vdb/scene_vdb.h"
#include "libvox/core/error.h"
#include "libvox/core/texel_formats.h"
#include "tools/cli/cli.h"
#include "tools/cmds/info_text.h"

namespace voxcli {

namespace fs = std::filesystem;
using namespace infotext;

std::optional<SceneFacts> sceneFactsOf(const std::string& path) {
  std::error_code ec;
  if (path.empty() || !fs::is_regular_file(path, ec)) return std::nullopt;
  if (vox::pagefile::looksLikePageFile(path)) {
    const vox::pagefile::Reader r = vox::pagefile::Reader::open(path);
    const auto& d = r.header().dims;
    return SceneFacts{vox::pagefile::readPageMeta(r.metaJson(), path).classes, vox::Dims{d[0], d[1], d[2]}};
  }
  // The header is all that is needed: leave the vote and colour grids in the file.
  const vox::Scene scene = vox::readSceneVdb(path, vox::SceneParts::OccupancyOnly);
  return SceneFacts{scene.header().classes, scene.header().dims};
}

std::vector<std::string> explainSummary(int cls, int conf, int obs, int mrg, const vox::ClassTable* classes) {
  if (cls == 0 && conf == 0 && obs == 0 && mrg == 0) return {"empty (no voxel, or no votes)"};
  std::vector<std::string> out;
  const vox::ClassInfo* ci = classes ? classes->find(uint8_t(cls)) : nullptr;
  out.push_back(ci ? ci->name + " (class " + std::to_string(cls) + ")" : "class " + std::to_string(cls));
  out.push_back("confidence " + percent(conf / 255.0) + " (" + std::to_string(conf) + "/255)");
  // obs = floor(16 log2(total + 1)): total lies in [2^(obs/16) - 1, 2^((obs+1)/16) - 1).
  const double lo = std::ceil(std::exp2(obs / 16.0) - 1 - 1e-9), hi = std::ceil(std::exp2((obs + 1) / 16.0) - 1 - 1e-9) - 1;
  std::string o = "observations " + std::to_string(obs) + " (total votes ";
  o += obs >= 255 ? ">= " + count(uint64_t(lo)) : lo >= hi ? count(uint64_t(lo)) : count(uint64_t(lo)) + ".." + count(uint64_t(hi));
  out.push_back(o + ")");
  out.push_back("margin " + percent(mrg / 255.0) + " (" + std::to_string(mrg) + "/255) of the votes");
  return out;
}

namespace {

// Sample `i` of an image as a number.
double sampleAt(const vox::Image& img, size_t i) {
  switch (img.type) {
    case vox::SampleType::U8: return img.pixels[i];
    case vox::SampleType::U16: return reinterpret_cast<const uint16_t*>(img.pixels.data())[i];
    case vox::SampleType::U32: return reinterpret_cast<const uint32_t*>(img.pixels.data())[i];
    case vox::SampleType::F16: return vox::halfToFloat(reinterpret_cast<const uint16_t*>(img.pixels.data())[i]);
    case vox::SampleType::F32: return reinterpret_cast<const float*>(img.pixels.data())[i];
  }
  return 0;
}

nlohmann::json sampleJson(const vox::Image& img, size_t i) {
  switch (img.type) {
    case vox::SampleType::U8: return img.pixels[i];
    case vox::SampleType::U16: return reinterpret_cast<const uint16_t*>(img.pixels.data())[i];
    case vox::SampleType::U32: return reinterpret_cast<const uint32_t*>(img.pixels.data())[i];
    case vox::SampleType::F16: return vox::halfToFloat(reinterpret_cast<const uint16_t*>(img.pixels.data())[i]);
    case vox::SampleType::F32: return reinterpret_cast<const float*>(img.pixels.data())[i];
  }
  return nullptr;
}

bool isBitmap(vox::AtlasContent c) {
  return c == vox::AtlasContent::Occupancy || c == vox::AtlasContent::Occupancy2;
}

// What the channels (or bits) of each content mean, one line each.
std::vector<std::string> channelMeaning(const vox::AtlasImageInfo& info, const std::string& className) {
  switch (info.content) {
    case vox::AtlasContent::Summary:
      return {"R cls   class with the most votes (ties: lowest id); 0 = empty",
              "G conf  top votes / all votes, 255 = 100%",
              "B obs   16 log2(all votes + 1): 16 = 1 vote, 64 = 15, 128 = 255",
              "A mrg   (top - second) votes / all votes, 255 = 100%"};
    case vox::AtlasContent::Identity:
      return {"RGB     (u, v, w) of the texel's voxel", "A       full scale where occupied; 0 = empty"};
    case vox::AtlasContent::Color:
      return {"RGB     the voxel's colour, sRGB", "A       255 where the voxel has a colour; 0 = none or empty"};
    case vox::AtlasContent::Votes:
      return {"R       votes for " + className + " at the voxel (0 = none)"};
    case vox::AtlasContent::Occupancy:
      return {"1 bit per voxel, 8 voxels per byte along x: texel (x, y) is",
              "bit x & 7 of byte (x >> 3, y), bit 0 the lowest; 1 = occupied"};
    case vox::AtlasContent::Occupancy2:
      return {"2 bits per voxel, 4 voxels per byte along x: texel (x, y) is",
              "bits 2(x & 3) (occupied) and 2(x & 3) + 1 (touched by a camera",
              "path) of byte (x >> 2, y)"};
  }
  return {};
}

}  // namespace

int infoAtlas(const std::string& path, const vox::Image& img, const std::optional<PixelXY>& pixel,
              const std::string& sceneArg, bool asJson) {
  // The entry, checked against the image (so that every read below stays in
  // it): the reader diff and verify-bijection use too.
  const std::optional<vox::AtlasImageInfo> entry = vox::atlasInfoOfImage(img, path);
  if (!entry)
    throw vox::Error(vox::ErrorKind::BadInput,
                     path + ": an image without a 'vox:atlas' or 'vox:canonical' entry: not an atlas, bitmap or render "
                            "written by vox");
  const vox::AtlasImageInfo& info = *entry;
  const vox::AtlasLayout& L = info.layout;
  const bool bitmap = isBitmap(info.content);

  // Class names: from --scene, else from the scene the atlas names (as given,
  // then beside the atlas), when it is there. A scene of other dims is not the
  // one the atlas was built from (its names and votes would be another
  // scene's): refused when given, passed over when found.
  std::string classesFrom = sceneArg, foundOtherDims;
  std::optional<vox::ClassTable> classes;
  if (!sceneArg.empty()) {
    const std::optional<SceneFacts> facts = sceneFactsOf(sceneArg);
    if (!facts) throw vox::Error(vox::ErrorKind::BadInput, sceneArg + ": no such file (--scene)");
    if (!(facts->dims == L.dims))
      throw vox::Error(vox::ErrorKind::BadInput,
                       path + ": built for dims " + vox::toString(L.dims) + " but " + sceneArg + " has " +
                           vox::toString(facts->dims) + "; give --scene the scene the atlas was built from");
    classes = facts->classes;
  } else {
    for (const fs::path& p : {fs::path(info.scene), fs::path(path).parent_path() / fs::path(info.scene).filename()}) {
      std::optional<SceneFacts> facts;
      try {
        facts = sceneFactsOf(p.string());
      } catch (const vox::Error&) {
        facts.reset();  // not a scene after all: names stay unknown
      }
      if (facts && !(facts->dims == L.dims)) {
        if (foundOtherDims.empty()) foundOtherDims = p.string() + " has dims " + vox::toString(facts->dims);
        continue;
      }
      if (facts) {
        classes = facts->classes;
        classesFrom = p.string();
        break;
      }
    }
  }
  auto classLabel = [&](int id) {
    const vox::ClassInfo* ci = classes ? classes->find(uint8_t(id)) : nullptr;
    return ci ? ci->name + " (class " + std::to_string(id) + ")" : "class " + std::to_string(id);
  };

  nlohmann::json j = vox::atlasInfoJson(info);
  j["file"] = path;
  j["kind"] = "atlas";
  j["image"] = {{"width", img.width}, {"height", img.height}, {"channels", img.channels},
                {"sample", vox::sampleTypeName(img.type)}};
  j["file_bytes"] = vox::fileSizeOrMinusOne(path);
  if (classes) j["classes_from"] = classesFrom;
  if (!classes && !foundOtherDims.empty()) j["scene_not_used"] = foundOtherDims + ", not the atlas's";
  if (info.content == vox::AtlasContent::Votes) {
    const vox::ClassInfo* ci = classes ? classes->find(info.classId) : nullptr;
    j["class_name"] = ci ? nlohmann::json(ci->name) : nlohmann::json(nullptr);
  }

  // What the texels hold: one pass over the image.
  const uint64_t domainTexels = uint64_t(L.dims.x) * L.dims.y * L.dims.z;
  uint64_t occupied = 0, touched = 0;
  struct ClassCount {
    uint64_t texels = 0, conf = 0, obs = 0, mrg = 0;
  };
  std::array<ClassCount, 256> perClass{};
  double maxValue = 0, sumValue = 0;
  if (bitmap) {
    const int bits = info.content == vox::AtlasContent::Occupancy ? 1 : 2;
    for (uint8_t byte : img.pixels)
      for (int k = 0; k < 8; k += bits) {
        occupied += (byte >> k) & 1;
        if (bits == 2) touched += (byte >> (k + 1)) & 1;
      }
  } else {
    const size_t n = size_t(img.width) * img.height, ch = img.channels;
    for (size_t p = 0; p < n; ++p) {
      const size_t i = p * ch;
      switch (info.content) {
        case vox::AtlasContent::Summary: {
          const uint8_t* s = img.pixels.data() + i;
          if (s[0] | s[1] | s[2] | s[3]) {
            ++occupied;
            ClassCount& c = perClass[s[0]];
            ++c.texels, c.conf += s[1], c.obs += s[2], c.mrg += s[3];
          }
          break;
        }
        case vox::AtlasContent::Votes: {
          const double v = sampleAt(img, i);
          if (v != 0) ++occupied, sumValue += v, maxValue = std::max(maxValue, v);
          break;
        }
        default:  // identity, colour: alpha marks the texels that hold something
          if (sampleAt(img, i + ch - 1) != 0) ++occupied;
      }
    }
  }
  nlohmann::json texels = {{"nonzero", occupied}, {"atlas", uint64_t(L.width) * L.height}, {"domain", domainTexels}};
  if (info.content == vox::AtlasContent::Occupancy2) texels["touched"] = touched;
  if (info.content == vox::AtlasContent::Votes) texels["max_votes"] = maxValue, texels["sum_votes"] = sumValue;
  if (info.content == vox::AtlasContent::Summary) {
    nlohmann::json pc = nlohmann::json::array();
    for (int id = 0; id < 256; ++id) {
      const ClassCount& c = perClass[size_t(id)];
      if (!c.texels) continue;
      nlohmann::json e = {{"id", id}, {"texels", c.texels}, {"mean_conf", double(c.conf) / double(c.texels)},
                          {"mean_obs", double(c.obs) / double(c.texels)}, {"mean_mrg", double(c.mrg) / double(c.texels)}};
      const vox::ClassInfo* ci = classes ? classes->find(uint8_t(id)) : nullptr;
      if (ci) e["name"] = ci->name;
      pc.push_back(e);
    }
    texels["per_class"] = pc;
  }
  j["texels"] = texels;

  // --pixel x,y: the texel's voxel and values.
  if (pixel) {
    const uint32_t x = pixel->x, y = pixel->y;
    if (x >= L.width || y >= L.height)
      throw vox::Error(vox::ErrorKind::Usage, "--pixel " + pixel->text() + ": outside the " + std::to_string(L.width) +
                                                  " x " + std::to_string(L.height) + " atlas (x 0.." +
                                                  std::to_string(L.width - 1) + ", y 0.." +
                                                  std::to_string(L.height - 1) + ")");
    nlohmann::json p = {{"texel", {info.layer, x, y}}};
    const auto voxel = L.toVoxel(info.layer, uint32_t(x), uint32_t(y));
    p["voxel"] = voxel ? nlohmann::json{voxel->u, voxel->v, voxel->w} : nlohmann::json(nullptr);
    if (bitmap) {
      const uint32_t perByte = info.content == vox::AtlasContent::Occupancy ? 8 : 4;
      const uint8_t byte = img.pixels[size_t(y) * img.width + x / perByte];
      const int bits = 8 / int(perByte), shift = bits * int(x % perByte);
      p["occupied"] = bool((byte >> shift) & 1);
      if (bits == 2) p["touched"] = bool((byte >> (shift + 1)) & 1);
    } else {
      nlohmann::json values = nlohmann::json::array();
      const size_t base = (size_t(y) * img.width + x) * img.channels;
      for (uint32_t c = 0; c < img.channels; ++c) values.push_back(sampleJson(img, base + c));
      p["values"] = values;
      if (info.content == vox::AtlasContent::Summary) {
        p["summary"] = {{"cls", values[0]}, {"conf", values[1]}, {"obs", values[2]}, {"mrg", values[3]}};
        if (classes)
          if (const vox::ClassInfo* ci = classes->find(uint8_t(values[0].get<int>()))) p["summary"]["class_name"] = ci->name;
      }
    }
    if (!sceneArg.empty() && voxel && vox::looksLikeVdb(sceneArg)) {
      const vox::Scene scene = vox::readSceneVdb(sceneArg);
      std::vector<vox::ClassVotes> storage;
      const auto v = scene.voxel(*voxel, storage);
      if (!v) {
        p["scene_voxel"] = nullptr;
      } else {
        nlohmann::json votes = nlohmann::json::object();
        for (const vox::ClassVotes& c : v->votes) {
          const vox::ClassInfo* ci = scene.header().classes.find(c.classId);
          votes[ci ? ci->name : std::to_string(c.classId)] = c.votes;
        }
        p["scene_voxel"] = {{"surface", v->surface}, {"votes", votes}};
      }
    }
    j["pixel"] = p;
  }
  if (asJson) {
    std::cout << vox::jsonText(j, 2) << "\n";
    return kExitOk;
  }

  // Text.
  std::ostringstream o;
  const std::string className =
      info.content == vox::AtlasContent::Votes ? classLabel(info.classId) : std::string();
  o << heading(path, std::string(vox::atlasContentName(info.content)) + " atlas (" + info.format + ")" +
                          (info.content == vox::AtlasContent::Votes ? " of " + className : std::string()) + ", layer " +
                          std::to_string(info.layer) + " of " + std::to_string(L.layers));
  o << line("built from", info.scene + (classes                   ? ""
                                        : foundOtherDims.empty() ? "  (not found: class ids only; --scene S names them)"
                                                                 : "  (not this atlas's scene: class ids only)"));
  if (!classes && !foundOtherDims.empty()) o << line("", fit(foundOtherDims + ", not the atlas's", kWidth - 16));
  o << line("scene dims", std::to_string(L.dims.x) + " x " + std::to_string(L.dims.y) + " x " + std::to_string(L.dims.z) +
                              " voxels");
  o << line("atlas", std::to_string(L.width) + " x " + std::to_string(L.height) + " texels: " +
                         std::to_string(L.tilesPerRow) + (L.tilesPerRow == 1 ? " tile" : " tiles") + " of " +
                         std::to_string(L.dims.x) + " x " + std::to_string(L.dims.y) + " per row, " +
                         std::to_string(L.rowsPerLayer) + (L.rowsPerLayer == 1 ? " tile row" : " tile rows"));
  const int64_t fileBytes = vox::fileSizeOrMinusOne(path);
  o << line("image", std::to_string(img.width) + " x " + std::to_string(img.height) + " x " +
                         std::to_string(img.channels) + " " + vox::sampleTypeName(img.type) +
                         (fileBytes >= 0 ? ", " + bytes(uint64_t(fileBytes)) + " on disk" : ""));
  const std::vector<std::string> meaning = channelMeaning(info, className);
  for (size_t i = 0; i < meaning.size(); ++i) o << line(i ? "" : bitmap ? "bits" : "channels", meaning[i]);
  const std::string what = bitmap ? "bit set" : info.content == vox::AtlasContent::Votes ? "texel with votes" : "texel in use";
  const std::string whatMany = bitmap                                     ? "bits set"
                               : info.content == vox::AtlasContent::Votes ? "texels with votes"
                                                                          : "texels in use";
  o << line(bitmap ? "occupied" : "texels",
            countOf(occupied, what, whatMany) + " (" + percent(domainTexels ? double(occupied) / double(domainTexels) : 0) +
                " of the layout's voxels)");
  if (info.content == vox::AtlasContent::Occupancy2) o << line("touched", countOf(touched, "voxel", "voxels"));
  if (info.content == vox::AtlasContent::Votes && occupied)
    o << line("votes", "max " + count(uint64_t(maxValue)) + ", mean " +
                           (sumValue / double(occupied) >= 1000 ? count(uint64_t(sumValue / double(occupied) + 0.5))
                                                                : real(sumValue / double(occupied), 4)) +
                           " per texel with votes");
  if (info.content == vox::AtlasContent::Summary && occupied) {
    Table t({{"id", true}, {"class", false, true}, {"texels", true}, {"share", true}, {"conf", true},
             {"obs", true}, {"margin", true}});
    for (int id = 0; id < 256; ++id) {
      const ClassCount& c = perClass[size_t(id)];
      if (!c.texels) continue;
      const vox::ClassInfo* ci = classes ? classes->find(uint8_t(id)) : nullptr;
      const double n = double(c.texels);
      t.row({std::to_string(id), ci ? ci->name : id == 0 ? "(no votes)" : "?", count(c.texels),
             percent(double(c.texels) / double(occupied)), percent(double(c.conf) / n / 255.0), real(double(c.obs) / n, 3),
             percent(double(c.mrg) / n / 255.0)});
    }
    o << line("per class", "texels, and the mean confidence, observations and margin bytes:");
    o << t.str();
  }
  if (j.contains("pixel")) {
    const nlohmann::json& p = j["pixel"];
    std::string where = "(" + std::to_string(p["texel"][1].get<uint64_t>()) + ", " +
                        std::to_string(p["texel"][2].get<uint64_t>()) + ")";
    o << line("texel", where + (p["voxel"].is_null()
                                    ? ": padding, no voxel maps here"
                                    : " is voxel (" + p["voxel"][0].dump() + ", " + p["voxel"][1].dump() + ", " +
                                          p["voxel"][2].dump() + ")"));
    if (p.contains("occupied"))
      o << line("bits", std::string(p["occupied"].get<bool>() ? "occupied" : "empty") +
                            (p.contains("touched") ? p["touched"].get<bool>() ? ", touched" : ", not touched" : ""));
    if (p.contains("values")) {
      std::string v;
      for (const auto& x : p["values"]) v += (v.empty() ? "" : ", ") + x.dump();
      o << line("values", "(" + v + ")");
    }
    if (p.contains("summary")) {
      const auto& s = p["summary"];
      const auto lines = explainSummary(s["cls"].get<int>(), s["conf"].get<int>(), s["obs"].get<int>(),
                                        s["mrg"].get<int>(), classes ? &*classes : nullptr);
      for (size_t i = 0; i < lines.size(); ++i) o << line(i ? "" : "meaning", lines[i]);
    }
    if (p.contains("scene_voxel")) {
      if (p["scene_voxel"].is_null()) {
        o << line("in the scene", "empty");
      } else {
        std::string v;
        for (const auto& [name, n] : p["scene_voxel"]["votes"].items()) v += (v.empty() ? "" : ", ") + name + " " + n.dump();
        o << line("in the scene", std::string(p["scene_voxel"]["surface"].get<bool>() ? "surface" : "interior") +
                                      " voxel; votes " + v);
      }
    }
  }
  std::cout << o.str();
  return kExitOk;
}

}  // namespace voxcli
