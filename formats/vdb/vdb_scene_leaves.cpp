#include "formats/vdb/vdb_scene_leaves.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cstring>
#include <unordered_map>
#include <variant>

#include "formats/core/file_util.h"
#include "formats/vdb/vdb_memory.h"
#include "formats/vdb/vdb_structure.h"
#include "libvox/core/bits.h"
#include "libvox/core/error.h"

// No OpenVDB here: `vox pack-chunks` runs in a module that does not load it
// (tools/cmds/pack_main.cpp, docs/startup.md).

namespace vox {

namespace {

/// The file is not of the form, or fails a scene check: read it the usual way.
struct NotOfTheForm {};

// Grid types as OpenVDB names them (Grid<T>::gridType()), for the standard 5-4-3 trees.
constexpr const char* kBoolTree = "Tree_bool_5_4_3";
constexpr const char* kInt32Tree = "Tree_int32_5_4_3";
constexpr const char* kVec3sTree = "Tree_vec3s_5_4_3";

/// Metadata as stored (count, then name, type name, size and value per entry),
/// already checked by the walk, as metaEntriesOf reads it back from an
/// openvdb::MetaMap: the five scene types by value, others as foreign by type name.
MetaEntries parseMeta(const uint8_t* p, size_t n) {
  size_t at = 0;
  auto take = [&](size_t bytes) {
    if (bytes > n - at) throw NotOfTheForm{};
    const uint8_t* q = p + at;
    at += bytes;
    return q;
  };
  auto u32 = [&] {
    uint32_t v;
    std::memcpy(&v, take(4), 4);
    return v;
  };
  auto str = [&] {
    const uint32_t len = u32();
    return std::string(reinterpret_cast<const char*>(take(len)), len);
  };
  MetaEntries out;
  const uint32_t count = u32();
  for (uint32_t i = 0; i < count; ++i) {
    std::string key = str(), type = str();
    const uint32_t size = u32();
    const uint8_t* v = take(size);
    auto fixed = [&](auto value) {
      if (size != sizeof value) throw NotOfTheForm{};
      std::memcpy(&value, v, sizeof value);
      return value;
    };
    MetaValue value;
    if (type == "string") value = std::string(reinterpret_cast<const char*>(v), size);
    else if (type == "int32") value = fixed(int32_t{});
    else if (type == "double") value = fixed(double{});
    else if (type == "vec3i") value = fixed(std::array<int32_t, 3>{});
    else if (type == "vec3d") value = fixed(std::array<double, 3>{});
    else value = ForeignMetaValue{type};
    if (!out.emplace(std::move(key), std::move(value)).second) throw NotOfTheForm{};
  }
  return out;
}

/// Receives the walk for readSceneLeaves: the scene's grids kept as leaves
/// (masks and active values), other grids' blocks decoded (so checked as the
/// one-pass reader checks them) and dropped. A scene check that fails throws
/// NotOfTheForm: the caller reads the file the usual way, which names it.
class LeavesSink final : public VdbWalkSink {
 public:
  LeavesSink(const std::string& path, bool occupancyOnly, uint64_t fileBytes)
      : path_(path), occupancyOnly_(occupancyOnly), fileBytes_(fileBytes) {}

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
    if (activeCount(mask) == 0 || (role.kind != Role::Occupancy && (v.compressionMeta != 0 || v.count != activeCount(mask))))
      notPlain_ = true;  // an empty leaf, or inactive values that are not the background
    if (role.kind == Role::Occupancy) {
      OccupancyLeaf& o = out_.occupancy[index];
      o.origin = v.origin;
      o.mask = mask;
      std::memcpy(o.surface.data(), v.boolValues, 64);
      for (size_t w = 0; w < 8; ++w)
        if (o.surface[w] & ~mask[w]) notPlain_ = true;
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
    if (!occupancyOnly_ && !join()) throw NotOfTheForm{};
    return std::move(out_);
  }

 private:
  struct Role {
    enum Kind { Ignored, Occupancy, Votes, Color } kind = Ignored;
    size_t slot = 0;  // Votes: index in out_.votes
  };

