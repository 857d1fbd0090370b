#include "formats/vdb/pyramid_vdb.h"

#include <algorithm>
#include <map>
#include <nlohmann/json.hpp>
#include <openvdb/io/File.h>

#include "formats/vdb/scene_vdb.h"
#include "formats/vdb/vdb_structure.h"
#include "libvox/core/error.h"
#include "libvox/scene/scene_grids.h"
#include "libvox/core/version.h"

namespace vox {

namespace {

using nlohmann::json;

json rgbJson(Rgb8 c) { return json::array({c.r, c.g, c.b}); }

json classesJson(const ClassTable& t) {
  json arr = json::array();
  for (const ClassInfo& c : t.classes()) {
    json j = {{"id", c.id}, {"name", c.name}, {"color", rgbJson(c.color)}};
    if (c.faces) {
      j["top"] = rgbJson(c.faces->top);
      j["bottom"] = rgbJson(c.faces->bottom);
      j["side"] = rgbJson(c.faces->side);
    }
    arr.push_back(std::move(j));
  }
  return arr;
}

json sourcesJson(const std::vector<SceneSource>& sources) {
  json arr = json::array();
  for (const SceneSource& s : sources)
    arr.push_back({{"path", s.path}, {"kind", s.kind}, {"sha256", s.sha256}, {"bytes", s.bytes}});
  return arr;
}

openvdb::math::Transform::Ptr transformOf(const SceneHeader& h) {
  openvdb::math::Transform::Ptr xform = openvdb::math::Transform::createLinearTransform(h.voxelSize);
  xform->postTranslate(openvdb::Vec3d(h.origin[0] + 0.5 * h.voxelSize, h.origin[1] + 0.5 * h.voxelSize,
                                      h.origin[2] + 0.5 * h.voxelSize));
  return xform;
}

// Level n >= 1 grids are named "mip<n>.<scene grid name>": a prefix, not a suffix, so
// that the scene reader (which refuses any "votes.*" grid it cannot parse) skips them.
std::string prefix(int level) { return level == 0 ? "" : "mip" + std::to_string(level) + "."; }

[[noreturn]] void bad(const std::string& path, const std::string& what) { throwBadInput(path + ": " + what); }

}  // namespace

void writePyramidVdb(const std::vector<const Scene*>& levels, MipOccupancy occupancy, const std::string& path) {
  ensureOpenVdbInitialized();
  if (levels.empty()) throw Error(ErrorKind::Internal, "writePyramidVdb: no levels");
  openvdb::GridPtrVec grids;
  json levelTable = json::array();
  for (size_t n = 0; n < levels.size(); ++n) {
    const Scene& scene = *levels[n];
    const SceneHeader& h = scene.header();
    if (h.mipLevel != int(n) + levels[0]->header().mipLevel)
      throw Error(ErrorKind::Internal, "writePyramidVdb: level " + std::to_string(n) + " has mipLevel " +
                                           std::to_string(h.mipLevel));
    const SceneGrids& g = scene.grids();
    const openvdb::math::Transform::Ptr xform = transformOf(h);
    auto add = [&](openvdb::GridBase::ConstPtr grid, const std::string& name) {
      openvdb::GridBase::Ptr copy = openvdb::ConstPtrCast<openvdb::GridBase>(grid)->copyGrid();
      copy->setTransform(xform->copy());
      copy->setName(prefix(int(n)) + name);
      copy->setSaveFloatAsHalf(false);
      if (n > 0) copy->insertMeta("vox:mip_level", openvdb::Int32Metadata(h.mipLevel));
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
    if (n > 0)
      levelTable.push_back({{"level", h.mipLevel},
                            {"dims", {h.dims.x, h.dims.y, h.dims.z}},
                            {"voxel_size", h.voxelSize},
                            {"occupied", scene.occupiedCount()}});
  }
  const SceneHeader& h = levels[0]->header();
  openvdb::MetaMap meta;
  meta.insertMeta("vox:format", openvdb::StringMetadata("voxbake-scene"));
  meta.insertMeta("vox:format_version", openvdb::Int32Metadata(kSceneFormatVersion));
  meta.insertMeta("vox:tool_version", openvdb::StringMetadata(kToolVersion));
  meta.insertMeta("vox:dims", openvdb::Vec3IMetadata(openvdb::Vec3i(int(h.dims.x), int(h.dims.y), int(h.dims.z))));
  meta.insertMeta("vox:voxel_size", openvdb::DoubleMetadata(h.voxelSize));
  meta.insertMeta("vox:origin", openvdb::Vec3DMetadata(openvdb::Vec3d(h.origin[0], h.origin[1], h.origin[2])));
  meta.insertMeta("vox:classes", openvdb::StringMetadata(classesJson(h.classes).dump()));
  meta.insertMeta("vox:sources", openvdb::StringMetadata(sourcesJson(h.sources).dump()));
  meta.insertMeta("vox:mip_level", openvdb::Int32Metadata(h.mipLevel));
  if (h.blockWorld) {
    json bw = {{"worldScale", h.blockWorld->worldScale},
               {"gridSize", {h.blockWorld->gridSize[0], h.blockWorld->gridSize[1], h.blockWorld->gridSize[2]}}};
    meta.insertMeta("vox:block_world", openvdb::StringMetadata(bw.dump()));
  }
  const json pyramid = {{"occupancy", mipOccupancyName(occupancy)}, {"levels", levelTable}};
  meta.insertMeta("vox:pyramid", openvdb::StringMetadata(pyramid.dump()));
  try {
    openvdb::io::File file(path);
    file.setCompression(openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK);
    file.write(grids, meta);
    file.close();
  } catch (const std::exception& e) {
    throwIo(path + ": cannot write the pyramid: " + e.what());
  }
}

bool isPyramidVdb(const std::string& path) {
  if (!looksLikeVdb(path)) return false;
  const VdbFrame frame = checkVdbStructure(path);
  return std::find(frame.metadataNames.begin(), frame.metadataNames.end(), "vox:pyramid") != frame.metadataNames.end();
}

std::string readPyramidMetadata(const std::string& path) {
  if (!isPyramidVdb(path)) return {};
  ensureOpenVdbInitialized();
  try {
    openvdb::io::File file(path);
    file.open(true);
    openvdb::MetaMap::Ptr meta = file.getMetadata();
    file.close();
    auto m = openvdb::DynamicPtrCast<const openvdb::StringMetadata>((*meta)["vox:pyramid"]);
    if (!m) bad(path, "metadata 'vox:pyramid' must be a string");
    return m->value();
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    bad(path, std::string("cannot read the OpenVDB metadata: ") + e.what());
  }
}

std::vector<Scene> readPyramidVdb(const std::string& path) {
  std::vector<Scene> levels;
  levels.push_back(readSceneVdb(path));  // level 0, fully checked (also the framing)
  const SceneHeader base = levels[0].header();

  openvdb::MetaMap::Ptr meta;
  openvdb::GridPtrVecPtr grids;
  try {
    openvdb::io::File file(path);
    file.open(false);
    meta = file.getMetadata();
    grids = file.getGrids();
    file.close();
  } catch (const std::exception& e) {
    bad(path, std::string("cannot read the OpenVDB file: ") + e.what());
  }
  auto pm = (*meta)["vox:pyramid"];
  if (!pm) return levels;  // a plain scene
  json pyramid;
  try {
    auto s = openvdb::DynamicPtrCast<const openvdb::StringMetadata>(pm);
    if (!s) bad(path, "metadata 'vox:pyramid' must be a string");
    pyramid = json::parse(s->value());
  } catch (const json::exception& e) {
    bad(path, std::string("metadata 'vox:pyramid' is not valid JSON: ") + e.what());
  }
  if (!pyramid.is_object() || !pyramid.contains("levels") || !pyramid["levels"].is_array())
    bad(path, "metadata 'vox:pyramid' needs a 'levels' array");
  const size_t nLevels = pyramid["levels"].size();
  const int maxLevel = maxMipLevels(base.dims);
  if (nLevels > size_t(maxLevel))
    bad(path, "metadata 'vox:pyramid' lists " + std::to_string(nLevels) + " levels; a " + toString(base.dims) +
                  " grid has at most " + std::to_string(maxLevel));
  // Grids by level (n >= 1): "mip<n>.<name>".
  std::map<int, std::vector<openvdb::GridBase::Ptr>> byLevel;
  for (const openvdb::GridBase::Ptr& g : *grids) {
    const std::string name = g->getName();
    if (name.rfind("mip", 0) != 0) continue;
    const size_t dot = name.find('.');
    const std::string num = name.substr(3, dot == std::string::npos ? std::string::npos : dot - 3);
    int n = -1;
    try {
      n = std::stoi(num);
    } catch (...) {
    }
    if (dot == std::string::npos || n < 1 || size_t(n) > nLevels || num != std::to_string(n))
      bad(path, "grid '" + name + "' is not mip<level>.<grid> with a level of 'vox:pyramid' (1.." +
                    std::to_string(nLevels) + ")");
    byLevel[n].push_back(g);
  }
  for (size_t n = 1; n <= nLevels; ++n) {
    const std::string where = "level " + std::to_string(n);
    Scene scene;
    SceneHeader& h = scene.header();
    h = base;
    h.mipLevel = base.mipLevel + int(n);
    h.dims = mipDims(base.dims, int(n));
    h.voxelSize = base.voxelSize * double(uint64_t(1) << n);
    SceneGrids& g = scene.grids();
    g.occupancy.reset();
    const openvdb::CoordBBox domain(openvdb::Coord(0), openvdb::Coord(int(h.dims.x) - 1, int(h.dims.y) - 1, int(h.dims.z) - 1));
    for (const openvdb::GridBase::Ptr& gb : byLevel[int(n)]) {
      const std::string full = gb->getName();
      const std::string name = full.substr(full.find('.') + 1);
      if (gb->activeVoxelCount() > 0 && !domain.isInside(gb->evalActiveVoxelBoundingBox()))
        bad(path, where + ": grid '" + full + "' has active voxels outside the level's dims " + toString(h.dims));
      gb->setTransform(openvdb::math::Transform::createLinearTransform(1.0));
      if (name == "occupancy") {
        auto grid = openvdb::GridBase::grid<openvdb::BoolGrid>(gb);
        if (!grid) bad(path, where + ": grid '" + full + "' has type " + gb->type() + ", expected bool");
        grid->tree().voxelizeActiveTiles();
        g.occupancy = grid;
      } else if (name.rfind("votes.", 0) == 0) {
        auto grid = openvdb::GridBase::grid<openvdb::Int32Grid>(gb);
        if (!grid) bad(path, where + ": grid '" + full + "' has type " + gb->type() + ", expected int32");
        int id = -1;
        try {
          id = std::stoi(name.substr(6));
        } catch (...) {
        }
        if (id < 1 || id > 255 || name != "votes." + std::to_string(id) || !h.classes.find(uint8_t(id)))
          bad(path, where + ": grid '" + full + "' is not votes.<a class id of 'vox:classes'>");
        grid->tree().voxelizeActiveTiles();
        for (auto it = grid->cbeginValueOn(); it; ++it)
          if (*it <= 0) bad(path, where + ": grid '" + full + "' has a vote count <= 0");
        grid->setName(name);
        g.votes.push_back({uint8_t(id), grid});
      } else if (name == "color") {
        auto grid = openvdb::GridBase::grid<openvdb::Vec3SGrid>(gb);
        if (!grid) bad(path, where + ": grid '" + full + "' has type " + gb->type() + ", expected vec3s");
        grid->tree().voxelizeActiveTiles();
        g.color = grid;
      }
    }
    if (!g.occupancy) bad(path, where + ": no grid 'mip" + std::to_string(n) + ".occupancy'");
    g.occupancy->setName("occupancy");
    if (g.color) g.color->setName("color");
    std::sort(g.votes.begin(), g.votes.end(), [](const ClassGrid& a, const ClassGrid& b) { return a.classId < b.classId; });
    for (size_t i = 1; i < g.votes.size(); ++i)
      if (g.votes[i].classId == g.votes[i - 1].classId) bad(path, where + ": two vote grids for one class");
    auto occ = g.occupancy->getConstAccessor();
    for (ClassGrid& cg : g.votes)
      for (auto it = cg.grid->cbeginValueOn(); it; ++it)
        if (!occ.isValueOn(it.getCoord())) bad(path, where + ": grid 'mip" + std::to_string(n) + ".votes." +
                                                         std::to_string(cg.classId) + "' has a vote at an unoccupied voxel");
    if (g.color)
      for (auto it = g.color->cbeginValueOn(); it; ++it)
        if (!occ.isValueOn(it.getCoord())) bad(path, where + ": grid 'mip" + std::to_string(n) + ".color' has a colour at an unoccupied voxel");
    std::vector<openvdb::Int32Grid::ConstAccessor> accs;
    for (ClassGrid& cg : g.votes) accs.push_back(cg.grid->getConstAccessor());
    for (auto it = g.occupancy->cbeginValueOn(); it; ++it) {
      bool any = false;
      for (auto& a : accs) any = any || a.isValueOn(it.getCoord());
      if (!any) bad(path, where + ": occupied voxel " + toString(Coord3{it.getCoord().x(), it.getCoord().y(), it.getCoord().z()}) +
                              " has no votes");
    }
    levels.push_back(std::move(scene));
  }
  return levels;
}

}  // namespace vox
