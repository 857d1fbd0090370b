#include "tools/cmds/info_json_files.h"

#include <algorithm>
#include <iostream>
#include <set>
#include <sstream>

#include "formats/core/file_util.h"
#include "formats/core/json_input.h"
#include "formats/core/json_text.h"
#include "formats/image/atlas_meta.h"
#include "formats/image/touched_json.h"
#include "tools/cli/cli.h"
#include "tools/cmds/info_text.h"

namespace voxcli {

using namespace infotext;

std::string voxJsonKind(const nlohmann::json& doc) {
  if (!doc.is_object()) return "";
  if (doc.contains("format") && doc["format"] == vox::kTouchedSetFormat) return "touched";
  if (doc.value("tool", std::string()) == "vox" && doc.contains("command") && doc.contains("phases")) return "report";
  if (doc.contains("layout") && doc.contains("files") && doc.contains("scene")) return "atlas_sidecar";
  return "";
}

int infoAtlasSidecar(const std::string& path, bool asJson) {
  const std::string text = vox::readFileBytes(path);
  const std::vector<vox::AtlasSidecarEntry> files = vox::atlasSidecarFromJson(text, path);
  if (asJson) {
    nlohmann::json j = vox::parseJsonInput(text, path);
    j["file"] = path;
    j["kind"] = "atlas_sidecar";
    std::cout << vox::jsonText(j, 2) << "\n";
    return kExitOk;
  }
  std::ostringstream o;
  o << heading(path, "atlas sidecar (the layout and files of one build-atlas run)");
  if (!files.empty()) {
    const vox::AtlasLayout& L = files[0].info.layout;
    o << line("built from", files[0].info.scene);
    o << line("scene dims", std::to_string(L.dims.x) + " x " + std::to_string(L.dims.y) + " x " +
                                std::to_string(L.dims.z) + " voxels");
    o << line("atlas", std::to_string(L.width) + " x " + std::to_string(L.height) + " texels, " +
                           countOf(L.tilesPerRow, "tile", "tiles") + " per row, " + countOf(L.layers, "layer", "layers"));
  }
  Table t({{"file", false, true}, {"content", false}, {"format", false}, {"layer", true}, {"class", true}});
  for (const auto& f : files)
    t.row({f.file, vox::atlasContentName(f.info.content), f.info.format, std::to_string(f.info.layer),
           f.info.content == vox::AtlasContent::Votes ? std::to_string(f.info.classId) : ""});
  o << line("files", std::to_string(files.size()));
  o << t.str();
  std::cout << o.str();
  return kExitOk;
}

int infoTouchedSet(const std::string& path, bool asJson) {
  const vox::TouchedSet t = vox::readTouchedSet(path);
  const uint64_t C = t.chunkSide;
  const uint64_t chunksX = C ? (t.dims.x + C - 1) / C : 0, chunksY = C ? (t.dims.y + C - 1) / C : 0,
                 chunksZ = C ? (t.dims.z + C - 1) / C : 0;
  const uint64_t gridChunks = chunksX * chunksY * chunksZ;
  uint64_t maxVoxels = 0;
  for (const auto& c : t.chunks) maxVoxels = std::max(maxVoxels, c.voxels);
  if (asJson) {
    nlohmann::json j = vox::parseJsonInput(vox::readFileBytes(path), path);
    j["file"] = path;
    j["kind"] = "touched";
    j["summary"] = {{"chunks_touched", t.chunks.size()}, {"chunks_in_grid", gridChunks}, {"max_voxels_in_a_chunk", maxVoxels}};
    std::cout << vox::jsonText(j, 2) << "\n";
    return kExitOk;
  }
  std::ostringstream o;
  o << heading(path, "touched set (the chunks a camera path's rays hit)");
  o << line("scene", t.scene);
  o << line("dims", std::to_string(t.dims.x) + " x " + std::to_string(t.dims.y) + " x " + std::to_string(t.dims.z) +
                        " voxels, chunks of " + std::to_string(C) + "^3");
  o << line("views", count(t.views) + ", " + countOf(t.rays, "ray", "rays") + ", " + count(t.hits) +
                         (t.hits == 1 ? " hits" : " hit") + " a voxel (" +
                         percent(t.rays ? double(t.hits) / double(t.rays) : 0) + ")");
  o << line("chunks", count(t.chunks.size()) + " of " + count(gridChunks) + " touched (" +
                          percent(gridChunks ? double(t.chunks.size()) / double(gridChunks) : 0) + ")");
  o << line("voxels", count(t.voxelsTouched) + " distinct hit; at most " + count(maxVoxels) + " in one chunk (of " +
                          count(C * C * C) + ")");
  if (!t.chunks.empty()) {
    // The busiest chunks: where a streamer's budget goes.
    std::vector<vox::TouchedChunk> top = t.chunks;
    std::stable_sort(top.begin(), top.end(), [](const auto& a, const auto& b) { return a.voxels > b.voxels; });
    if (top.size() > 5) top.resize(5);
    Table tab({{"chunk", false}, {"morton", true}, {"voxels", true}, {"of the chunk", true}});
    for (const auto& c : top)
      tab.row({"(" + std::to_string(c.chunk[0]) + ", " + std::to_string(c.chunk[1]) + ", " + std::to_string(c.chunk[2]) + ")",
               std::to_string(c.morton), count(c.voxels), percent(double(c.voxels) / double(C * C * C))});
    o << line("busiest", "the chunks with the most voxels hit:");
    o << tab.str();
  }
  std::cout << o.str();
  return kExitOk;
}

namespace {

// A JSON value in a few characters: numbers rounded, short arrays inline.
std::string brief(const nlohmann::json& v) {
  if (v.is_null()) return "-";
  if (v.is_boolean()) return v.get<bool>() ? "yes" : "no";
  if (v.is_number_unsigned()) return count(v.get<uint64_t>());
  if (v.is_number_integer()) {
    const int64_t i = v.get<int64_t>();
    return i < 0 ? "-" + count(uint64_t(-i)) : count(uint64_t(i));
  }
  if (v.is_number_float()) return real(v.get<double>(), 4);
  if (v.is_string()) return v.get<std::string>();
  if (v.is_array()) {
    if (v.empty()) return "-";
    if (v.size() <= 4 && std::all_of(v.begin(), v.end(), [](const auto& e) { return e.is_number(); })) {
      std::string s;
      for (const auto& e : v) s += (s.empty() ? "" : " x ") + (e.is_number_float() ? real(e.get<double>(), 4) : e.dump());
      return s;
    }
    if (std::all_of(v.begin(), v.end(), [](const auto& e) { return e.is_string(); })) {
      std::string s;
      for (const auto& e : v) s += (s.empty() ? "" : ", ") + e.get<std::string>();
      return s.empty() ? "-" : s;
    }
    return counted(v.size(), "entry", "entries");
  }
  return counted(v.size(), "key", "keys");
}

// True when every line of `text` fits kWidth display columns.
bool fitsWidth(const std::string& text) {
  size_t start = 0;
  while (start <= text.size()) {
    const size_t end = std::min(text.find('\n', start), text.size());
    if (columns(text.substr(start, end - start)) > kWidth) return false;
    start = end + 1;
  }
  return true;
}

// `parts` joined by ", " after `indent` + `head`, wrapped at kWidth.
std::string wrap(const std::string& head, const std::vector<std::string>& parts, const std::string& indent) {
  std::string out, cur = indent + head;
  const size_t contColumns = columns(indent) + columns(head);
  const std::string cont(contColumns, ' ');
  size_t used = contColumns;
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::string piece = parts[i] + (i + 1 < parts.size() ? "," : "");
    const size_t pieceColumns = columns(piece);
    if (used + 1 + pieceColumns > kWidth && used > contColumns) {
      out += cur + "\n";
      cur = cont + piece;
      used = contColumns + pieceColumns;
    } else {
      cur += (used == contColumns ? "" : " ") + piece;
      used += (used == contColumns ? 0 : 1) + pieceColumns;
    }
  }
  return out + cur + "\n";
}

// An object's entries as key-value lines; arrays of objects as tables.
void describeObject(std::ostringstream& o, const nlohmann::json& obj, const std::string& indent) {
  for (const auto& [key, v] : obj.items()) {
    if (v.is_array() && !v.empty() && std::all_of(v.begin(), v.end(), [](const auto& e) { return e.is_object(); })) {
      std::vector<std::string> keys;
      std::set<std::string> seen;
      for (const auto& e : v)
        for (const auto& [k, x] : e.items())
          if (seen.insert(k).second) keys.push_back(k);
      std::vector<Table::Column> cols;
      for (const auto& k : keys) cols.push_back({k, true, false});
      Table t(cols);
      for (const auto& e : v) {
        std::vector<std::string> cells;
        for (const auto& k : keys) cells.push_back(e.contains(k) ? brief(e[k]) : "");
        t.row(cells);
      }
      const std::string table = t.str();
      if (fitsWidth(table)) {
        o << indent << key << ":\n" << table;
        continue;
      }
      // Too wide for a table: one wrapped "key value, ..." paragraph per element.
      o << indent << key << ":\n";
      for (size_t i = 0; i < v.size(); ++i) {
        std::vector<std::string> parts;
        for (const auto& [k, x] : v[i].items())
          if (!x.is_null()) parts.push_back(k + " " + brief(x));
        o << wrap("[" + std::to_string(i) + "] ", parts, "    ");
      }
    } else if (v.is_object() && !v.empty()) {
      o << indent << key << ":\n";
      describeObject(o, v, indent + "  ");
    } else {
      std::string k = indent + key;
      const size_t keyColumns = columns(k);
      if (keyColumns < 24) k += std::string(24 - keyColumns, ' ');
      const size_t used = 3 + std::max<size_t>(keyColumns, 24);  // a key past 24 columns leaves less for the value
      o << "  " << k << " " << fit(brief(v), used < kWidth ? kWidth - used : 1) << "\n";
    }
  }
}

}  // namespace

