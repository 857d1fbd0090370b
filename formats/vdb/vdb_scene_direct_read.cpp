#include "formats/vdb/vdb_scene_direct_read.h"

#include <openvdb/io/io.h>
#include <openvdb/tree/ValueAccessor.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <istream>
#include <memory>
#include <streambuf>
#include <unordered_map>
#include <type_traits>
#include <vector>

#include "formats/core/file_util.h"
#include "formats/vdb/vdb_checked_file.h"
#include "formats/vdb/vdb_memory.h"
#include "formats/vdb/vdb_scene_leaves.h"
#include "formats/vdb/vdb_structure.h"
#include "libvox/core/error.h"
#include "libvox/scene/scene_grids.h"

namespace vox {

namespace {

/// Thrown by the sink for a file not of the form: it is read the old way.
struct NotOfTheForm {};

/// A read-only stream over walked bytes, for OpenVDB's metadata and transform
/// readers. The bytes stay within their range whatever the reader does.
class ByteStream : private std::streambuf, public std::istream {
 public:
  ByteStream(const uint8_t* p, size_t n, const VdbFrame& frame) : std::istream(static_cast<std::streambuf*>(this)) {
    char* b = const_cast<char*>(reinterpret_cast<const char*>(p));  // never written: get area only
    setg(b, b, b + n);
    // The file's versions, as io::File tags its stream (old versions read
    // transforms differently).
    openvdb::io::setVersion(*this, openvdb::VersionId(frame.libraryMajor, frame.libraryMinor), frame.fileVersion);
  }

 private:
  // Seeking within the bytes, for readers that skip or measure.
  std::streampos seekoff(std::streamoff off, std::ios_base::seekdir dir, std::ios_base::openmode) override {
    const std::streamoff size = egptr() - eback(), at = gptr() - eback();
    const std::streamoff to = dir == std::ios_base::beg ? off : dir == std::ios_base::cur ? at + off : size + off;
    if (to < 0 || to > size) return std::streampos(std::streamoff(-1));
    setg(eback(), eback() + to, egptr());
    return std::streampos(to);
  }
  std::streampos seekpos(std::streampos pos, std::ios_base::openmode which) override {
    return seekoff(std::streamoff(pos), std::ios_base::beg, which);
  }
};

/// The 512-bit masks of a leaf from the 64 bytes the file stores.
template <typename MaskT>
void loadMask(MaskT& mask, const uint8_t* bytes) {
  for (openvdb::Index w = 0; w < MaskT::WORD_COUNT; ++w)
    std::memcpy(&mask.template getWord<openvdb::Index64>(w), bytes + 8 * w, 8);
}

/// The leaves of one grid, built concurrently, then added to its tree.
class TreeBuilder {
 public:
  virtual ~TreeBuilder() = default;
  virtual void leaf(size_t index, const VdbLeafValues& v) = 0;
  virtual void assemble() = 0;
  openvdb::GridBase::Ptr grid;
};

template <typename GridT>
class TypedTreeBuilder final : public TreeBuilder {
  using TreeT = typename GridT::TreeType;
  using LeafT = typename TreeT::LeafNodeType;
  using ValueT = typename GridT::ValueType;

 public:
  TypedTreeBuilder(typename GridT::Ptr g, size_t leafCount) : typed_(g), background_(g->background()), leaves_(leafCount) {
    grid = g;
  }

  void leaf(size_t index, const VdbLeafValues& v) override {
    auto leaf = std::make_unique<LeafT>(openvdb::PartialCreate(), openvdb::Coord(v.origin[0], v.origin[1], v.origin[2]),
                                        background_, false);
    loadMask(leaf->getValueMask(), v.valueMask);
    if constexpr (std::is_same_v<ValueT, bool>) {
      // LeafNode<bool>::readBuffers: the values are a second bit mask.
      typename LeafT::NodeMaskType bits;
      loadMask(bits, v.boolValues);
      leaf->buffer() = typename LeafT::Buffer(bits);
    } else {
      leaf->allocate();
      values(leaf->buffer().data(), leaf->getValueMask(), v);
    }
    leaves_[index] = std::move(leaf);
  }

  void assemble() override {
    // File order is tree order: the accessor keeps the path to the last leaf.
    openvdb::tree::ValueAccessor<TreeT> acc(typed_->tree());
    for (std::unique_ptr<LeafT>& leaf : leaves_) acc.addLeaf(leaf.release());
    std::vector<std::unique_ptr<LeafT>>().swap(leaves_);
  }

