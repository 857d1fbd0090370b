#include "formats/image/touched_json.h"

#include <nlohmann/json.hpp>

#include "formats/core/file_util.h"
#include "formats/core/json_fields.h"
#include "formats/core/json_input.h"
#include "formats/core/json_text.h"
#include "libvox/core/error.h"
#include "libvox/core/morton.h"

namespace vox {

namespace {

using nlohmann::json;

[[noreturn]] void bad(const std::string& name, const std::string& what) { throwBadInput(name + ": " + what); }

uint32_t unsigned32(const json& j, const std::string& name, const std::string& element) {
  const uint64_t v = jsonUnsigned(j, name, element);
  if (v > UINT32_MAX) bad(name, element + " must fit in 32 bits");
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
  return jsonText(doc, 1) + "\n";
}

TouchedSet parseTouchedSet(const std::string& text, const std::string& name) {
  json doc;
  try {
    doc = parseJsonInput(text, name);
  } catch (const json::exception& e) {  // parse_error, and out_of_range.406 for a number past double's range
    bad(name, std::string("not valid JSON: ") + e.what());
  }
  if (!doc.is_object() || !doc.contains("format") || doc["format"] != kTouchedSetFormat)
    bad(name, std::string("not a touched set (expected \"format\": \"") + kTouchedSetFormat + "\")");
  TouchedSet set;
  set.scene = jsonString(jsonMember(doc, "scene", name), name, "scene");
  set.dims = jsonDims(jsonMember(doc, "dims", name), name, "dims");
  set.chunkSide = unsigned32(jsonMember(doc, "chunk_size", name), name, "chunk_size");
  if (set.chunkSide == 0) bad(name, "chunk_size must be positive");
  set.views = jsonUnsigned(jsonMember(doc, "views", name), name, "views");
  set.rays = jsonUnsigned(jsonMember(doc, "rays", name), name, "rays");
  set.hits = jsonUnsigned(jsonMember(doc, "hits", name), name, "hits");
  set.voxelsTouched = jsonUnsigned(jsonMember(doc, "voxels_touched", name), name, "voxels_touched");
  const json& chunks = jsonMember(doc, "chunks", name);
  if (!chunks.is_array()) bad(name, "chunks must be an array");
  uint64_t voxelSum = 0;
  for (size_t i = 0; i < chunks.size(); ++i) {
    const std::string element = "chunks[" + std::to_string(i) + "]";
    const json& c = chunks[i];
    if (!c.is_object()) bad(name, element + " must be an object");
    const json& xyz = jsonMember(c, "chunk", name + ": " + element);
    if (!xyz.is_array() || xyz.size() != 3) bad(name, element + ".chunk must be 3 integers");
    TouchedChunk chunk;
    for (size_t a = 0; a < 3; ++a)
      chunk.chunk[a] = unsigned32(xyz[a], name, element + ".chunk[" + std::to_string(a) + "]");
    chunk.morton = jsonUnsigned(jsonMember(c, "morton", name + ": " + element), name, element + ".morton");
    chunk.voxels = jsonUnsigned(jsonMember(c, "voxels", name + ": " + element), name, element + ".voxels");
    if (chunk.morton != mortonEncode(chunk.chunk[0], chunk.chunk[1], chunk.chunk[2]))
      bad(name, element + ".morton is not the Morton key of its chunk");
    if (!set.chunks.empty() && !(set.chunks.back().morton < chunk.morton))
      bad(name, element + " is out of Morton order (or repeats a chunk)");
    voxelSum += chunk.voxels;
    set.chunks.push_back(chunk);
  }
  if (jsonUnsigned(jsonMember(doc, "chunks_touched", name), name, "chunks_touched") != set.chunks.size())
    bad(name, "chunks_touched is not the number of chunks listed");
  if (voxelSum != set.voxelsTouched) bad(name, "voxels_touched is not the sum of the chunks' voxels");
  return set;
}

TouchedSet readTouchedSet(const std::string& path) { return parseTouchedSet(readFileBytes(path), path); }

}  // namespace vox
