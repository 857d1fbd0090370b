#include "formats/vdb/scene_vdb.h"

#include "formats/scene/scene_meta.h"
#include "formats/vdb/vdb_structure.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <openvdb/io/File.h>

#include "libvox/core/error.h"
#include "libvox/scene/scene_grids.h"
#include "libvox/core/version.h"

namespace vox {

namespace {

using nlohmann::json;

constexpr const char* kFormatName = "voxbake-scene";

[[noreturn]] void bad(const std::string& path, const std::string& what) {
  throwBadInput(path + ": " + what);
}

Rgb8 parseRgb(const std::string& path, const json& j, const std::string& what) {
  if (!j.is_array() || j.size() != 3) bad(path, what + " must be an array of 3 integers 0..255");
  Rgb8 c;
  uint8_t* out[3] = {&c.r, &c.g, &c.b};
  for (int i = 0; i < 3; ++i) {
    if (!j[i].is_number_integer() || j[i].get<int64_t>() < 0 || j[i].get<int64_t>() > 255)
      bad(path, what + " must be an array of 3 integers 0..255");
    *out[i] = uint8_t(j[i].get<int>());
  }
  return c;
}

template <typename MetaT>
auto requireMeta(const openvdb::MetaMap& meta, const std::string& path,
                                      const std::string& key, const char* typeName) {
  auto m = meta[key];
  if (!m) bad(path, "metadata key '" + key + "' is missing; this file is not a voxbake scene (write one with `vox voxelize`)");
  auto typed = openvdb::DynamicPtrCast<const MetaT>(m);
  if (!typed) bad(path, "metadata key '" + key + "' has type " + m->typeName() + ", expected " + typeName);
  return typed->value();
}

}  // namespace

void writeSceneVdb(const Scene& scene, const std::string& path) {
  ensureOpenVdbInitialized();
  const SceneHeader& h = scene.header();
  const SceneGrids& g = scene.grids();

  // Every grid carries the index-to-world transform (voxel centre at
  // origin + (i + 0.5) * voxelSize) so other VDB readers place voxels right.
  openvdb::math::Transform::Ptr xform = openvdb::math::Transform::createLinearTransform(h.voxelSize);
  xform->postTranslate(openvdb::Vec3d(h.origin[0] + 0.5 * h.voxelSize, h.origin[1] + 0.5 * h.voxelSize,
                                      h.origin[2] + 0.5 * h.voxelSize));
  openvdb::GridPtrVec grids;
  auto add = [&](openvdb::GridBase::ConstPtr grid, const std::string& name) {
    // A shallow copy shares the tree, so the in-memory scene is not modified.
    openvdb::GridBase::Ptr copy = openvdb::ConstPtrCast<openvdb::GridBase>(grid)->copyGrid();
    copy->setTransform(xform->copy());
    copy->setName(name);
    copy->setSaveFloatAsHalf(false);
    grids.push_back(copy);
    return copy;
  };
  add(g.occupancy, "occupancy");
  for (const ClassGrid& cg : g.votes) {
    auto grid = add(cg.grid, "votes." + std::to_string(cg.classId));
    grid->insertMeta("vox:class_id", openvdb::Int32Metadata(cg.classId));
    const ClassInfo* info = h.classes.find(cg.classId);
    grid->insertMeta("vox:class_name", openvdb::StringMetadata(info ? info->name : ""));
  }
  if (g.color) {
    auto grid = add(g.color, "color");
    grid->setVectorType(openvdb::VEC_INVARIANT);
    grid->insertMeta("vox:color_space", openvdb::StringMetadata("linear"));
  }

  openvdb::MetaMap meta;
  meta.insertMeta("vox:format", openvdb::StringMetadata(kFormatName));
  meta.insertMeta("vox:format_version", openvdb::Int32Metadata(kSceneFormatVersion));
  meta.insertMeta("vox:tool_version", openvdb::StringMetadata(kToolVersion));
  meta.insertMeta("vox:dims", openvdb::Vec3IMetadata(openvdb::Vec3i(int(h.dims.x), int(h.dims.y), int(h.dims.z))));
  meta.insertMeta("vox:voxel_size", openvdb::DoubleMetadata(h.voxelSize));
  meta.insertMeta("vox:origin", openvdb::Vec3DMetadata(openvdb::Vec3d(h.origin[0], h.origin[1], h.origin[2])));
  meta.insertMeta("vox:classes", openvdb::StringMetadata(classTableJson(h.classes)));
  meta.insertMeta("vox:sources", openvdb::StringMetadata(sourcesJson(h.sources)));
  meta.insertMeta("vox:mip_level", openvdb::Int32Metadata(h.mipLevel));
  if (h.blockWorld) {
    meta.insertMeta("vox:block_world", openvdb::StringMetadata(blockWorldJson(*h.blockWorld)));
  }
  try {
    openvdb::io::File file(path);
    file.setCompression(openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK);
    file.write(grids, meta);
    file.close();
  } catch (const std::exception& e) {
    throwIo(path + ": cannot write the scene: " + e.what());
  }
}

bool looksLikeVdb(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  int32_t magic = 0;
  in.read(reinterpret_cast<char*>(&magic), sizeof magic);
  return in && magic == 0x56444220;  // OpenVDB's OPENVDB_MAGIC (" BDV")
}

Scene readSceneVdb(const std::string& path) { return readSceneVdb(path, SceneParts::All); }

Scene readSceneVdb(const std::string& path, SceneParts parts) {
  ensureOpenVdbInitialized();
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) bad(path, "cannot open the file (missing or unreadable)");
  }
  if (!looksLikeVdb(path)) bad(path, "not an OpenVDB file (wrong magic number)");
  checkVdbStructure(path);  // refuses truncated files before OpenVDB trusts their lengths

  openvdb::MetaMap::Ptr meta;
  openvdb::GridPtrVecPtr grids;
  try {
    openvdb::io::File file(path);
    file.open(/*delayLoad=*/false);
    meta = file.getMetadata();
    if (parts == SceneParts::All) {
      grids = file.getGrids();
    } else {
      grids = std::make_shared<openvdb::GridPtrVec>();
      if (file.hasGrid("occupancy")) grids->push_back(file.readGrid("occupancy"));
    }
    file.close();
  } catch (const std::exception& e) {
    // OpenVDB may quote garbage from a corrupt file: keep the message short and printable.
    std::string why;
    for (char c : std::string(e.what()).substr(0, 160)) why += (c >= 32 && c < 127) ? c : '?';
    bad(path, "cannot read the OpenVDB file (corrupt?): " + why);
  }

  SceneHeader h;
  const std::string format = requireMeta<openvdb::StringMetadata>(*meta, path, "vox:format", "string");
  if (format != kFormatName) bad(path, "metadata 'vox:format' is '" + format + "', expected '" + kFormatName + "'");
  const int version = requireMeta<openvdb::Int32Metadata>(*meta, path, "vox:format_version", "int32");
  if (version < 1 || version > kSceneFormatVersion)
    bad(path, "scene format version " + std::to_string(version) + " is not supported (this vox reads 1.." +
                  std::to_string(kSceneFormatVersion) + "); upgrade vox");
  const openvdb::Vec3i dims = requireMeta<openvdb::Vec3IMetadata>(*meta, path, "vox:dims", "vec3i");
  if (dims.x() < 1 || dims.y() < 1 || dims.z() < 1)
    bad(path, "metadata 'vox:dims' must be >= 1 on every axis");
  h.dims = {uint32_t(dims.x()), uint32_t(dims.y()), uint32_t(dims.z())};
  h.voxelSize = requireMeta<openvdb::DoubleMetadata>(*meta, path, "vox:voxel_size", "double");
  if (!(h.voxelSize > 0) || !std::isfinite(h.voxelSize)) bad(path, "metadata 'vox:voxel_size' must be finite and > 0");
  const openvdb::Vec3d origin = requireMeta<openvdb::Vec3DMetadata>(*meta, path, "vox:origin", "vec3d");
  h.origin = {origin.x(), origin.y(), origin.z()};
  h.mipLevel = requireMeta<openvdb::Int32Metadata>(*meta, path, "vox:mip_level", "int32");

  try {
    const json classes = json::parse(requireMeta<openvdb::StringMetadata>(*meta, path, "vox:classes", "string"));
    if (!classes.is_array()) bad(path, "metadata 'vox:classes' must be a JSON array");
    for (size_t i = 0; i < classes.size(); ++i) {
      const json& c = classes[i];
      const std::string where = "metadata 'vox:classes' entry " + std::to_string(i);
      if (!c.is_object() || !c.contains("id") || !c["id"].is_number_integer() || !c.contains("name") ||
          !c["name"].is_string())
        bad(path, where + " needs an integer 'id' and a string 'name'");
      const int64_t id = c["id"].get<int64_t>();
      if (id < 1 || id > kMaxClassId) bad(path, where + " has id " + std::to_string(id) + ", expected 1..255");
      ClassInfo info;
      info.id = uint8_t(id);
      info.name = c["name"].get<std::string>();
      if (c.contains("color")) info.color = parseRgb(path, c["color"], where + " 'color'");
      if (c.contains("top") || c.contains("bottom") || c.contains("side")) {
        if (!c.contains("top") || !c.contains("bottom") || !c.contains("side"))
          bad(path, where + " needs all of 'top', 'bottom' and 'side' or none");
        info.faces = FacePalette{parseRgb(path, c["top"], where + " 'top'"),
                                 parseRgb(path, c["bottom"], where + " 'bottom'"),
                                 parseRgb(path, c["side"], where + " 'side'")};
      }
      h.classes.add(std::move(info), path + ": metadata 'vox:classes'");
    }
    if (auto m = (*meta)["vox:sources"]) {
      const json sources = json::parse(requireMeta<openvdb::StringMetadata>(*meta, path, "vox:sources", "string"));
      for (const json& s : sources)
        h.sources.push_back({s.value("path", ""), s.value("kind", ""), s.value("sha256", ""),
                             s.value("bytes", uint64_t(0))});
    }
    if (auto m = (*meta)["vox:block_world"]) {
      const json bw = json::parse(requireMeta<openvdb::StringMetadata>(*meta, path, "vox:block_world", "string"));
      BlockWorldPlacement p;
      p.worldScale = bw.at("worldScale").get<double>();
      for (int i = 0; i < 3; ++i) p.gridSize[i] = bw.at("gridSize").at(i).get<uint32_t>();
      h.blockWorld = p;
    }
  } catch (const json::exception& e) {
    bad(path, std::string("malformed JSON in scene metadata: ") + e.what());
  }

  Scene scene;
  scene.header() = h;
  SceneGrids& g = scene.grids();
  g.occupancy.reset();
  const openvdb::CoordBBox domain(openvdb::Coord(0), openvdb::Coord(dims.x() - 1, dims.y() - 1, dims.z() - 1));
  for (const openvdb::GridBase::Ptr& base : *grids) {
    const std::string name = base->getName();
    auto checkDomain = [&](const openvdb::GridBase& grid) {
      const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
      if (grid.activeVoxelCount() > 0 && !domain.isInside(box))
        bad(path, "grid '" + name + "' has active voxels outside the dims " + toString(h.dims));
    };
    if (name == "occupancy") {
      auto grid = openvdb::GridBase::grid<openvdb::BoolGrid>(base);
      if (!grid) bad(path, "grid 'occupancy' has type " + base->type() + ", expected bool");
      checkDomain(*grid);
      grid->tree().voxelizeActiveTiles();  // other writers may store full blocks as tiles
      g.occupancy = grid;
    } else if (name.rfind("votes.", 0) == 0) {
      auto grid = openvdb::GridBase::grid<openvdb::Int32Grid>(base);
      if (!grid) bad(path, "grid '" + name + "' has type " + base->type() + ", expected int32");
      int id = 0;
      try {
        id = std::stoi(name.substr(6));
      } catch (...) {
        id = -1;
      }
      if (id < 1 || id > kMaxClassId || name != "votes." + std::to_string(id))
        bad(path, "grid '" + name + "' is not named votes.<class id 1..255>");
      if (!h.classes.find(uint8_t(id)))
        bad(path, "grid '" + name + "' holds votes for class " + std::to_string(id) + ", which is not in 'vox:classes'");
      checkDomain(*grid);
      grid->tree().voxelizeActiveTiles();
      for (auto it = grid->cbeginValueOn(); it; ++it)
        if (*it <= 0)
          bad(path, "grid '" + name + "' has vote count " + std::to_string(*it) + " at " +
                        toString(Coord3{it.getCoord().x(), it.getCoord().y(), it.getCoord().z()}) +
                        "; counts must be >= 1");
      g.votes.push_back({uint8_t(id), grid});
    } else if (name == "color") {
      auto grid = openvdb::GridBase::grid<openvdb::Vec3SGrid>(base);
      if (!grid) bad(path, "grid 'color' has type " + base->type() + ", expected vec3s");
      checkDomain(*grid);
      grid->tree().voxelizeActiveTiles();
      g.color = grid;
    }
    // Other grids are ignored, so users may add their own.
  }
  if (!g.occupancy) bad(path, "no grid named 'occupancy' (bool); this is not a voxbake scene — convert "
                              "OpenVDB level sets or fog volumes with `vox voxelize FILE.vdb`");
  std::sort(g.votes.begin(), g.votes.end(), [](const ClassGrid& a, const ClassGrid& b) { return a.classId < b.classId; });
  for (size_t i = 1; i < g.votes.size(); ++i)
    if (g.votes[i].classId == g.votes[i - 1].classId)
      bad(path, "two vote grids for class " + std::to_string(g.votes[i].classId));
  // Reset transforms: in memory the grids use index space.
  auto identity = [](openvdb::GridBase& grid) { grid.setTransform(openvdb::math::Transform::createLinearTransform(1.0)); };
  identity(*g.occupancy);
  for (ClassGrid& cg : g.votes) identity(*cg.grid);
  if (g.color) identity(*g.color);
  if (parts == SceneParts::OccupancyOnly) return scene;
  // Topology invariants: every vote/colour voxel is occupied and every occupied
  // voxel has a vote.
  auto occ = g.occupancy->getConstAccessor();
  for (ClassGrid& cg : g.votes)
    for (auto it = cg.grid->cbeginValueOn(); it; ++it)
      if (!occ.isValueOn(it.getCoord()))
        bad(path, "grid '" + cg.grid->getName() + "' has a vote at an unoccupied voxel " +
                      toString(Coord3{it.getCoord().x(), it.getCoord().y(), it.getCoord().z()}));
  std::vector<openvdb::Int32Grid::ConstAccessor> accs;
  for (ClassGrid& cg : g.votes) accs.push_back(cg.grid->getConstAccessor());
  for (auto it = g.occupancy->cbeginValueOn(); it; ++it) {
    bool any = false;
    for (auto& a : accs) any = any || a.isValueOn(it.getCoord());
    if (!any)
      bad(path, "occupied voxel " + toString(Coord3{it.getCoord().x(), it.getCoord().y(), it.getCoord().z()}) +
                    " has no votes in any 'votes.<id>' grid");
  }
  return scene;
}

}  // namespace vox