 private:
  /// io::readCompressedValues' result for one leaf: `v.count` values are
  /// either all 512 or the active ones in voxel order; inactive voxels get
  /// the background, its negation or the stored inactive values, picked by
  /// the selection mask.
  void values(ValueT* dst, const typename LeafT::NodeMaskType& active, const VdbLeafValues& v) const {
    constexpr size_t size = sizeof(ValueT);
    if (v.count == LeafT::SIZE) {
      std::memcpy(static_cast<void*>(dst), v.values, LeafT::SIZE * size);
      return;
    }
    ValueT inactive0 = v.compressionMeta == 0 ? background_ : openvdb::math::negative(background_);
    ValueT inactive1 = background_;
    if (v.inactive[0]) std::memcpy(static_cast<void*>(&inactive0), v.inactive[0], size);
    if (v.inactive[1]) std::memcpy(static_cast<void*>(&inactive1), v.inactive[1], size);
    std::fill(dst, dst + LeafT::SIZE, inactive0);
    if (v.selectionMask) {
      typename LeafT::NodeMaskType selection;
      loadMask(selection, v.selectionMask);
      for (auto it = selection.beginOn(); it; ++it) dst[it.pos()] = inactive1;
    }
    size_t t = 0;
    for (openvdb::Index w = 0; w < LeafT::NodeMaskType::WORD_COUNT; ++w)
      for (uint64_t bits = active.template getWord<openvdb::Index64>(w); bits; bits &= bits - 1)
        std::memcpy(static_cast<void*>(&dst[w * 64 + openvdb::Index(std::countr_zero(bits))]), v.values + size * t++, size);
  }

  typename GridT::Ptr typed_;
  ValueT background_;
  std::vector<std::unique_ptr<LeafT>> leaves_;
};

/// Receives the walk: the scene's metadata and header, the memory guard, then
/// each read grid's leaves.
class SceneSink final : public VdbWalkSink {
 public:
  SceneSink(const std::string& path, bool occupancyOnly) : path_(path), occupancyOnly_(occupancyOnly) {}

  void fileMetadata(const uint8_t* bytes, size_t size) override {
    meta_ = bytes;
    metaBytes_ = size;
  }

  std::vector<VdbLeafUse> topologyWalked(const VdbFrame& frame, const std::vector<VdbGridLayout>& layouts) override {
    for (size_t i = 0; i < frame.grids.size(); ++i) {
      const VdbGridFrame& g = frame.grids[i];
      const VdbGridLayout& l = layouts[i];
      if (!g.checked || !g.instanceParent.empty() || l.halfFloat || !l.leavesOnly || kindOf(g.type) == Kind::Other)
        throw NotOfTheForm{};
    }
    try {
      ByteStream in(meta_, metaBytes_, frame);
      openvdb::MetaMap meta;
      meta.readMeta(in);
      file_.metadata = metaEntriesOf(meta);
    } catch (...) {
      rethrowVdbReadError(path_, "the OpenVDB file metadata");
    }
    file_.header = sceneHeaderFromMetadata(file_.metadata, path_);
    checkSceneReadMemory(frame, occupancyOnly_, path_);
    std::vector<VdbLeafUse> use(frame.grids.size(), VdbLeafUse::Frame);
    builders_.resize(frame.grids.size());
    for (size_t i = 0; i < frame.grids.size(); ++i) {
      const VdbGridFrame& g = frame.grids[i];
      if (occupancyOnly_ && g.uniqueName != kOccupancyGridName) continue;
      use[i] = VdbLeafUse::Deliver;
      switch (kindOf(g.type)) {
        case Kind::Bool: builders_[i] = builder<openvdb::BoolGrid>(frame, g, layouts[i]); break;
        case Kind::Int32: builders_[i] = builder<openvdb::Int32Grid>(frame, g, layouts[i]); break;
        case Kind::Vec3s: builders_[i] = builder<openvdb::Vec3SGrid>(frame, g, layouts[i]); break;
        case Kind::Other: throw NotOfTheForm{};
      }
    }
    return use;
  }

  void leaf(size_t grid, size_t index, const VdbLeafValues& values) override { builders_[grid]->leaf(index, values); }

  void gridDone(size_t grid) override { builders_[grid]->assemble(); }

  VdbSceneFile take() {
    for (const std::unique_ptr<TreeBuilder>& b : builders_)
      if (b) file_.grids.push_back(b->grid);
    builders_.clear();
    return std::move(file_);
  }

