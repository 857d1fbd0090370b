#include "formats/image/touched_json.h"

#include <nlohmann/json.hpp>

#include "formats/core/file_util.h"
#include "libvox/core/error.h"
#include "libvox/core/morton.h"

namespace vox {

namespace {

using nlohmann::json;

[[noreturn]] void bad(const std::string& name, const std::string& what) { throwBadInput(name + ": " + what); }

const json& member(const json& object, const char* key, const std::string& name, const std::string& where = "") {
  if (!object.contains(key)) bad(name, (where.empty() ? std::string("no \"") : where + " has no \"") + key + "\"");
  return object[key];
}

uint64_t count(const json& j, const std::string& name, const std::string& where) {
  if (!j.is_number_unsigned()) bad(name, where + " must be a non-negative integer");
  return j.get<uint64_t>();
}

uint32_t count32(const json& j, const std::string& name, const std::string& where) {
  const uint64_t v = count(j, name, where);
  if (v > UINT32_MAX) bad(name, where + " must fit in 32 bits");
  return uint32_t(v);
}

}  // namespace

std::string touchedSetJson(const TouchedSet& set) {
  json chunks = json::array();
  for (const TouchedChunk& c : set.chunks) chunks.push_back({{"chunk", c.chunk}, {"morton", c.morton}, {"voxels", c.voxels}});
  const json doc = {{"format", kTouchedSetFormat},
                    {"scene", set.scene},
                    {"dims", {set.dims.x, set.dims.y, set.dims.z}},
                    {"chunk_size", set.chunkSide},
                    {"views", set.views},
                    {"rays", set.rays},
                    {"hits", set.hits},
                    {"voxels_touched", set.voxelsTouched},
                    {"chunks_touched", set.chunks.size()},
                    {"chunks", chunks}};
  return doc.dump(1) + "\n";
}

TouchedSet parseTouchedSet(const std::string& text, const std::string& name) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::parse_error& e) {
    bad(name, std::string("not valid JSON: ") + e.what());
  }
  if (!doc.is_object() || !doc.contains("format") || doc["format"] != kTouchedSetFormat)
    bad(name, std::string("not a touched set (expected \"format\": \"") + kTouchedSetFormat + "\")");
  TouchedSet set;
  const json& scene = member(doc, "scene", name);
  if (!scene.is_string()) bad(name, "\"scene\" must be a string");
  set.scene = scene.get<std::string>();
  const json& dims = member(doc, "dims", name);
  if (!dims.is_array() || dims.size() != 3) bad(name, "\"dims\" must be 3 integers");
  set.dims = {count32(dims[0], name, "dims[0]"), count32(dims[1], name, "dims[1]"), count32(dims[2], name, "dims[2]")};
  set.chunkSide = count32(member(doc, "chunk_size", name), name, "chunk_size");
  if (set.chunkSide == 0) bad(name, "chunk_size must be positive");
  set.views = count(member(doc, "views", name), name, "views");
  set.rays = count(member(doc, "rays", name), name, "rays");
  set.hits = count(member(doc, "hits", name), name, "hits");
  set.voxelsTouched = count(member(doc, "voxels_touched", name), name, "voxels_touched");
  const json& chunks = member(doc, "chunks", name);
  if (!chunks.is_array()) bad(name, "\"chunks\" must be an array");
  uint64_t voxelSum = 0;
  for (size_t i = 0; i < chunks.size(); ++i) {
    const std::string where = "chunks[" + std::to_string(i) + "]";
    const json& c = chunks[i];
    if (!c.is_object()) bad(name, where + " must be an object");
    const json& xyz = member(c, "chunk", name, where);
    if (!xyz.is_array() || xyz.size() != 3) bad(name, where + ".chunk must be 3 integers");
    TouchedChunk chunk;
    for (size_t a = 0; a < 3; ++a) chunk.chunk[a] = count32(xyz[a], name, where + ".chunk[" + std::to_string(a) + "]");
    chunk.morton = count(member(c, "morton", name, where), name, where + ".morton");
    chunk.voxels = count(member(c, "voxels", name, where), name, where + ".voxels");
    if (chunk.morton != mortonEncode(chunk.chunk[0], chunk.chunk[1], chunk.chunk[2]))
      bad(name, where + ".morton is not the Morton key of its chunk");
    if (!set.chunks.empty() && !(set.chunks.back().morton < chunk.morton))
      bad(name, where + " is out of Morton order (or repeats a chunk)");
    voxelSum += chunk.voxels;
    set.chunks.push_back(chunk);
  }
  if (count(member(doc, "chunks_touched", name), name, "chunks_touched") != set.chunks.size())
    bad(name, "chunks_touched is not the number of chunks listed");
  if (voxelSum != set.voxelsTouched) bad(name, "voxels_touched is not the sum of the chunks' voxels");
  return set;
}

TouchedSet readTouchedSet(const std::string& path) { return parseTouchedSet(readFileBytes(path), path); }

}  // namespace vox
