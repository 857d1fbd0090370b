#include "formats/vdb/vdb_scene_direct_read.h"

#include <openvdb/io/io.h>
#include <openvdb/tree/ValueAccessor.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <istream>
#include <memory>
#include <streambuf>
#include <type_traits>
#include <vector>

#include "formats/core/file_util.h"
#include "formats/vdb/vdb_checked_file.h"
#include "formats/vdb/vdb_memory.h"
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

std::optional<VdbSceneFile> readVdbSceneFileDirect(VdbTopologyWalk& walked, bool occupancyOnly) {
  ensureOpenVdbInitialized();
  SceneSink sink(walked.path(), occupancyOnly);
  try {
    walked.finish(sink);
  } catch (const NotOfTheForm&) {
    return std::nullopt;
  }
  return sink.take();
}

}  // namespace vox