 private:
  enum class Kind { Bool, Int32, Vec3s, Other };
  static Kind kindOf(const std::string& type) {
    if (type == openvdb::BoolGrid::gridType()) return Kind::Bool;
    if (type == openvdb::Int32Grid::gridType()) return Kind::Int32;
    if (type == openvdb::Vec3SGrid::gridType()) return Kind::Vec3s;
    return Kind::Other;
  }

  /// The grid as Archive::readGrid makes it before its tree: the root's
  /// background, the grid metadata (without the delayed-load index, which
  /// OpenVDB drops on read) and the transform.
  template <typename GridT>
  std::unique_ptr<TreeBuilder> builder(const VdbFrame& frame, const VdbGridFrame& g, const VdbGridLayout& l) {
    typename GridT::ValueType background;
    std::memcpy(static_cast<void*>(&background), l.background, sizeof background);
    typename GridT::Ptr grid = GridT::create(background);
    try {
      grid->setSaveFloatAsHalf(false);
      ByteStream meta(l.metadata, l.metadataBytes, frame);
      grid->readMeta(meta);
      if ((*grid)[openvdb::GridBase::META_FILE_DELAYED_LOAD]) grid->removeMeta(openvdb::GridBase::META_FILE_DELAYED_LOAD);
      ByteStream transform(l.transform, l.transformBytes, frame);
      grid->readTransform(transform);
    } catch (...) {
      rethrowVdbReadError(path_, "grid '" + g.uniqueName + "'");
    }
    return std::make_unique<TypedTreeBuilder<GridT>>(grid, size_t(g.leafCount));
  }

  std::string path_;
  bool occupancyOnly_;
  const uint8_t* meta_ = nullptr;
  size_t metaBytes_ = 0;
  VdbSceneFile file_;
  std::vector<std::unique_ptr<TreeBuilder>> builders_;
};

/// Receives the walk for readSceneLeaves: the scene's grids kept as leaves
/// (masks and active values), other grids' blocks decoded (so checked as the
/// one-pass reader checks them) and dropped. A scene check that fails throws
/// NotOfTheForm: the caller reads the file the usual way, which names it.
class LeavesSink final : public VdbWalkSink {
 public:
  explicit LeavesSink(const std::string& path) : path_(path) {}

  void fileMetadata(const uint8_t* bytes, size_t size) override {
    meta_ = bytes;
    metaBytes_ = size;
  }

  std::vector<VdbLeafUse> topologyWalked(const VdbFrame& frame, const std::vector<VdbGridLayout>& layouts) override {
    try {
      return roles(frame, layouts);
    } catch (const NotOfTheForm&) {
      throw;
    } catch (...) {  // bad metadata, no scene header, the memory guard: the usual reader says which
      throw NotOfTheForm{};
    }
  }

  void leaf(size_t grid, size_t index, const VdbLeafValues& v) override {
    const Role role = roles_[grid];
    if (role.kind == Role::Ignored) return;
    std::array<uint64_t, 8> mask;
    std::memcpy(mask.data(), v.valueMask, 64);
    if (!insideDims(v.origin, mask)) throw NotOfTheForm{};  // "active voxels outside the dims"
    if (role.kind == Role::Occupancy) {
      OccupancyLeaf& o = out_.occupancy[index];
      o.origin = v.origin;
      o.mask = mask;
      std::memcpy(o.surface.data(), v.boolValues, 64);
      return;
    }
    if (role.kind == Role::Votes) {
      SceneLeaf<int32_t>& l = out_.votes[role.slot].leaves[index];
      l.origin = v.origin;
      l.mask = mask;
      l.values = activeValues<int32_t>(mask, v);
      const size_t n = activeCount(mask);
      for (size_t i = 0; i < n; ++i)
        if (l.values[i] <= 0) throw NotOfTheForm{};  // "counts must be >= 1"
      return;
    }
    SceneLeaf<std::array<float, 3>>& l = out_.colorLeaves[index];
    l.origin = v.origin;
    l.mask = mask;
    l.values = activeValues<std::array<float, 3>>(mask, v);
  }

  void gridDone(size_t) override {}

  /// The joins and the topology checks, once every leaf is in.
  SceneLeaves take() {
    if (!join()) throw NotOfTheForm{};
    return std::move(out_);
  }

 private:
  struct Role {
    enum Kind { Ignored, Occupancy, Votes, Color } kind = Ignored;
    size_t slot = 0;  // Votes: index in out_.votes
  };

