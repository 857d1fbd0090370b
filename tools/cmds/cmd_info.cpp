// vox info FILE: what a file holds, for people (default) or scripts (--json).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

#include "formats/core/file_kinds.h"
#include "formats/core/file_util.h"
#include "formats/core/json_input.h"
#include "formats/core/json_text.h"
#include "formats/image/atlas_meta.h"
#include "formats/image/atlas_preview.h"
#include "formats/image/image.h"
#include "formats/image/render_meta.h"
#include "formats/pagefile/pagefile.h"
#include "formats/scene/class_table_json.h"
#include "formats/scene/scene_meta.h"
#include "formats/vdb/fuse_vdb.h"
#include "formats/vdb/scene_vdb.h"
#include "formats/vdb/vdb_memory.h"
#include "formats/vdb/vdb_structure.h"
#include "libvox/core/error.h"
#include "libvox/core/texel_formats.h"
#include "libvox/core/memory_budget.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"
#include "tools/cmds/info_atlas.h"
#include "tools/cmds/info_canonical.h"
#include "tools/cmds/info_json_files.h"
#include "tools/cmds/info_pages.h"
#include "tools/cmds/info_pixel.h"
#include "tools/cmds/info_text.h"

namespace voxcli {

namespace {

struct InfoOptions {
  std::string file;
  bool json = false;
  std::string pixel;  // "x,y" for atlases and canonical renders
  std::string scene;  // atlases: the scene, for class names and votes; renders: with --pixel
  CLI::Option* pixelOption = nullptr;  // given, even as "": parsed (an empty text is refused, not ignored)
  CLI::Option* sceneOption = nullptr;
  std::string maxMemory;  // --max-memory (info has no other common option)
};

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
  if (h.region) j["region"] = nlohmann::json::parse(vox::regionJson(*h.region));
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

std::string v3(const nlohmann::json& a) {
  return infotext::triple(a[0].get<double>(), a[1].get<double>(), a[2].get<double>(), 6);
}

std::string dimsText(const nlohmann::json& d) {
  return d[0].dump() + " x " + d[1].dump() + " x " + d[2].dump();
}

void printScene(const nlohmann::json& j) {
  using namespace infotext;
  std::ostringstream o;
  const uint64_t domain = j["dims"][0].get<uint64_t>() * j["dims"][1].get<uint64_t>() * j["dims"][2].get<uint64_t>();
  const uint64_t occupied = j["occupied"], surface = j["surface"], interior = j["interior"];
  o << heading(j["file"].get<std::string>(), "voxbake scene");
  o << line("dims", dimsText(j["dims"]) + " (" + countOf(domain, "voxel", "voxels") + ")");
  o << line("voxel size", measured(j["voxel_size"].get<double>(), 6, "world unit", "world units"));
  o << line("world bounds", v3(j["world_bounds"]["min"]) + " .. " + v3(j["world_bounds"]["max"]));
  if (j.contains("block_world"))
    o << line("block world", "worldScale " + real(j["block_world"]["world_scale"].get<double>(), 6) + ", grid " +
                                 j["block_world"]["grid_size"][0].dump() + "," + j["block_world"]["grid_size"][1].dump() +
                                 "," + j["block_world"]["grid_size"][2].dump() + " (block-map placement)");
  if (j["mip_level"].get<int>() != 0) o << line("mip level", j["mip_level"].dump());
  if (j.contains("region")) o << line("region", regionText(j["region"]));
  o << line("occupied", countOf(occupied, "voxel", "voxels") + " (" + percent(domain ? double(occupied) / double(domain) : 0.0) +
                            " of the domain)");
  o << line("", count(surface) + " surface (" + percent(occupied ? double(surface) / double(occupied) : 0.0) + "), " +
                    count(interior) + " interior");
  if (j["has_color"].get<bool>())
    o << line("colour", countOf(j["colored"].get<uint64_t>(), "voxel", "voxels") + " coloured (" +
                            percent(occupied ? double(j["colored"].get<uint64_t>()) / double(occupied) : 0.0) + ")");
  else
    o << line("colour", "none (class colours only)");
  if (j["bounds"].is_null())
    o << line("bounds", "(empty scene)");
  else
    o << line("bounds", v3(j["bounds"]["min"]) + " .. " + v3(j["bounds"]["max"]) + " (index, inclusive)");
  if (j.contains("free_grid"))
    o << line("free grid", "'" + std::string(vox::kFreeGridName) + "' (" + j["free_grid"]["type"].get<std::string>() + ", " +
                               count(j["free_grid"]["leaves"].get<uint64_t>()) +
                               " leaves of 8^3): vox fuse's free-space counts, read back by vox fuse -i (docs/fuse.md)");
  const int64_t fileBytes = j["file_bytes"].get<int64_t>();
  // Two figures, because commands read scenes in two forms: OpenVDB trees
  // (fuse -i, merge, diff, build-atlas...) and the leaf readers' packed
  // leaves (mip, pack-chunks, render-canonical, export), often 5x smaller.
  o << line("memory", bytes(j["memory_bytes"].get<uint64_t>()) + " in OpenVDB trees, " +
                          bytes(j["packed_leaf_bytes"].get<uint64_t>()) + " as packed leaves" +
                          (fileBytes >= 0 ? "; file " + bytes(uint64_t(fileBytes)) : ""));
  o << line("classes", std::to_string(j["classes"].size()) +
                           (j["classes"].empty() ? "" : ": voxels with a vote, voxels the class wins, votes"));
  if (!j["classes"].empty()) {
    Table t({{"id", true}, {"name", false, true}, {"colour", false}, {"voxels", true}, {"share", true},
             {"wins", true}, {"votes", true}});
    for (const auto& c : j["classes"]) {
      const uint64_t v = c["voxels"], wins = c["mode_voxels"], votes = c["votes"];
      t.row({c["id"].dump(), c["name"].get<std::string>(),
             hexColor(c["color"][0].get<int>(), c["color"][1].get<int>(), c["color"][2].get<int>()), count(v),
             percent(occupied ? double(v) / double(occupied) : 0.0), count(wins), compact(votes)});
    }
    o << t.str();
  }
  for (const auto& s : j["sources"]) {
    std::string text = s["path"].get<std::string>() + " (" + s["kind"].get<std::string>();
    if (s["bytes"].get<uint64_t>()) text += ", " + bytes(s["bytes"].get<uint64_t>());
    if (!s["sha256"].get<std::string>().empty()) text += ", sha256 " + s["sha256"].get<std::string>().substr(0, 12) + "…";
    o << line("source", fit(text + ")", infotext::kWidth - 16));
  }
  std::cout << o.str();
}

/// --pixel and --scene decode atlases and canonical renders (--scene with a
/// render: with --pixel): given with `what`, another kind, they are refused
/// rather than ignored.
void refusePixelAndScene(const InfoOptions& o, const std::string& what) {
  if (o.pixelOption->count() > 0)
    throw vox::Error(vox::ErrorKind::Usage, "--pixel applies to atlases and canonical renders, not to " + what);
  if (o.sceneOption->count() > 0)
    throw vox::Error(vox::ErrorKind::Usage, "--scene applies to atlases and canonical renders, not to " + what);
}

/// Every kind `vox info` reads, for the "unsupported file" message.
std::string kindsRead() {
  return "a scene or pyramid (.vdb), an OpenVDB grid file (.vdb), an atlas or occupancy bitmap (.png, .exr), a "
         "canonical render (.png, .exr), a page file (.vpk), a touched set (.json from render-canonical --touched), an "
         "atlas sidecar (STEM.atlas.json) or a run report (.json from --report)";
}

int infoJsonFile(const InfoOptions& o) {
  nlohmann::json doc;
  try {
    doc = vox::parseJsonInput(vox::readFileBytes(o.file), o.file);
  } catch (const nlohmann::json::exception& e) {
    throw vox::Error(vox::ErrorKind::BadInput, o.file + ": not valid JSON (" + e.what() + "); vox info reads " + kindsRead());
  }
  const std::string kind = voxJsonKind(doc);
  if (kind.empty())
    throw vox::Error(vox::ErrorKind::BadInput,
                     o.file + ": a JSON file vox info does not know (not a touched set, \"format\": "
                              "\"voxbake-touched\", an atlas sidecar or a report, \"tool\": \"vox\"); vox info reads " +
                         kindsRead());
  refusePixelAndScene(o, kind == "atlas_sidecar" ? "an atlas sidecar" : kind == "touched" ? "a touched set" : "a report");
  if (kind == "atlas_sidecar") return infoAtlasSidecar(o.file, o.json);
  return kind == "touched" ? infoTouchedSet(o.file, o.json) : infoReport(o.file, doc, o.json);
}

int runInfo(const InfoOptions& o) {
  vox::setProcessMemoryLimit(vox::memoryLimitFrom(o.maxMemory, "--max-memory"), "--max-memory");
  std::optional<PixelXY> pixel;
  if (o.pixelOption->count() > 0) pixel = parsePixel(o.pixel);
  if (o.sceneOption->count() > 0 && o.scene.empty())
    throw vox::Error(vox::ErrorKind::Usage, "--scene '': an empty path; give the scene or page file");
  vox::requireRegularFile(o.file);
  // --scene is an input like FILE: a directory or a FIFO is refused up front
  // (it was passed over, and the atlas's own scene reported "not found").
  if (!o.scene.empty()) try {
      vox::requireRegularFile(o.scene);
    } catch (const vox::Error& e) {
      throw vox::Error(e.kind, std::string(e.what()) + " (--scene)");
    }
  if (vox::isPngFile(o.file) || vox::isExrFile(o.file)) {
    const vox::Image img = vox::isPngFile(o.file) ? vox::readPng(o.file) : vox::readExr(o.file);
    if (!img.textValue(vox::kRenderMetaKey).empty()) return infoCanonical(o.file, img, pixel, o.scene, o.json);
    if (const std::string preview = img.textValue(vox::kPreviewTextKey); !preview.empty()) {
      // A build-atlas --preview image: for looking at, not for sampling.
      refusePixelAndScene(o, "a preview (a picture of an atlas: give the atlas itself)");
      nlohmann::json j = vox::parseJsonInputOrDiscarded(preview, o.file + ": its 'vox:preview' entry");
      if (j.is_discarded() || !j.is_object())
        throw vox::Error(vox::ErrorKind::BadInput, o.file + ": its 'vox:preview' entry is not a JSON object");
      j["file"] = o.file;
      j["kind"] = "preview";
      j["image"] = {{"width", img.width}, {"height", img.height}, {"channels", img.channels}};
      if (o.json) {
        std::cout << vox::jsonText(j, 2) << "\n";
      } else {
        std::cout << infotext::heading(o.file, "preview of " + j.value("atlas", std::string("?")) + " (" +
                                                     j.value("content", std::string("?")) + "), " +
                                                     std::to_string(img.width) + " x " + std::to_string(img.height) +
                                                     (img.channels == 1 ? " gray" : " RGB"))
                  << infotext::line("note", "a picture for people; vox info the atlas itself to decode texels");
        for (const auto& [k, v] : j.items()) {
          if (k == "atlas" || k == "content" || k == "file" || k == "kind" || k == "image") continue;
          if (!v.is_array()) {
            std::cout << infotext::line(k, v.is_string() ? v.get<std::string>() : v.dump());
            continue;
          }
          for (size_t i = 0; i < v.size(); ++i)
            std::cout << infotext::line(i ? "" : k, v[i].is_string() ? v[i].get<std::string>() : v[i].dump());
        }
      }
      return kExitOk;
    }
    return infoAtlas(o.file, img, pixel, o.scene, o.json);
  }
  if (vox::pagefile::looksLikePageFile(o.file)) {
    refusePixelAndScene(o, "a page file (.vpk)");
    return infoPageFile(o.file, o.json);
  }
  if (vox::hasExtension(o.file, ".json")) return infoJsonFile(o);
  if (!vox::looksLikeVdb(o.file))
    throw vox::Error(vox::ErrorKind::BadInput, o.file + ": not a file vox info reads; it reads " + kindsRead());
  // A .vdb without voxbake metadata (a level set, a fog volume): list its
  // grids, walked whole. A scene is walked while it is read (readSceneVdb):
  // here only its framing.
  vox::VdbFrame frame = vox::checkVdbStructure(o.file, vox::VdbCheck::Framing);
  refusePixelAndScene(o, "a scene or OpenVDB file (.vdb)");
  if (std::find(frame.metadataNames.begin(), frame.metadataNames.end(), "vox:format") == frame.metadataNames.end()) {
    frame = vox::checkVdbStructure(o.file);
    nlohmann::json j = {{"file", o.file},
                        {"kind", "openvdb"},
                        {"file_bytes", vox::fileSizeOrMinusOne(o.file)},
                        {"file_version", frame.fileVersion},
                        {"library_version", std::to_string(frame.libraryMajor) + "." + std::to_string(frame.libraryMinor)}};
    nlohmann::json grids = nlohmann::json::array();
    for (const vox::VdbGridFrame& g : frame.grids) grids.push_back({{"name", g.uniqueName}, {"type", g.type}});
    j["grids"] = grids;
    if (o.json) {
      std::cout << vox::jsonText(j, 2) << "\n";
    } else {
      std::cout << infotext::heading(o.file, "OpenVDB file (format " + std::to_string(frame.fileVersion) +
                                                  "), not a voxbake scene");
      infotext::Table t({{"grid", false, true}, {"type", false}});
      for (const vox::VdbGridFrame& g : frame.grids) t.row({g.uniqueName, g.type});
      std::cout << infotext::line("grids", std::to_string(frame.grids.size())) << t.str();
      // voxelize reads the first float or double grid (formats/vdb/vdb_grid_input.h).
      const bool scalar = std::any_of(frame.grids.begin(), frame.grids.end(), [](const vox::VdbGridFrame& g) {
        return g.type.rfind("Tree_float_", 0) == 0 || g.type.rfind("Tree_double_", 0) == 0;
      });
      if (scalar)
        std::cout << "  make a scene of it with: vox voxelize " << o.file
                  << " --res N -o scene.vdb  (a fog volume also needs --threshold T)\n";
      else
        std::cout << "  vox voxelize reads float and double grids (level sets, fog volumes); this file has none\n";
    }
    return kExitOk;
  }
  const vox::Scene scene = vox::readSceneVdb(o.file);
  nlohmann::json j = sceneJson(o.file, scene);
  // The whole walk (remembered from the read above): leaf counts per grid.
  const vox::VdbFrame full = vox::checkVdbStructure(o.file);
  // Level 0's grids, as memory_bytes counts them: a pyramid's levels above are left out.
  vox::VdbFrame level0 = full;
  std::erase_if(level0.grids, [](const vox::VdbGridFrame& g) { return vox::hasPyramidLevelPrefix(g.uniqueName); });
  j["packed_leaf_bytes"] = uint64_t(vox::sceneGridBytes(level0, false, vox::SceneReadForm::PackedLeaves) + 0.5);
  for (const vox::VdbGridFrame& g : full.grids)
    if (g.uniqueName == vox::kFreeGridName)  // a `vox fuse` output
      j["free_grid"] = {{"type", g.type}, {"leaves", g.leafCount}};
  const nlohmann::json pyramid = pyramidInfoJson(o.file);  // `vox mip` files: the levels above 0
  if (!pyramid.is_null()) j["pyramid"] = pyramid;
  if (o.json)
    std::cout << vox::jsonText(j, 2) << "\n";
  else
    printScene(j);
  if (!o.json && !pyramid.is_null()) std::cout << pyramidInfoText(pyramid);
  return kExitOk;
}

}  // namespace

Command registerInfo(CLI::App& root) {
  auto opts = std::make_shared<InfoOptions>();
  CLI::App* cmd = root.add_subcommand(
      "info", "Describe a scene or pyramid (.vdb), an OpenVDB file, an atlas or bitmap (.png/.exr), a canonical render, "
              "a page file (.vpk), a touched set, atlas sidecar or run report (.json)");
  cmd->add_option("file", opts->file, "File to describe")->required();
  cmd->add_flag("--json", opts->json, "Print JSON on stdout instead of a summary");
  opts->pixelOption = cmd->add_option(
      "--pixel", opts->pixel,
      "Atlases: decode texel x,y to its voxel and values; canonical renders: the voxel under pixel x,y");
  opts->sceneOption = cmd->add_option(
      "--scene", opts->scene,
      "Atlases: the scene (or page file) built from, for class names and, with --pixel, votes (default: the scene "
      "they name, when it exists with their dims); canonical renders, with --pixel: the scene rendered");
  addMaxMemoryOption(*cmd, opts->maxMemory);
  return {cmd, [opts] { return runInfo(*opts); }};
}

}  // namespace voxcli
