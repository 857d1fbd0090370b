#include "tools/cmds/info_pages.h"

#include <cstdio>
#include <iostream>
#include <sstream>

#include "formats/core/json_input.h"
#include "formats/core/json_text.h"
#include "formats/pagefile/pagefile.h"
#include "formats/pagefile/pagefile_meta.h"
#include "formats/scene/scene_meta.h"
#include "formats/vdb/pyramid_vdb.h"
#include "libvox/core/error.h"
#include "tools/cli/cli.h"
#include "tools/cmds/info_text.h"

namespace voxcli {

namespace {

// Per level of the index: chunks, full chunks, voxels, payload bytes.
nlohmann::json levelsJson(const vox::pagefile::Reader& r) {
  const vox::pagefile::Header& h = r.header();
  nlohmann::json levels = nlohmann::json::array();
  for (int l = 0; l < h.levelCount; ++l) {
    const auto [a, b] = r.levelRange(l);
    uint64_t v = 0, bytes = 0, full = 0;
    for (size_t i = a; i < b; ++i) {
      v += r.entries()[i].occupied;
      bytes += r.entries()[i].size;
      full += (r.entries()[i].flags & vox::pagefile::kChunkFull) ? 1 : 0;
    }
    const auto d = h.levelDims(l);
    levels.push_back({{"level", l}, {"dims", d}, {"voxel_size", h.voxelSize * double(uint64_t(1) << l)},
                      {"chunks", b - a}, {"full_chunks", full}, {"voxels", v}, {"payload_bytes", bytes},
                      {"bytes_per_voxel", v ? double(bytes) / double(v) : 0.0}});
  }
  return levels;
}

// What `vox info --json` prints: the header, the index per level, the metadata.
nlohmann::json pageFileJson(const std::string& path, const vox::pagefile::Reader& r, const vox::pagefile::PageMeta& meta) {
  const vox::pagefile::Header& h = r.header();
  nlohmann::json j;
  j["file"] = path;
  j["kind"] = "pagefile";
  j["version"] = vox::pagefile::kVersion;
  j["layout"] = vox::pagefile::layoutName(h.layout);
  j["chunk"] = h.chunkSide();
  j["align"] = 1u << h.alignLog2;
  j["dims"] = h.dims;
  j["voxel_size"] = h.voxelSize;
  j["origin"] = h.origin;
  j["channels"] = nlohmann::json::array({"occupancy", "summary"});
  if (h.flags & vox::pagefile::kFlagColor) j["channels"].push_back("color");
  if (h.flags & vox::pagefile::kFlagSurface) j["channels"].push_back("surface");
  j["file_bytes"] = h.fileBytes;
  j["header_bytes"] = vox::pagefile::kHeaderBytes;
  j["index_bytes"] = h.chunkCount * vox::pagefile::kIndexEntryBytes;
  j["meta_bytes"] = h.metaBytes;
  const nlohmann::json levels = levelsJson(r);
  uint64_t voxels = 0, payload = 0;
  for (const auto& l : levels) {
    voxels += l["voxels"].get<uint64_t>();
    payload += l["payload_bytes"].get<uint64_t>();
  }
  j["chunks"] = h.chunkCount;
  j["voxels"] = voxels;
  j["payload_bytes"] = payload;
  j["bytes_per_voxel"] = voxels ? double(h.fileBytes) / double(voxels) : 0.0;
  j["levels"] = levels;
  j["classes"] = nlohmann::json::parse(vox::classTableJson(meta.classes));
  j["sources"] = nlohmann::json::parse(vox::sourcesJson(meta.sources));
  if (!meta.mipOccupancy.empty()) j["mip_occupancy"] = meta.mipOccupancy;
  if (meta.region) j["region"] = nlohmann::json::parse(vox::regionJson(*meta.region));
  return j;
}

// What `vox info` prints, from pageFileJson's result.
std::string pageFileText(const std::string& path, const vox::pagefile::Header& h, const nlohmann::json& j) {
  using namespace infotext;
  const uint64_t voxels = j["voxels"].get<uint64_t>(), payload = j["payload_bytes"].get<uint64_t>();
  std::ostringstream o;
  o << heading(path, "voxbake page file (version " + std::to_string(vox::pagefile::kVersion) + ", " +
                          j["layout"].get<std::string>() + " layout)");
  o << line("dims", std::to_string(h.dims[0]) + " x " + std::to_string(h.dims[1]) + " x " + std::to_string(h.dims[2]) +
                        " voxels of " + measured(h.voxelSize, 6, "world unit", "world units"));
  o << line("chunks", count(h.chunkCount) + " of " + std::to_string(h.chunkSide()) + "^3 voxels, payloads aligned to " +
                          std::to_string(1u << h.alignLog2) + " bytes");
  std::string ch;
  for (const auto& c : j["channels"]) ch += (ch.empty() ? "" : ", ") + c.get<std::string>();
  o << line("channels", ch);
  o << line("size", bytes(h.fileBytes) + " for " + countOf(voxels, "voxel", "voxels") + ": " +
                        real(j["bytes_per_voxel"].get<double>(), 3) + " bytes per voxel");
  o << line("", "payloads " + bytes(payload) + " (" + percent(h.fileBytes ? double(payload) / double(h.fileBytes) : 0) +
                    "), index " + bytes(j["index_bytes"].get<uint64_t>()) + ", metadata " +
                    bytes(j["meta_bytes"].get<uint64_t>()));
  if (j.contains("region")) o << line("region", regionText(j["region"]));
  std::string names;
  for (const auto& c : j["classes"]) names += (names.empty() ? "" : ", ") + c["name"].get<std::string>();
  o << line("classes", std::to_string(j["classes"].size()) + (names.empty() ? "" : ": " + fit(names, kWidth - 22)));
  Table t({{"level", true}, {"dims", false}, {"voxel size", true}, {"chunks", true}, {"full", true}, {"voxels", true},
           {"payload", true}, {"B/voxel", true}});
  for (const auto& l : j["levels"]) {
    const std::string dims = std::to_string(l["dims"][0].get<uint32_t>()) + "x" + std::to_string(l["dims"][1].get<uint32_t>()) +
                             "x" + std::to_string(l["dims"][2].get<uint32_t>());
    t.row({l["level"].dump(), dims, real(l["voxel_size"].get<double>(), 4), count(l["chunks"].get<uint64_t>()),
           count(l["full_chunks"].get<uint64_t>()), count(l["voxels"].get<uint64_t>()),
           bytes(l["payload_bytes"].get<uint64_t>()), real(l["bytes_per_voxel"].get<double>(), 3)});
  }
  o << line("levels", std::to_string(j["levels"].size()));
  o << t.str();
  return o.str();
}

}  // namespace

int infoPageFile(const std::string& path, bool asJson) {
  const vox::pagefile::Reader r = vox::pagefile::Reader::open(path);
  const vox::pagefile::PageMeta meta = vox::pagefile::readPageMeta(r.metaJson(), path);
  const nlohmann::json j = pageFileJson(path, r, meta);
  if (asJson)
    std::cout << vox::jsonText(j, 2) << "\n";
  else
    std::cout << pageFileText(path, r.header(), j);
  return kExitOk;
}

nlohmann::json pyramidInfoJson(const std::string& path) {
  const std::string text = vox::readPyramidMetadata(path);
  if (text.empty()) return nullptr;
  try {
    return vox::parseJsonInput(text, path + ": metadata 'vox:pyramid'");
  } catch (const nlohmann::json::exception& e) {
    throw vox::Error(vox::ErrorKind::BadInput, path + ": metadata 'vox:pyramid': not valid JSON: " + e.what());
  }
}

std::string pyramidInfoText(const nlohmann::json& p) {
  using namespace infotext;
  std::ostringstream o;
  const auto& levels = p.value("levels", nlohmann::json::array());
  o << line("pyramid", counted(levels.size(), "level", "levels") + " above level 0 (occupancy " +
                           p.value("occupancy", std::string("?")) + "; grids mipN.*)");
  Table t({{"level", true}, {"dims", false}, {"voxel size", true}, {"occupied", true}});
  for (const auto& l : levels)
    t.row({std::to_string(l.value("level", 0)),
           std::to_string(l["dims"][0].get<uint32_t>()) + " x " + std::to_string(l["dims"][1].get<uint32_t>()) + " x " +
               std::to_string(l["dims"][2].get<uint32_t>()),
           real(l.value("voxel_size", 0.0), 6), count(l.value("occupied", uint64_t(0)))});
  if (t.rows()) o << t.str();
  return o.str();
}

}  // namespace voxcli