  static size_t activeCount(const std::array<uint64_t, 8>& mask) {
    size_t n = 0;
    for (uint64_t w : mask) n += size_t(std::popcount(w));
    return n;
  }

  /// The values of the active voxels in ascending voxel order, from a buffer
  /// of all 512 values or of the active ones.
  template <typename T>
  static std::unique_ptr<T[]> activeValues(const std::array<uint64_t, 8>& mask, const VdbLeafValues& v) {
    const size_t n = activeCount(mask);
    if (v.count != 512 && v.count != n) throw NotOfTheForm{};
    std::unique_ptr<T[]> out(new T[n]);
    if (v.count == n) {
      std::memcpy(static_cast<void*>(out.get()), v.values, n * sizeof(T));
      return out;
    }
    size_t t = 0;
    for (size_t w = 0; w < 8; ++w)
      for (uint64_t bits = mask[w]; bits; bits &= bits - 1)
        std::memcpy(static_cast<void*>(&out[t++]), v.values + sizeof(T) * (w * 64 + size_t(std::countr_zero(bits))),
                    sizeof(T));
    return out;
  }

  /// Every active voxel of the leaf lies inside the scene's dims, and the leaf
  /// can be joined by a 63-bit key (origins below 2^24).
  bool insideDims(const std::array<int32_t, 3>& o, const std::array<uint64_t, 8>& mask) const {
    uint64_t any = 0;
    for (uint64_t w : mask) any |= w;
    if (!any) return true;
    const std::array<uint32_t, 3> dims{out_.header.dims.x, out_.header.dims.y, out_.header.dims.z};
    bool whole = true;
    for (int a = 0; a < 3; ++a) {
      if (o[a] < 0 || o[a] >= (1 << 24)) return false;
      whole = whole && int64_t(o[a]) + 8 <= int64_t(dims[a]);
    }
    if (whole) return true;
    for (size_t w = 0; w < 8; ++w)
      for (uint64_t bits = mask[w]; bits; bits &= bits - 1) {
        const uint32_t off = uint32_t(w * 64 + size_t(std::countr_zero(bits)));
        if (uint32_t(o[0]) + (off >> 6) >= dims[0] || uint32_t(o[1]) + ((off >> 3) & 7) >= dims[1] ||
            uint32_t(o[2]) + (off & 7) >= dims[2])
          return false;
      }
    return true;
  }

  static uint64_t leafKey(const std::array<int32_t, 3>& o) {
    return uint64_t(uint32_t(o[0]) >> 3) << 42 | uint64_t(uint32_t(o[1]) >> 3) << 21 | uint64_t(uint32_t(o[2]) >> 3);
  }

  std::vector<VdbLeafUse> roles(const VdbFrame& frame, const std::vector<VdbGridLayout>& layouts) {
    for (size_t i = 0; i < frame.grids.size(); ++i) {
      const VdbGridFrame& g = frame.grids[i];
      const VdbGridLayout& l = layouts[i];
      if (!g.checked || !g.instanceParent.empty() || l.halfFloat || !l.leavesOnly) throw NotOfTheForm{};
    }
    ByteStream in(meta_, metaBytes_, frame);
    openvdb::MetaMap meta;
    meta.readMeta(in);
    out_.metadata = metaEntriesOf(meta);
    out_.header = sceneHeaderFromMetadata(out_.metadata, path_);
    checkSceneReadMemory(frame, false, path_);
    roles_.resize(frame.grids.size());
    bool occupancy = false;
    for (size_t i = 0; i < frame.grids.size(); ++i) {
      const VdbGridFrame& g = frame.grids[i];
      const VdbGridLayout& l = layouts[i];
      // The name levelGridsFromVdb goes by: the grid's "name" metadata.
      ByteStream gridMeta(l.metadata, l.metadataBytes, frame);
      openvdb::MetaMap gm;
      gm.readMeta(gridMeta);
      const openvdb::Metadata::ConstPtr nameMeta = gm[openvdb::GridBase::META_GRID_NAME];
      const std::string name = nameMeta ? nameMeta->str() : "";
      const size_t leaves = size_t(g.leafCount);
      Role& r = roles_[i];
      if (name == kOccupancyGridName) {
        if (occupancy || g.type != openvdb::BoolGrid::gridType()) throw NotOfTheForm{};
        occupancy = true;
        r.kind = Role::Occupancy;
        out_.occupancy.resize(leaves);
      } else if (looksLikeVoteGridName(name)) {
        const std::optional<uint8_t> id = classIdOfVoteGridName(name);
        if (g.type != openvdb::Int32Grid::gridType() || !id || !out_.header.classes.find(*id)) throw NotOfTheForm{};
        for (const SceneLeaves::Votes& v : out_.votes)
          if (v.classId == *id) throw NotOfTheForm{};
        r.kind = Role::Votes;
        r.slot = out_.votes.size();
        out_.votes.emplace_back().classId = *id;
        out_.votes.back().leaves.resize(leaves);
      } else if (name == kColorGridName) {
        if (out_.hasColor || g.type != openvdb::Vec3SGrid::gridType()) throw NotOfTheForm{};
        out_.hasColor = true;
        r.kind = Role::Color;
        out_.colorLeaves.resize(leaves);
      } else if (g.type != openvdb::BoolGrid::gridType() && g.type != openvdb::Int32Grid::gridType() &&
                 g.type != openvdb::Vec3SGrid::gridType()) {
        throw NotOfTheForm{};  // the one-pass reader's form: the usual path reads such files
      }
    }
    if (!occupancy) throw NotOfTheForm{};
    return std::vector<VdbLeafUse>(frame.grids.size(), VdbLeafUse::Deliver);
  }

