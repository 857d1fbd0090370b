// vox info FILE: what a file holds, for people (default) or scripts (--json).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "formats/core/file_kinds.h"
#include "formats/core/file_util.h"
#include "formats/image/atlas_meta.h"
#include "formats/image/image.h"
#include "formats/image/render_meta.h"
#include "formats/pagefile/pagefile.h"
#include "formats/scene/class_table_json.h"
#include "formats/vdb/scene_vdb.h"
#include "formats/vdb/vdb_structure.h"
#include "libvox/core/error.h"
#include "libvox/core/texel_formats.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"
#include "tools/cmds/info_canonical.h"
#include "tools/cmds/info_pages.h"

namespace voxcli {

namespace {

struct InfoOptions {
  std::string file;
  bool json = false;
  std::string pixel;  // "x,y" for atlases
  std::string scene;  // with --pixel: the scene, for class names and votes
};

int infoAtlas(const InfoOptions& o) {
  vox::AtlasImageInfo info;
  const vox::Image img = vox::readAtlasImage(o.file, info);
  nlohmann::json j = vox::atlasInfoJson(info);
  j["file"] = o.file;
  j["kind"] = "atlas";
  j["image"] = {{"width", img.width}, {"height", img.height}, {"channels", img.channels},
                {"sample", vox::sampleTypeName(img.type)}};
  j["file_bytes"] = vox::fileSizeOrMinusOne(o.file);
  if (!o.pixel.empty()) {
    const size_t comma = o.pixel.find(',');
    char* end = nullptr;
    const unsigned long x = std::strtoul(o.pixel.c_str(), &end, 10);
    const unsigned long y = comma == std::string::npos ? 0 : std::strtoul(o.pixel.c_str() + comma + 1, &end, 10);
    if (comma == std::string::npos || *end != '\0' || x >= info.layout.width || y >= info.layout.height)
      throw vox::Error(vox::ErrorKind::Usage, "--pixel " + o.pixel + ": expected x,y inside the " +
                                                  std::to_string(info.layout.width) + " x " +
                                                  std::to_string(info.layout.height) + " atlas");
    nlohmann::json p = {{"texel", {info.layer, x, y}}};
    const auto voxel = info.layout.toVoxel(info.layer, uint32_t(x), uint32_t(y));
    p["voxel"] = voxel ? nlohmann::json{voxel->u, voxel->v, voxel->w} : nlohmann::json(nullptr);
    const bool bitmap = info.content == vox::AtlasContent::Occupancy || info.content == vox::AtlasContent::Occupancy2;
    if (bitmap) {
      const uint32_t perByte = info.content == vox::AtlasContent::Occupancy ? 8 : 4;
      const uint8_t byte = img.pixels[size_t(y) * img.width + x / perByte];
      const int bits = 8 / int(perByte), shift = bits * int(x % perByte);
      p["occupied"] = bool((byte >> shift) & 1);
      if (bits == 2) p["touched"] = bool((byte >> (shift + 1)) & 1);
    } else {
      nlohmann::json values = nlohmann::json::array();
      const size_t base = (size_t(y) * img.width + x) * img.channels;
      for (uint32_t c = 0; c < img.channels; ++c) {
        const size_t i = base + c;
        switch (img.type) {
          case vox::SampleType::U8: values.push_back(img.pixels[i]); break;
          case vox::SampleType::U16: values.push_back(reinterpret_cast<const uint16_t*>(img.pixels.data())[i]); break;
          case vox::SampleType::U32: values.push_back(reinterpret_cast<const uint32_t*>(img.pixels.data())[i]); break;
          case vox::SampleType::F16: values.push_back(vox::halfToFloat(reinterpret_cast<const uint16_t*>(img.pixels.data())[i])); break;
          case vox::SampleType::F32: values.push_back(reinterpret_cast<const float*>(img.pixels.data())[i]); break;
        }
      }
      p["values"] = values;
      if (info.content == vox::AtlasContent::Summary)
        p["summary"] = {{"cls", values[0]}, {"conf", values[1]}, {"obs", values[2]}, {"mrg", values[3]}};
    }
    if (!o.scene.empty() && voxel) {
      const vox::Scene scene = vox::readSceneVdb(o.scene);
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
        if (p.contains("summary")) {
          const vox::ClassInfo* ci = scene.header().classes.find(uint8_t(p["summary"]["cls"].get<int>()));
          if (ci) p["summary"]["class_name"] = ci->name;
        }
      }
    }
    j["pixel"] = p;
  }
  if (o.json) {
    std::cout << j.dump(2) << "\n";
    return kExitOk;
  }
  const vox::AtlasLayout& L = info.layout;
  std::cout << o.file << ": " << vox::atlasContentName(info.content) << " atlas (" << info.format << "), layer "
            << info.layer << " of " << L.layers << "\n"
            << "  scene dims    " << vox::toString(L.dims) << "\n"
            << "  atlas         " << L.width << " x " << L.height << ", " << L.tilesPerRow << " tiles per row, "
            << L.rowsPerLayer << " tile rows per layer\n"
            << "  image         " << img.width << " x " << img.height << " x " << img.channels << " "
            << vox::sampleTypeName(img.type) << "\n"
            << "  built from    " << info.scene << "\n";
  if (j.contains("pixel")) std::cout << "  pixel         " << j["pixel"].dump() << "\n";
  return kExitOk;
}

nlohmann::json sceneJson(const std::string& path, const vox::Scene& scene) {
  const vox::SceneHeader& h = scene.header();
  const vox::SceneStats s = scene.stats();
  nlohmann::json j;
  j["file"] = path;
  j["kind"] = "scene";
  j["file_bytes"] = vox::fileSizeOrMinusOne(path);
  j["dims"] = {h.dims.x, h.dims.y, h.dims.z};
  j["voxel_size"] = h.voxelSize;
  j["origin"] = h.origin;
  j["world_bounds"] = {
      {"min", h.origin},
      {"max", {h.origin[0] + h.dims.x * h.voxelSize, h.origin[1] + h.dims.y * h.voxelSize,
               h.origin[2] + h.dims.z * h.voxelSize}}};
  j["mip_level"] = h.mipLevel;
  if (h.blockWorld)
    j["block_world"] = {{"world_scale", h.blockWorld->worldScale}, {"grid_size", h.blockWorld->gridSize}};
  j["occupied"] = s.occupied;
  j["surface"] = s.surface;
  j["interior"] = s.occupied - s.surface;
  j["colored"] = s.colored;
  j["has_color"] = scene.hasColor();
  if (s.bounds.empty())
    j["bounds"] = nullptr;
  else
    j["bounds"] = {{"min", {s.bounds.min.u, s.bounds.min.v, s.bounds.min.w}},
                   {"max", {s.bounds.max.u, s.bounds.max.v, s.bounds.max.w}}};
  nlohmann::json classes = nlohmann::json::array();
  for (const vox::ClassInfo& c : h.classes.classes()) {
    // The stored class entry, with the face palette grouped under "faces", and the counts.
    nlohmann::json cj = vox::classInfoToJson(c);
    if (c.faces) {
      nlohmann::json faces;
      for (const char* face : {"top", "bottom", "side"}) {
        faces[face] = cj[face];
        cj.erase(face);
      }
      cj["faces"] = faces;
    }
    cj["voxels"] = 0;
    cj["mode_voxels"] = 0;
    cj["votes"] = 0;
    for (const auto& p : s.perClass)
      if (p.classId == c.id) {
        cj["voxels"] = p.voxelsWithVotes;
        cj["mode_voxels"] = p.modeVoxels;
        cj["votes"] = p.votes;
      }
    classes.push_back(cj);
  }
  j["classes"] = classes;
  j["memory_bytes"] = s.memoryBytes;
  nlohmann::json sources = nlohmann::json::array();
  for (const vox::SceneSource& src : h.sources)
    sources.push_back({{"path", src.path}, {"kind", src.kind}, {"sha256", src.sha256}, {"bytes", src.bytes}});
  j["sources"] = sources;
  return j;
}

std::string humanBytes(uint64_t b) {
  char buf[64];
  if (b < 10 * 1024) std::snprintf(buf, sizeof buf, "%llu B", (unsigned long long)b);
  else if (b < 10ull * 1024 * 1024) std::snprintf(buf, sizeof buf, "%.1f KiB", b / 1024.0);
  else std::snprintf(buf, sizeof buf, "%.1f MiB", b / 1048576.0);
  return buf;
}

void printScene(const nlohmann::json& j) {
  std::ostringstream o;
  auto v3 = [](const nlohmann::json& a) {
    std::ostringstream s;
    s << "(" << a[0].dump() << ", " << a[1].dump() << ", " << a[2].dump() << ")";
    return s.str();
  };
  const uint64_t domain = j["dims"][0].get<uint64_t>() * j["dims"][1].get<uint64_t>() * j["dims"][2].get<uint64_t>();
  const uint64_t occupied = j["occupied"];
  o << j["file"].get<std::string>() << ": voxbake scene\n";
  o << "  dims          " << j["dims"][0] << " x " << j["dims"][1] << " x " << j["dims"][2] << " (" << domain
    << " voxels)\n";
  o << "  voxel size    " << j["voxel_size"].get<double>() << " world units\n";
  o << "  world bounds  " << v3(j["world_bounds"]["min"]) << " .. " << v3(j["world_bounds"]["max"]) << "\n";
  if (j.contains("block_world"))
    o << "  block world   worldScale " << j["block_world"]["world_scale"].get<double>() << ", grid "
      << j["block_world"]["grid_size"][0] << "," << j["block_world"]["grid_size"][1] << ","
      << j["block_world"]["grid_size"][2] << " (block-map placement)\n";
  if (j["mip_level"].get<int>() != 0) o << "  mip level     " << j["mip_level"] << "\n";
  char pct[32];
  std::snprintf(pct, sizeof pct, "%.3f%%", domain ? 100.0 * double(occupied) / double(domain) : 0.0);
  o << "  occupied      " << occupied << " (" << pct << " of the domain): " << j["surface"] << " surface, "
    << j["interior"] << " interior" << (j["has_color"].get<bool>() ? ", " + j["colored"].dump() + " coloured" : "")
    << "\n";
  if (j["bounds"].is_null())
    o << "  bounds        (empty scene)\n";
  else
    o << "  bounds        " << v3(j["bounds"]["min"]) << " .. " << v3(j["bounds"]["max"]) << " (index, inclusive)\n";
  o << "  classes       " << j["classes"].size() << "\n";
  char line[256];
  std::snprintf(line, sizeof line, "    %3s  %-14s %-9s %12s %12s %14s\n", "id", "name", "colour", "voxels",
                "mode voxels", "votes");
  o << line;
  for (const auto& c : j["classes"]) {
    char hex[16];
    std::snprintf(hex, sizeof hex, "#%02x%02x%02x", c["color"][0].get<int>(), c["color"][1].get<int>(),
                  c["color"][2].get<int>());
    std::snprintf(line, sizeof line, "    %3d  %-14s %-9s %12llu %12llu %14llu\n", c["id"].get<int>(),
                  c["name"].get<std::string>().c_str(), hex, (unsigned long long)c["voxels"].get<uint64_t>(),
                  (unsigned long long)c["mode_voxels"].get<uint64_t>(), (unsigned long long)c["votes"].get<uint64_t>());
    o << line;
  }
  o << "  memory        " << humanBytes(j["memory_bytes"]) << " in OpenVDB trees; file "
    << humanBytes(j["file_bytes"].get<int64_t>() < 0 ? 0 : j["file_bytes"].get<uint64_t>()) << "\n";
  for (const auto& s : j["sources"]) {
    o << "  source        " << s["path"].get<std::string>() << " (" << s["kind"].get<std::string>();
    if (!s["sha256"].get<std::string>().empty()) o << ", sha256 " << s["sha256"].get<std::string>().substr(0, 16) << "…";
    o << ")\n";
  }
  std::cout << o.str();
}

int runInfo(const InfoOptions& o) {
  vox::requireRegularFile(o.file);
  if (vox::isPngFile(o.file) || vox::isExrFile(o.file)) {
    const vox::Image img = vox::isPngFile(o.file) ? vox::readPng(o.file) : vox::readExr(o.file);
    if (!img.textValue(vox::kRenderMetaKey).empty()) return infoCanonical(o.file, img, o.pixel, o.scene, o.json);
    return infoAtlas(o);
  }
  if (vox::pagefile::looksLikePageFile(o.file)) return infoPageFile(o.file, o.json);
  if (!o.pixel.empty()) throw vox::Error(vox::ErrorKind::Usage, "--pixel applies to atlas images");
  if (!vox::looksLikeVdb(o.file))
    throw vox::Error(vox::ErrorKind::BadInput, o.file + ": not a file vox knows (expected " +
                                                   vox::describe(vox::FileKind::Vdb) + ", " +
                                                   vox::describe(vox::FileKind::Image) + " or " +
                                                   vox::describe(vox::FileKind::PageFile) + ")");
  // A .vdb without voxbake metadata (a level set, a fog volume): list its grids.
  const vox::VdbFrame frame = vox::checkVdbStructure(o.file);
  if (std::find(frame.metadataNames.begin(), frame.metadataNames.end(), "vox:format") == frame.metadataNames.end()) {
    nlohmann::json j = {{"file", o.file},
                        {"kind", "openvdb"},
                        {"file_bytes", vox::fileSizeOrMinusOne(o.file)},
                        {"file_version", frame.fileVersion},
                        {"library_version", std::to_string(frame.libraryMajor) + "." + std::to_string(frame.libraryMinor)}};
    nlohmann::json grids = nlohmann::json::array();
    for (const vox::VdbGridFrame& g : frame.grids) grids.push_back({{"name", g.uniqueName}, {"type", g.type}});
    j["grids"] = grids;
    if (o.json) {
      std::cout << j.dump(2) << "\n";
    } else {
      std::cout << o.file << ": OpenVDB file (format " << frame.fileVersion << "), not a voxbake scene\n";
      for (const vox::VdbGridFrame& g : frame.grids) std::cout << "  grid  " << g.uniqueName << "  (" << g.type << ")\n";
      std::cout << "  make a scene of it with: vox voxelize " << o.file << " --res N -o scene.vdb\n";
    }
    return kExitOk;
  }
  const vox::Scene scene = vox::readSceneVdb(o.file);
  nlohmann::json j = sceneJson(o.file, scene);
  const nlohmann::json pyramid = pyramidInfoJson(o.file);  // `vox mip` files: the levels above 0
  if (!pyramid.is_null()) j["pyramid"] = pyramid;
  if (o.json)
    std::cout << j.dump(2) << "\n";
  else
    printScene(j);
  if (!o.json && !pyramid.is_null()) std::cout << pyramidInfoText(pyramid);
  return kExitOk;
}

}  // namespace

Command registerInfo(CLI::App& root) {
  auto opts = std::make_shared<InfoOptions>();
  CLI::App* cmd = root.add_subcommand("info", "Describe a scene or pyramid (.vdb), an OpenVDB file, an atlas (.png/.exr) or a page file (.vpk)");
  cmd->add_option("file", opts->file, "File to describe")->required();
  cmd->add_flag("--json", opts->json, "Print JSON on stdout instead of a summary");
  cmd->add_option("--pixel", opts->pixel, "Atlases: decode texel x,y to its voxel and values; canonical renders: the voxel under pixel x,y");
  cmd->add_option("--scene", opts->scene, "With --pixel: the scene (or page file), for class names, summary and votes");
  return {cmd, [opts] { return runInfo(*opts); }};
}

}  // namespace voxcli