int infoReport(const std::string& path, const nlohmann::json& doc, bool asJson) {
  if (asJson) {
    nlohmann::json j = doc;
    j["file"] = path;
    j["kind"] = "report";
    std::cout << vox::jsonText(j, 2) << "\n";
    return kExitOk;
  }
  std::ostringstream o;
  const double total = doc.value("total_seconds", 0.0);
  o << heading(path, "report of `vox " + doc.value("command", std::string("?")) + "`, exit " +
                          std::to_string(doc.value("exit_code", -1)) + ", " + real(total, 3) + " s on " +
                          countOf(doc.value("threads", uint64_t(0)), "thread", "threads"));
  if (doc.contains("argv") && doc["argv"].is_array()) {
    std::string cmd;
    for (const auto& a : doc["argv"]) cmd += (cmd.empty() ? "" : " ") + (a.is_string() ? a.get<std::string>() : a.dump());
    o << line("command line", fit(cmd, kWidth - 16));
  }
  o << line("version", doc.value("version", std::string("?")));
  if (doc.contains("inputs")) o << line("inputs", fit(brief(doc["inputs"]), kWidth - 16));
  if (doc.contains("outputs")) o << line("outputs", fit(brief(doc["outputs"]), kWidth - 16));
  if (doc.contains("phases") && doc["phases"].is_array() && !doc["phases"].empty()) {
    Table t({{"phase", false, true}, {"seconds", true}, {"share", true}});
    for (const auto& p : doc["phases"]) {
      const double s = p.value("seconds", 0.0);
      t.row({p.value("name", std::string("?")), real(s, 3), percent(total > 0 ? s / total : 0)});
    }
    o << line("phases", "");
    o << t.str();
  }
  for (const char* section : {"counts", "error"})
    if (doc.contains(section) && doc[section].is_object() && !doc[section].empty()) {
      o << line(section, "");
      describeObject(o, doc[section], "  ");
    }
  std::cout << o.str();
  return kExitOk;
}

}  // namespace voxcli