  /// Joins the vote and colour leaves to the occupancy leaves; false when a
  /// vote or colour lies outside the occupancy or an occupied voxel has no vote.
  bool join() {
    std::unordered_map<uint64_t, uint32_t> byOrigin;
    byOrigin.reserve(out_.occupancy.size());
    for (size_t i = 0; i < out_.occupancy.size(); ++i) byOrigin.emplace(leafKey(out_.occupancy[i].origin), uint32_t(i));
    auto joinGrid = [&](const auto& leaves, std::vector<uint32_t>& at) {
      at.assign(out_.occupancy.size(), SceneLeaves::kNoLeaf);
      for (size_t j = 0; j < leaves.size(); ++j) {
        if (activeCount(leaves[j].mask) == 0) continue;
        const auto found = byOrigin.find(leafKey(leaves[j].origin));
        if (found == byOrigin.end()) return false;
        const OccupancyLeaf& o = out_.occupancy[found->second];
        for (size_t w = 0; w < 8; ++w)
          if (leaves[j].mask[w] & ~o.mask[w]) return false;
        at[found->second] = uint32_t(j);
      }
      return true;
    };
    std::sort(out_.votes.begin(), out_.votes.end(),
              [](const SceneLeaves::Votes& a, const SceneLeaves::Votes& b) { return a.classId < b.classId; });
    for (SceneLeaves::Votes& v : out_.votes)
      if (!joinGrid(v.leaves, v.at)) return false;
    if (out_.hasColor && !joinGrid(out_.colorLeaves, out_.colorAt)) return false;
    for (size_t i = 0; i < out_.occupancy.size(); ++i) {
      std::array<uint64_t, 8> unvoted = out_.occupancy[i].mask;
      for (const SceneLeaves::Votes& v : out_.votes)
        if (v.at[i] != SceneLeaves::kNoLeaf)
          for (size_t w = 0; w < 8; ++w) unvoted[w] &= ~v.leaves[v.at[i]].mask[w];
      for (uint64_t w : unvoted)
        if (w) return false;
    }
    return true;
  }

  std::string path_;
  const uint8_t* meta_ = nullptr;
  size_t metaBytes_ = 0;
  std::vector<Role> roles_;
  SceneLeaves out_;
};

}  // namespace

std::optional<VdbSceneFile> readVdbSceneFileDirect(const std::string& path, bool occupancyOnly) {
  checkVdbFileOpenable(path);
  ensureOpenVdbInitialized();
  const FileView file(path);  // mapped
  SceneSink sink(path, occupancyOnly);
  try {
    walkVdbInto(reinterpret_cast<const uint8_t*>(file.data()), file.size(), path, sink);
  } catch (const NotOfTheForm&) {
    return std::nullopt;
  }
  return sink.take();
}

}  // namespace vox

namespace vox {

std::optional<SceneLeaves> readSceneLeaves(const std::string& path) {
  checkVdbFileOpenable(path);
  ensureOpenVdbInitialized();
  const FileView file(path);  // mapped
  LeavesSink sink(path);
  try {
    walkVdbInto(reinterpret_cast<const uint8_t*>(file.data()), file.size(), path, sink);
    return sink.take();
  } catch (const NotOfTheForm&) {
    return std::nullopt;
  }
}

}  // namespace vox
