#include "formats/vdb/blockmap_json.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <unordered_map>

#include "formats/core/file_util.h"
#include "formats/core/json_input.h"
#include "libvox/core/error.h"
#include "libvox/core/sha256.h"

namespace vox {

namespace {
using nlohmann::json;

std::string typeList() {
  std::string s;
  for (size_t i = 0; i < blockTypeNames().size(); ++i) s += (i ? ", " : "") + blockTypeNames()[i];
  return s;
}
}  // namespace

Scene parseBlockMap(const std::string& text, const std::string& path, const BlockMapOptions& options) {
  auto bad = [&](const std::string& what, Setting fix = Setting::None) { throwBadInput(path + ": " + what, fix); };
  for (int i = 0; i < 3; ++i)
    if (options.gridSize[i] == 0 || options.gridSize[i] > kMaxBlockWorldSide)
      throwUsage("the block world's grid size must be 1.." + std::to_string(kMaxBlockWorldSide) + " on every axis",
                 Setting::BlockWorldGrid);
  json doc;
  try {
    doc = parseJsonInput(text, path);
  } catch (const json::parse_error& e) {
    bad("not valid JSON (byte " + std::to_string(e.byte) + "): " + e.what());
  } catch (const json::exception& e) {  // a number past double's range (out_of_range.406) is not a parse_error
    bad(std::string("not valid JSON: ") + e.what());
  }
  if (!doc.is_object()) bad("expected a JSON object with 'worldScale' and 'blocks'");
  if (!doc.contains("worldScale")) bad("missing 'worldScale' (a number > 0, e.g. 2.0)");
  if (!doc["worldScale"].is_number()) bad("'worldScale' must be a number > 0");
  const double scale = doc["worldScale"].get<double>();
  if (!(scale > 0) || !std::isfinite(scale)) bad("'worldScale' must be a finite number > 0");
  if (!doc.contains("blocks")) bad("missing 'blocks' (an array of {\"position\": [x,y,z], \"blockType\": name})");
  const json& blocks = doc["blocks"];
  if (!blocks.is_array()) bad("'blocks' must be an array");

  struct Block {
    std::array<uint32_t, 3> p;
    uint8_t cls;
  };
  std::vector<Block> parsed;
  parsed.reserve(blocks.size());
  std::unordered_map<uint64_t, size_t> seen;  // packed position -> block index
  const auto& names = blockTypeNames();
  const char* axes = "xyz";
  for (size_t i = 0; i < blocks.size(); ++i) {
    const std::string where = "block " + std::to_string(i);
    const json& b = blocks[i];
    if (!b.is_object()) bad(where + ": expected an object with 'position' and 'blockType'");
    if (!b.contains("position")) bad(where + ": missing 'position' ([x, y, z] integers)");
    if (!b.contains("blockType")) bad(where + ": missing 'blockType' (one of " + typeList() + ")");
    const json& pos = b["position"];
    if (!pos.is_array() || pos.size() != 3) bad(where + ": 'position' must be an array of 3 integers");
    Block blk{};
    for (int a = 0; a < 3; ++a) {
      const json& c = pos[a];
      if (!c.is_number()) bad(where + ": position " + axes[a] + " is not a number");
      if (!c.is_number_integer()) {
        const double d = c.get<double>();
        bad(where + ": position " + axes[a] + " = " + c.dump() + " is not an integer" +
            (d == std::floor(d) ? " (write it without a decimal point)" : ""));
      }
      if (c.is_number_unsigned() ? false : c.get<int64_t>() < 0)
        bad(where + ": position " + axes[a] + " = " + c.dump() + " is negative; positions start at 0");
      const uint64_t v = c.is_number_unsigned() ? c.get<uint64_t>() : uint64_t(c.get<int64_t>());
      if (v >= options.gridSize[a])
        bad(where + ": position " + axes[a] + " = " + std::to_string(v) + " is outside the world grid " +
            std::to_string(options.gridSize[0]) + "," + std::to_string(options.gridSize[1]) + "," +
            std::to_string(options.gridSize[2]) + " (0.." + std::to_string(options.gridSize[a] - 1) +
            "); give a larger block world grid",
            Setting::BlockWorldGrid);
      blk.p[a] = uint32_t(v);
    }
    if (!b["blockType"].is_string()) bad(where + ": 'blockType' must be a string (one of " + typeList() + ")");
    const std::string type = b["blockType"].get<std::string>();
    auto it = std::find(names.begin(), names.end(), type);
    if (it == names.end()) bad(where + ": unknown blockType '" + type + "'; expected one of " + typeList());
    blk.cls = uint8_t(it - names.begin());
    const uint64_t key = (uint64_t(blk.p[0]) << 42) | (uint64_t(blk.p[1]) << 21) | blk.p[2];
    // Positions are < gridSize <= kMaxBlockWorldSide = 2^21, so 21 bits per axis pack without collisions.
    auto [at, inserted] = seen.emplace(key, i);
    if (!inserted)
      bad(where + ": position [" + std::to_string(blk.p[0]) + ", " + std::to_string(blk.p[1]) + ", " +
          std::to_string(blk.p[2]) + "] is already used by block " + std::to_string(at->second) +
          "; each position may hold one block");
    if (blk.cls != 0) parsed.push_back(blk);
  }
  if (parsed.empty()) bad("the map has no solid blocks (only Air or none); there is nothing to voxelize");

  SceneHeader header;
  std::array<uint32_t, 3> maxp{0, 0, 0};
  for (const Block& b : parsed)
    for (int a = 0; a < 3; ++a) maxp[a] = std::max(maxp[a], b.p[a]);
  header.dims = {maxp[0] + 1, maxp[1] + 1, maxp[2] + 1};
  header.voxelSize = scale;
  header.origin = {-double(options.gridSize[0]) / 2.0 * scale, 0.0, -double(options.gridSize[2]) / 2.0 * scale};
  if (const std::string problem = placementProblem(header.voxelSize, header.origin, header.dims); !problem.empty())
    bad("'worldScale' " + doc["worldScale"].dump() + " with the grid size " + std::to_string(options.gridSize[0]) + "," +
        std::to_string(options.gridSize[1]) + "," + std::to_string(options.gridSize[2]) + ": " + problem +
        "; use a worldScale near 1");
  header.classes = blockPalette();
  header.blockWorld = BlockWorldPlacement{scale, options.gridSize};

  auto solid = [&](int64_t x, int64_t y, int64_t z) {
    if (x < 0 || y < 0 || z < 0) return false;
    auto it = seen.find((uint64_t(x) << 42) | (uint64_t(y) << 21) | uint64_t(z));
    if (it == seen.end()) return false;
    const json& t = blocks[it->second]["blockType"];
    return t.get<std::string>() != "Air";
  };
  SceneBuilder builder(header);
  for (const Block& b : parsed) {
    const int64_t x = b.p[0], y = b.p[1], z = b.p[2];
    const bool surface = !solid(x - 1, y, z) || !solid(x + 1, y, z) || !solid(x, y - 1, z) ||
                         !solid(x, y + 1, z) || !solid(x, y, z - 1) || !solid(x, y, z + 1);
    builder.addVotes({int32_t(x), int32_t(y), int32_t(z)}, b.cls, 1, surface);
  }
  return std::move(builder).build();
}

Scene readBlockMap(const std::string& path, const BlockMapOptions& options) {
  const std::string text = readFileBytes(path);
  Scene scene = parseBlockMap(text, path, options);
  Sha256 h;
  h.update(text.data(), text.size());
  scene.header().sources.push_back({path, "blockmap", h.hexDigest(), text.size()});
  return scene;
}

}  // namespace vox