  static size_t activeCount(const std::array<uint64_t, 8>& mask) {
    size_t n = 0;
    for (uint64_t w : mask) n += size_t(bitCount(w));
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
    out_.metadata = parseMeta(meta_, metaBytes_);
    out_.header = sceneHeaderFromMetadata(out_.metadata, path_);
    checkSceneReadMemory(frame, occupancyOnly_, path_, SceneReadForm::PackedLeaves, fileBytes_);
    roles_.resize(frame.grids.size());
    bool occupancy = false;
    for (size_t i = 0; i < frame.grids.size(); ++i) {
      const VdbGridFrame& g = frame.grids[i];
      const VdbGridLayout& l = layouts[i];
      // The name levelGridsFromVdb goes by: the grid's "name" metadata.
      const MetaEntries gridMeta = parseMeta(l.metadata, l.metadataBytes);
      const auto nameAt = gridMeta.find("name");
      if (nameAt != gridMeta.end() && !std::holds_alternative<std::string>(nameAt->second)) throw NotOfTheForm{};
      const std::string name = nameAt == gridMeta.end() ? "" : std::get<std::string>(nameAt->second);
      if (occupancyOnly_ && name != g.uniqueName) throw NotOfTheForm{};
      const size_t leaves = size_t(g.leafCount);
      Role& r = roles_[i];
      if (!plainGrid(name, gridMeta, l, leaves)) notPlain_ = true;
      if (name == kOccupancyGridName) {
        if (occupancy || g.type != kBoolTree) throw NotOfTheForm{};
        occupancy = true;
        r.kind = Role::Occupancy;
        out_.occupancy.resize(leaves);
      } else if (looksLikeVoteGridName(name)) {
        const std::optional<uint8_t> id = classIdOfVoteGridName(name);
        if (g.type != kInt32Tree || !id || !out_.header.classes.find(*id)) throw NotOfTheForm{};
        for (const SceneLeaves::Votes& v : out_.votes)
          if (v.classId == *id) throw NotOfTheForm{};
        r.kind = Role::Votes;
        r.slot = out_.votes.size();
        out_.votes.emplace_back().classId = *id;
        out_.votes.back().leaves.resize(leaves);
      } else if (name == kColorGridName) {
        if (out_.hasColor || g.type != kVec3sTree) throw NotOfTheForm{};
        out_.hasColor = true;
        r.kind = Role::Color;
        out_.colorLeaves.resize(leaves);
      } else if (g.type != kBoolTree && g.type != kInt32Tree &&
                 g.type != kVec3sTree) {
        throw NotOfTheForm{};  // the one-pass reader's form: the usual path reads such files
      }
    }
    if (!occupancy) throw NotOfTheForm{};
    std::vector<VdbLeafUse> use(frame.grids.size(), VdbLeafUse::Deliver);
    if (occupancyOnly_) {
      // Nothing of the other grids is kept: their blocks are framed, not decompressed.
      for (size_t i = 0; i < frame.grids.size(); ++i)
        if (roles_[i].kind != Role::Occupancy) {
          roles_[i].kind = Role::Ignored;
          use[i] = VdbLeafUse::Frame;
        }
      out_.votes.clear();
      out_.hasColor = false;
    }
    return use;
  }

  /// A scene grid whose background is 0, whose metadata keys are among those
  /// voxbake's writers give it (which a rewrite replaces) and, for votes, with
  /// leaves; or another grid.
  static bool plainGrid(const std::string& name, const MetaEntries& meta, const VdbGridLayout& l, size_t leaves) {
    MetaEntries own;
    if (looksLikeVoteGridName(name) && leaves == 0) return false;
    if (looksLikeVoteGridName(name)) own = voteGridMetadata(ClassTable{}, 0);
    else if (name == kColorGridName) own = colorGridMetadata(), own["vector_type"] = std::string();
    else if (name != kOccupancyGridName) return true;
    for (const char* key : {"name", "file_bbox_min", "file_bbox_max", "file_compression", "file_mem_bytes",
                            "file_voxel_count", "is_saved_as_half_float", "file_delayed_load"})
      own[key] = std::string();
    for (const auto& entry : meta)
      if (!own.count(entry.first)) return false;
    for (uint32_t b = 0; b < l.valueSize; ++b)
      if (l.background[b] != 0) return false;
    return true;
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
    out_.plainForm = !notPlain_;  // every leaf is in
    return true;
  }

  std::string path_;
  bool occupancyOnly_;
  uint64_t fileBytes_ = 0;  // the mapped file's size, for the memory guard
  const uint8_t* meta_ = nullptr;
  size_t metaBytes_ = 0;
  std::vector<Role> roles_;
  SceneLeaves out_;
  std::atomic<bool> notPlain_{false};  // set by leaf() on several threads
};

}  // namespace

std::optional<SceneLeaves> readSceneLeaves(const std::string& path, SceneLeafParts parts) {
  checkVdbFileOpenable(path);
  const FileView file(path);  // mapped
  LeavesSink sink(path, parts == SceneLeafParts::OccupancyOnly, file.size());
  try {
    walkVdbInto(reinterpret_cast<const uint8_t*>(file.data()), file.size(), path, sink);
    return sink.take();
  } catch (const NotOfTheForm&) {
    return std::nullopt;
  }
}

}  // namespace vox
