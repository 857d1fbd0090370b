#include "formats/vdb/vdb_scene_grids.h"

#include <cerrno>
#include <cstring>

#include <openvdb/io/File.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <functional>
#include <optional>
#include <vector>

#include "formats/core/file_util.h"
#include "formats/scene/vdb_content_uuid.h"
#include "formats/vdb/scene_vdb.h"
#include "formats/vdb/vdb_checked_file.h"
#include "formats/vdb/vdb_memory.h"
#include "formats/vdb/vdb_scene_direct_read.h"
#include "formats/vdb/vdb_structure.h"
#include "libvox/core/error.h"
#include "libvox/core/parallel.h"

namespace vox {

namespace {

[[noreturn]] void bad(const std::string& where, const std::string& what) { throwBadInput(where + ": " + what); }

Coord3 toCoord3(const openvdb::Coord& c) { return {c.x(), c.y(), c.z()}; }

/// The leaves of `tree` in tree order: the order of its value iterators once
/// it has no active tiles.
template <typename TreeT>
std::vector<const typename TreeT::LeafNodeType*> leavesOf(const TreeT& tree) {
  std::vector<const typename TreeT::LeafNodeType*> leaves;
  leaves.reserve(tree.leafCount());
  tree.getNodes(leaves);
  return leaves;
}

/// The first i in [0, n) for which bad(i) holds, else n; checked in parallel
/// (libvox/core/parallel.h), the same at any thread count.
size_t firstBad(size_t n, const std::function<bool(size_t)>& bad) {
  std::atomic<size_t> first{n};
  parallelForEach(n, 0, 256, [&](size_t i) {
    if (i > first.load(std::memory_order_relaxed) || !bad(i)) return;
    size_t now = first.load();
    while (i < now && !first.compare_exchange_weak(now, i)) {
    }
  });
  return first.load();
}

/// The first voxel of `mask` in iteration order, as global coordinates of the leaf at `origin`.
template <typename MaskT>
openvdb::Coord firstOn(const MaskT& mask, const openvdb::Coord& origin) {
  const openvdb::Index n = mask.findFirstOn();
  return origin + openvdb::Coord(int(n >> 6), int((n >> 3) & 7), int(n & 7));
}


}  // namespace

void insertVdbMetadata(openvdb::MetaMap& into, const MetaEntries& entries) {
  for (const auto& [key, value] : entries) {
    struct Insert {
      openvdb::MetaMap& into;
      const std::string& key;
      void operator()(const std::string& v) const { into.insertMeta(key, openvdb::StringMetadata(v)); }
      void operator()(int32_t v) const { into.insertMeta(key, openvdb::Int32Metadata(v)); }
      void operator()(double v) const { into.insertMeta(key, openvdb::DoubleMetadata(v)); }
      void operator()(const std::array<int32_t, 3>& v) const {
        into.insertMeta(key, openvdb::Vec3IMetadata(openvdb::Vec3i(v[0], v[1], v[2])));
      }
      void operator()(const std::array<double, 3>& v) const {
        into.insertMeta(key, openvdb::Vec3DMetadata(openvdb::Vec3d(v[0], v[1], v[2])));
      }
      void operator()(const ForeignMetaValue& v) const {
        throw Error(ErrorKind::Internal, "insertVdbMetadata: '" + key + "' has foreign type " + v.typeName);
      }
    };
    std::visit(Insert{into, key}, value);
  }
}

MetaEntries metaEntriesOf(const openvdb::MetaMap& meta) {
  MetaEntries out;
  for (auto it = meta.beginMeta(); it != meta.endMeta(); ++it) {
    const openvdb::Metadata::Ptr& m = it->second;
    if (auto s = openvdb::DynamicPtrCast<openvdb::StringMetadata>(m)) out[it->first] = s->value();
    else if (auto i = openvdb::DynamicPtrCast<openvdb::Int32Metadata>(m)) out[it->first] = int32_t(i->value());
    else if (auto d = openvdb::DynamicPtrCast<openvdb::DoubleMetadata>(m)) out[it->first] = double(d->value());
    else if (auto v = openvdb::DynamicPtrCast<openvdb::Vec3IMetadata>(m))
      out[it->first] = std::array<int32_t, 3>{v->value().x(), v->value().y(), v->value().z()};
    else if (auto w = openvdb::DynamicPtrCast<openvdb::Vec3DMetadata>(m))
      out[it->first] = std::array<double, 3>{w->value().x(), w->value().y(), w->value().z()};
    else out[it->first] = ForeignMetaValue{m->typeName()};
  }
  return out;
}

void appendSceneGrids(const Scene& scene, const std::string& prefix, const MetaEntries& extra, openvdb::GridPtrVec& out) {
  const SceneHeader& h = scene.header();
  const SceneGrids& g = scene.grids();
  openvdb::math::Transform::Ptr xform = voxelCentreTransform(h.voxelSize, h.origin);
  auto add = [&](openvdb::GridBase::ConstPtr grid, const std::string& name, const MetaEntries& gridMeta) {
    // A shallow copy shares the tree, so the in-memory scene is not modified.
    openvdb::GridBase::Ptr copy = openvdb::ConstPtrCast<openvdb::GridBase>(grid)->copyGrid();
    copy->setTransform(xform->copy());
    copy->setName(prefix + name);
    copy->setSaveFloatAsHalf(false);
    insertVdbMetadata(*copy, extra);
    insertVdbMetadata(*copy, gridMeta);
    out.push_back(copy);
    return copy;
  };
  add(g.occupancy, kOccupancyGridName, {});
  for (const ClassGrid& cg : g.votes) add(cg.grid, voteGridName(cg.classId), voteGridMetadata(h.classes, cg.classId));
  if (g.color) add(g.color, kColorGridName, colorGridMetadata())->setVectorType(openvdb::VEC_INVARIANT);
}

void writeVdbFile(const std::string& path, const openvdb::GridPtrVec& grids, const openvdb::MetaMap& meta,
                  const std::string& what) {
  int writeErrno = 0;  // the stream hides it; a failed write leaves it in errno
  try {
    openvdb::io::File file(path);
    file.setCompression(openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK);
    errno = 0;
    file.write(grids, meta);
    file.close();
    writeErrno = errno;
  } catch (const std::exception& e) {
    throwIo(outputName(path) + ": cannot write the " + what + ": " + e.what());
  }
  // OpenVDB writes through a std::ofstream whose failures it does not check: on
  // a full disk it returns normally and leaves a truncated file. Walking the
  // file's framing (every grid must end inside the file) catches that.
  try {
    checkVdbStructure(path, VdbCheck::Framing);
  } catch (const Error&) {
    const bool known = writeErrno == ENOSPC || writeErrno == EFBIG || writeErrno == EDQUOT || writeErrno == EIO;
    throwIo(outputName(path) + ": the " + what + " was not written completely (the file on disk ends early: " +
            (known ? std::string(std::strerror(writeErrno)) : std::string("is the disk full?")) + ")");
  }
  stampVdbContentUuid(path, outputName(path));  // OpenVDB's is random: the same scene, the same bytes
}

VdbSceneFile readVdbSceneFile(const std::string& path, bool occupancyOnly, VdbSceneReader reader) {
  if (reader == VdbSceneReader::Auto)
    if (std::optional<VdbSceneFile> direct = readVdbSceneFileDirect(path, occupancyOnly)) return std::move(*direct);
  return readVdbSceneFileChecked(path, occupancyOnly);
}

VdbSceneFile readVdbSceneFile(VdbTopologyWalk& walked, bool occupancyOnly) {
  if (std::optional<VdbSceneFile> direct = readVdbSceneFileDirect(walked, occupancyOnly)) return std::move(*direct);
  return readVdbSceneFileChecked(walked.path(), occupancyOnly);
}

VdbSceneFile readVdbSceneFileChecked(const std::string& path, bool occupancyOnly) {
  CheckedVdbFile file(path);  // refuses corrupt files before OpenVDB trusts their sizes
  VdbSceneFile f;
  const openvdb::MetaMap::Ptr meta = file.metadata();
  f.metadata = metaEntriesOf(*meta);
  f.header = sceneHeaderFromMetadata(f.metadata, path);
  checkSceneReadMemory(file.frame(), occupancyOnly, path);  // before any grid is read
  for (const VdbGridFrame& g : file.frame().grids) {
    // Grids vox could not check (point grids) are never read; the scene's own
    // grids are never of such a type, so one named like them is refused.
    const bool sceneName = g.uniqueName.find(kOccupancyGridName) != std::string::npos ||
                           g.uniqueName.find(kColorGridName) != std::string::npos ||
                           g.uniqueName.find("votes.") != std::string::npos;
    if (!g.checked) {
      if (sceneName) bad(path, "grid '" + g.uniqueName + "': " + g.uncheckedWhy);
      continue;
    }
    if (occupancyOnly && g.uniqueName != kOccupancyGridName) continue;
    f.grids.push_back(file.readGrid(g.uniqueName));
  }
  return f;
}

SceneGrids levelGridsFromVdb(const openvdb::GridPtrVec& fileGrids, const std::string& prefix, const SceneHeader& h,
                             const std::string& where, bool checkTopology) {
  SceneGrids g;
  const openvdb::CoordBBox domain(openvdb::Coord(0),
                                  openvdb::Coord(int(h.dims.x) - 1, int(h.dims.y) - 1, int(h.dims.z) - 1));
  for (const openvdb::GridBase::Ptr& base : fileGrids) {
    const std::string fileName = base->getName();
    if (fileName.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string name = fileName.substr(prefix.size());
    const std::string grid = "grid '" + fileName + "'";
    auto expectType = [&](const auto& typed, const char* type) {
      if (!typed) bad(where, grid + " has type " + base->type() + ", expected " + type);
      if (typed->activeVoxelCount() > 0 && !domain.isInside(typed->evalActiveVoxelBoundingBox()))
        bad(where, grid + " has active voxels outside the dims " + toString(h.dims));
      typed->tree().voxelizeActiveTiles();  // other writers may store full blocks as tiles
      typed->setName(name);
      typed->setTransform(openvdb::math::Transform::createLinearTransform(1.0));  // in memory: index space
    };
    if (name == kOccupancyGridName) {
      g.occupancy = openvdb::GridBase::grid<openvdb::BoolGrid>(base);
      expectType(g.occupancy, "bool");
    } else if (looksLikeVoteGridName(name)) {
      auto votes = openvdb::GridBase::grid<openvdb::Int32Grid>(base);
      if (!votes) bad(where, grid + " has type " + base->type() + ", expected int32");
      const std::optional<uint8_t> id = classIdOfVoteGridName(name);
      if (!id) bad(where, grid + " is not named " + prefix + "votes.<class id 1..255>");
      if (!h.classes.find(*id))
        bad(where, grid + " holds votes for class " + std::to_string(*id) + ", which is not in 'vox:classes'");
      expectType(votes, "int32");
      // Leaf by leaf in parallel; the voxel named is the first in iteration order.
      const auto leaves = leavesOf(votes->tree());
      auto nonPositive = [&](size_t i) {
        const auto& leaf = *leaves[i];
        const int32_t* value = leaf.buffer().data();
        for (openvdb::Index w = 0; w < openvdb::Int32Tree::LeafNodeType::NodeMaskType::WORD_COUNT; ++w)
          for (uint64_t bits = leaf.getValueMask().template getWord<openvdb::Index64>(w); bits; bits &= bits - 1)
            if (value[w * 64 + openvdb::Index(std::countr_zero(bits))] <= 0) return true;
        return false;
      };
      const size_t at = firstBad(leaves.size(), nonPositive);
      if (at < leaves.size())
        for (auto it = leaves[at]->cbeginValueOn(); it; ++it)
          if (*it <= 0)
            bad(where, grid + " has vote count " + std::to_string(*it) + " at " + toString(toCoord3(it.getCoord())) +
                           "; counts must be >= 1");
      g.votes.push_back({*id, votes});
    } else if (name == kColorGridName) {
      g.color = openvdb::GridBase::grid<openvdb::Vec3SGrid>(base);
      expectType(g.color, "vec3s");
    }
    // Other grids are ignored, so users may add their own.
  }
  if (!g.occupancy)
    bad(where, "no grid named '" + prefix + kOccupancyGridName + "' (bool)" +
                   (prefix.empty() ? "; this is not a voxbake scene — convert OpenVDB level sets or fog volumes "
                                     "with `vox voxelize FILE.vdb`"
                                   : ""));
  std::sort(g.votes.begin(), g.votes.end(), [](const ClassGrid& a, const ClassGrid& b) { return a.classId < b.classId; });
  for (size_t i = 1; i < g.votes.size(); ++i)
    if (g.votes[i].classId == g.votes[i - 1].classId)
      bad(where, "two vote grids for class " + std::to_string(g.votes[i].classId));
  if (!checkTopology) return g;

  // Every vote and colour voxel is occupied and every occupied voxel has a
  // vote: leaf masks against leaf masks, in parallel. Checks and voxels are
  // named in the order of a voxel-by-voxel walk (vote grids by class, then
  // colour, then occupancy; voxels in iteration order).
  const openvdb::BoolTree& occ = g.occupancy->tree();
  using Mask = openvdb::BoolTree::LeafNodeType::NodeMaskType;
  auto outside = [&](const auto& leaf) {  // the leaf's active voxels that are not occupied
    Mask m = leaf.getValueMask();
    if (const auto* o = occ.probeConstLeaf(leaf.origin())) m -= o->getValueMask();
    return m;
  };
  auto subsetOfOccupancy = [&](const auto& tree, const std::string& message) {
    const auto leaves = leavesOf(tree);
    const size_t at = firstBad(leaves.size(), [&](size_t i) { return !outside(*leaves[i]).isOff(); });
    if (at < leaves.size())
      bad(where, message + toString(toCoord3(firstOn(outside(*leaves[at]), leaves[at]->origin()))));
  };
  for (const ClassGrid& cg : g.votes)
    subsetOfOccupancy(cg.grid->tree(), "grid '" + prefix + cg.grid->getName() + "' has a vote at an unoccupied voxel ");
  if (g.color)
    subsetOfOccupancy(g.color->tree(), "grid '" + prefix + kColorGridName + "' has a colour at an unoccupied voxel ");
  auto unvoted = [&](const openvdb::BoolTree::LeafNodeType& leaf) {  // occupied voxels without a vote
    Mask m = leaf.getValueMask();
    for (const ClassGrid& cg : g.votes)
      if (const auto* v = cg.grid->tree().probeConstLeaf(leaf.origin())) m -= v->getValueMask();
    return m;
  };
  const auto occLeaves = leavesOf(occ);
  const size_t at = firstBad(occLeaves.size(), [&](size_t i) { return !unvoted(*occLeaves[i]).isOff(); });
  if (at < occLeaves.size())
    bad(where, "occupied voxel " + toString(toCoord3(firstOn(unvoted(*occLeaves[at]), occLeaves[at]->origin()))) +
                   " has no votes in any '" + prefix + "votes.<id>' grid");
  return g;
}

}  // namespace vox
