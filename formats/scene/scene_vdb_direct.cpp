#include "formats/scene/scene_vdb_direct.h"

#include "formats/core/file_util.h"
#include "formats/core/writeback.h"
#include "formats/scene/blosc_lz4_frame.h"

#include <algorithm>
#include <array>
#include <bit>
#include <climits>
#include <cmath>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <unordered_map>

#include "formats/scene/scene_meta.h"
#include "formats/scene/vdb_content_uuid.h"
#include "libvox/core/bits.h"
#include "libvox/core/crc32c.h"
#include "libvox/core/error.h"
#include "libvox/core/ordered_pipeline.h"
#include "libvox/core/parallel.h"

namespace vox {

namespace {

// ---------------------------------------------------------------- format constants
// OpenVDB 10: file format 224, library 10.0, trees 5-4-3 (root -> 32^3 -> 16^3 -> 8^3 leaves).
constexpr int64_t kMagic = 0x56444220;
constexpr uint32_t kFileVersion = 224, kLibraryMajor = 10, kLibraryMinor = 0;
constexpr uint32_t kCompressBloscActiveMask = 0x4 | 0x2;  // io::COMPRESS_BLOSC | io::COMPRESS_ACTIVE_MASK
constexpr int kLog2Int4 = 4, kLog2Int5 = 5;               // child counts per axis of the two internal levels
constexpr int kShiftInt4 = kBlockLog2 + kLog2Int4;          // 7: an int4 node spans 128 voxels
constexpr int kShiftInt5 = kShiftInt4 + kLog2Int5;          // 12: an int5 node spans 4096 voxels

enum class GridKind { Bool, Int32, Vec3s };

// Node sizes as OpenVDB's memUsage() counts them (x86-64, OpenVDB 10), for the
// `file_mem_bytes` statistic: tree + root objects, one internal node of each
// level without its children, one leaf.
struct MemSizes {
  uint64_t treeAndRoot, int5, int4, leaf;
};
MemSizes memSizes(GridKind k) {
  switch (k) {
    case GridKind::Bool: return {1304, 270348, 33804, 144};
    case GridKind::Int32: return {1304, 270348, 33804, 2144};
    default: return {1320, 532492, 66572, 6240};
  }
}

// ---------------------------------------------------------------- byte sink

class Sink {
 public:
  Sink(const std::string& path, const std::string& what) : path_(path), what_(what), f_(std::fopen(path.c_str(), "wb")) {
    if (!f_) throwIo(path + ": cannot create the " + what + " file: " + std::strerror(errno));
    std::setvbuf(f_, nullptr, _IOFBF, 1 << 20);
  }
  ~Sink() {
    if (f_) std::fclose(f_);
  }
  void bytes(const void* p, size_t n) {
    if (n && std::fwrite(p, 1, n, f_) != n) fail();
    if (hashing_) hash(p, n);
    pos_ += n;
    // Each finished MB goes to the kernel's writeback at once, so the
    // commit's fsync waits for the tail only (formats/core/writeback.h).
    if (!vox::handOnWritten(f_, pos_, queued_)) fail();
  }
  template <typename T>
  void pod(const T& v) {
    bytes(&v, sizeof v);
  }
  void string(const std::string& s) {  // OpenVDB's writeString: int32 length, then the characters
    pod(int32_t(s.size()));
    bytes(s.data(), s.size());
  }
  uint64_t pos() const { return pos_; }
  void patch(uint64_t at, const void* p, size_t n) {
    if (std::fflush(f_) != 0 || std::fseek(f_, long(at), SEEK_SET) != 0 || std::fwrite(p, 1, n, f_) != n ||
        std::fseek(f_, 0, SEEK_END) != 0)
      fail();
  }
  void startHashing() { hashing_ = true; }
  std::array<uint32_t, 4> digest() const { return crc_; }
  void close() {
    const int bad = std::fflush(f_) != 0 || std::ferror(f_);
    const int closed = std::fclose(f_);
    f_ = nullptr;
    if (bad || closed != 0) fail();
  }

 private:
  // Worded like the OpenVDB writer's check (formats/vdb/vdb_scene_grids.cpp), naming the output, not its temporary.
  [[noreturn]] void fail() {
    const std::string reason = std::strerror(errno);  // before anything else can change errno
    throwIo(outputName(path_) + ": the " + what_ + " was not written completely (" + reason + ")");
  }
  void hash(const void* p, size_t n) {
    for (size_t k = 0; k < crc_.size(); ++k) crc_[k] = crc32c(p, n, crc_[k]);
  }
  std::string path_, what_;
  std::FILE* f_;
  uint64_t pos_ = 0, queued_ = 0;
  bool hashing_ = false;
  std::array<uint32_t, 4> crc_ = kVdbUuidSeeds;
};

void append(std::string& out, const void* p, size_t n) { out.append(static_cast<const char*>(p), n); }
template <typename T>
void appendPod(std::string& out, const T& v) {
  append(out, &v, sizeof v);
}

// OpenVDB's bloscToStream: int64 size then the Blosc frame (LZ4, level 9,
// shuffle, typesize 4, one block), or -size and the raw bytes when Blosc fails.
void appendBlosc(std::string& out, const void* data, size_t bytes) {
  // One frame buffer per thread, grown and never zeroed: a fresh zeroed
  // vector per leaf was a malloc, a memset and a free for every leaf written.
  // The frame itself comes from bloscLz4Frame, Blosc's bytes without Blosc's
  // allocation per call (its header says why).
  thread_local std::vector<char> frameBuffer;
  const size_t frameSize = bytes + kBloscFrameOverhead;
  if (frameBuffer.size() < frameSize) frameBuffer.resize(frameSize);
  char* frame = frameBuffer.data();
  const size_t n = bloscLz4Frame(data, bytes, sizeof(float), frame, frameSize);
  if (n == 0) {
    appendPod(out, -int64_t(bytes));
    append(out, data, bytes);
  } else {
    appendPod(out, int64_t(n));
    append(out, frame, n);
  }
}

// ---------------------------------------------------------------- metadata

/// A metadata value as OpenVDB stores it: its type name and its bytes
/// (strings as their characters, numbers and vectors as their native bytes).
struct MetaBytes {
  std::string type;
  std::string bytes;
};
template <typename T>
MetaBytes metaPod(const char* type, const T& v) {
  MetaBytes m{type, {}};
  appendPod(m.bytes, v);
  return m;
}
struct MetaValueBytes {
  std::string operator()(const std::string& v) const { return v; }
  std::string operator()(const ForeignMetaValue& v) const {
    throw Error(ErrorKind::Internal, "writeSceneVdbDirect: metadata of foreign type " + v.typeName);
  }
  template <typename T>
  std::string operator()(const T& v) const {
    std::string out;
    appendPod(out, v);
    return out;
  }
};
MetaBytes metaBytes(const MetaValue& value) { return {metaTypeName(value), std::visit(MetaValueBytes{}, value)}; }
std::map<std::string, MetaBytes> metaBytes(const MetaEntries& entries) {
  std::map<std::string, MetaBytes> out;
  for (const auto& [name, value] : entries) out[name] = metaBytes(value);
  return out;
}

// MetaMap::writeMeta: int32 count, then (name, type name, int32 size, bytes) sorted by name.
void writeMeta(Sink& out, const std::map<std::string, MetaBytes>& meta) {
  out.pod(int32_t(meta.size()));
  for (const auto& [name, m] : meta) {
    out.string(name);
    out.string(m.type);
    out.pod(int32_t(m.bytes.size()));
    out.bytes(m.bytes.data(), m.bytes.size());
  }
}

// ---------------------------------------------------------------- tree layout

/// Tree order of leaves: by int5 node, then int4 node, then leaf, each by
/// (x, y, z) of its origin, which is the order OpenVDB visits children in.
bool treeOrder(const VoxelBlock* a, const VoxelBlock* b) {
  for (int shift : {kShiftInt5, kShiftInt4, kBlockLog2}) {
    const std::array<int32_t, 3> ka{a->origin[0] >> shift, a->origin[1] >> shift, a->origin[2] >> shift};
    const std::array<int32_t, 3> kb{b->origin[0] >> shift, b->origin[1] >> shift, b->origin[2] >> shift};
    if (ka != kb) return ka < kb;
  }
  return false;
}

/// Index of a child inside its parent: x-major, z fastest.
uint32_t childIndex(const std::array<int32_t, 3>& o, int childShift, int log2) {
  const int32_t m = (1 << log2) - 1;
  return (uint32_t((o[0] >> childShift) & m) << (2 * log2)) | (uint32_t((o[1] >> childShift) & m) << log2) |
         uint32_t((o[2] >> childShift) & m);
}

struct GridPlan {
  std::string name;
  GridKind kind;
  uint8_t classId = 0;                  // votes grids
  std::vector<const VoxelBlock*> leaves;  // in tree order
  std::vector<const ClassBlock*> votes;  // votes grids: the class block of each leaf
  const SceneHeader* header = nullptr;   // the scene's placement and classes
  const MetaEntries* extraMeta = nullptr;  // added to the grid's metadata (a pyramid level's)
};

/// The per-leaf active mask of a grid.
std::array<uint64_t, kBlockWords> activeMask(const GridPlan& g, size_t i) {
  std::array<uint64_t, kBlockWords> m{};
  const VoxelBlock& b = *g.leaves[i];
  switch (g.kind) {
    case GridKind::Bool: m = b.occupied; break;
    case GridKind::Int32: {
      const ClassBlock* cb = g.votes[i];
      const bool runs = b.hasRuns() && b.runClass == g.classId;
      for (int k = 0; k < kBlockWords; ++k) {
        if (cb) m[size_t(k)] |= cb->voted[size_t(k)];
        if (runs && b.runVotes) m[size_t(k)] |= b.runMask[size_t(k)];
      }
      break;
    }
    case GridKind::Vec3s:
      for (int k = 0; k < kBlockWords; ++k) m[size_t(k)] = b.colored[size_t(k)] & b.occupied[size_t(k)];
      break;
  }
  return m;
}

/// Compressed value buffers of full uniform vote leaves, by count (per thread).
std::unordered_map<uint32_t, std::string>& uniformLeafCache() {
  thread_local std::unordered_map<uint32_t, std::string> cache;
  return cache;
}

/// LeafNode::writeBuffers for one leaf, appended to `out`.
void leafBuffer(const GridPlan& g, size_t i, const std::array<uint64_t, kBlockWords>& mask, std::string& out) {
  const VoxelBlock& b = *g.leaves[i];
  append(out, mask.data(), sizeof mask);
  if (g.kind == GridKind::Bool) {
    // LeafNode<bool>: mask, origin, then the value bits (the surface flags).
    append(out, b.origin.data(), sizeof b.origin);
    for (int k = 0; k < kBlockWords; ++k) appendPod(out, uint64_t(b.surface[size_t(k)] & b.occupied[size_t(k)]));
    return;
  }
  // io::writeCompressedValues with active-mask compression: every inactive
  // value is the background (0), so the metadata byte is NO_MASK_OR_INACTIVE_VALS
  // and only the active values follow, in voxel order.
  out.push_back(char(0));
  if (g.kind == GridKind::Int32) {
    const ClassBlock* cb = g.votes[i];
    bool full = true;
    for (uint64_t w : mask) full = full && w == ~uint64_t(0);
    if (!cb && full) {
      // A block of interior runs only (the bulk of a solid fill): 512 equal
      // counts, whose compressed form is the same every time.
      auto& cached = uniformLeafCache()[b.runVotes];
      if (cached.empty()) {
        std::array<int32_t, kBlockVoxels> vals;
        vals.fill(int32_t(b.runVotes));
        appendBlosc(cached, vals.data(), sizeof vals);
      }
      out += cached;
      return;
    }
    // The active voxels in order, the class block's counts in the same order.
    std::array<int32_t, kBlockVoxels> vals;
    size_t n = 0, slot = 0;
    const bool runs = b.hasRuns() && b.runClass == g.classId;
    for (int k = 0; k < kBlockWords; ++k)
      for (uint64_t bits = mask[size_t(k)]; bits; bits &= bits - 1) {
        const int i = k * 64 + std::countr_zero(bits);
        uint32_t v = cb && cb->has(i) ? cb->counts[cb->dense ? size_t(i) : slot++] : 0;
        if (runs && ((b.runMask[size_t(k)] >> (i & 63)) & 1)) v = saturatingVotes(v, b.runVotes);
        vals[n++] = int32_t(v);
      }
    appendBlosc(out, vals.data(), n * sizeof(int32_t));
  } else {
    std::array<std::array<float, 3>, kBlockVoxels> vals;
    size_t n = 0;
    forEachColor(b, mask, [&](int, const std::array<float, 3>& rgb) { vals[n++] = rgb; });
    appendBlosc(out, vals.data(), n * sizeof(vals[0]));
  }
}

// The transform writeSceneVdb gives every grid, as OpenVDB stores it: a
// uniform scale s and translation t go through Transform::copy(), whose
// simplify() rebuilds the map from its affine matrix, so the stored scale is
// (s + t) - t per axis in double arithmetic, and the map stays uniform only
// while those agree within 1e-15 (math::isApproxEqual); otherwise it is a
// ScaleTranslateMap with three scales.
void writeTransform(Sink& out, const SceneHeader& h) {
  const double s = h.voxelSize;
  const std::array<double, 3> t{h.origin[0] + 0.5 * s, h.origin[1] + 0.5 * s, h.origin[2] + 0.5 * s};
  std::array<double, 3> scale;
  for (int k = 0; k < 3; ++k) {
    volatile double sum = s + t[size_t(k)];  // two roundings, as in AffineMap::applyMap
    scale[size_t(k)] = sum - t[size_t(k)];
  }
  const bool uniform = !(std::abs(scale[0] - scale[1]) > 1e-15) && !(std::abs(scale[0] - scale[2]) > 1e-15);
  if (uniform) scale[1] = scale[2] = scale[0];
  if (!(std::abs(scale[0] * scale[1] * scale[2]) >= 3e-15))
    throwUsage("voxel size " + std::to_string(s) +
               " is too small for an OpenVDB transform (voxel volume must be >= 3e-15); use a larger voxel size or "
               "scale the mesh",
               Setting::VoxelSize);
  out.string(uniform ? "UniformScaleTranslateMap" : "ScaleTranslateMap");
  out.pod(t);
  std::array<double, 3> voxel, inv, invSqr, invTwice;
  for (size_t k = 0; k < 3; ++k) {
    voxel[k] = std::abs(scale[k]);
    inv[k] = 1.0 / scale[k];
    invSqr[k] = inv[k] * inv[k];
    invTwice[k] = inv[k] / 2;
  }
  out.pod(scale);
  out.pod(voxel);
  out.pod(inv);
  out.pod(invSqr);
  out.pod(invTwice);
}

struct GridStats {
  uint64_t voxels = 0;
  std::array<int32_t, 3> lo{INT_MAX, INT_MAX, INT_MAX}, hi{INT_MIN, INT_MIN, INT_MIN};
};

/// Leaves of a batch of leaf buffers, and batches in flight per thread
/// (directWriteBytes counts kLeavesPerBatch * kBatchesPerThread a thread).
constexpr size_t kLeavesPerBatch = 512, kBatchesPerThread = 2;

void writeGrid(Sink& out, const GridPlan& g, unsigned threads) {
  const SceneHeader& h = *g.header;
  const size_t nLeaves = g.leaves.size();
  // Pieces of contiguous leaves in tree order (at least 64 each), one per
  // thread, their results combined in order: nothing depends on the thread count.
  auto piecesOf = [threads](size_t n) {
    return std::max(1u, std::min<unsigned>(threads, unsigned(std::max<size_t>(1, n / 64))));
  };
  const unsigned pieces = piecesOf(nLeaves);
  // The active voxels and their box first: the grid's metadata comes before its leaves.
  std::vector<GridStats> partStats(pieces);
  parallelPieces(nLeaves, pieces, pieces, [&](size_t b, size_t e, size_t t) {
    GridStats& s = partStats[t];
    for (size_t i = b; i < e; ++i) {
      const auto mask = activeMask(g, i);
      for (int k = 0; k < kBlockWords; ++k) {
        if (!mask[size_t(k)]) continue;
        s.voxels += uint64_t(bitCount(mask[size_t(k)]));
        // Bounding box of the active voxels: x and y from the word, z from the bits.
        const VoxelBlock& blk = *g.leaves[i];
        const int x = k, yLo = std::countr_zero(mask[size_t(k)]) >> 3, yHi = (63 - std::countl_zero(mask[size_t(k)])) >> 3;
        uint8_t zBits = 0;
        for (uint64_t w = mask[size_t(k)]; w; w >>= 8) zBits |= uint8_t(w & 0xff);
        const int zLo = std::countr_zero(zBits), zHi = 7 - std::countl_zero(zBits);
        const std::array<int32_t, 3> lo{blk.origin[0] + x, blk.origin[1] + yLo, blk.origin[2] + zLo};
        const std::array<int32_t, 3> hi{blk.origin[0] + x, blk.origin[1] + yHi, blk.origin[2] + zHi};
        for (int a = 0; a < 3; ++a) s.lo[size_t(a)] = std::min(s.lo[size_t(a)], lo[size_t(a)]), s.hi[size_t(a)] = std::max(s.hi[size_t(a)], hi[size_t(a)]);
      }
    }
  });
  GridStats stats;
  for (const GridStats& s : partStats) {
    stats.voxels += s.voxels;
    for (int a = 0; a < 3; ++a) stats.lo[size_t(a)] = std::min(stats.lo[size_t(a)], s.lo[size_t(a)]), stats.hi[size_t(a)] = std::max(stats.hi[size_t(a)], s.hi[size_t(a)]);
  }
  // Internal nodes: the distinct int5 and int4 origins, in tree order.
  std::vector<std::array<int32_t, 3>> int5, int4;
  for (const VoxelBlock* b : g.leaves) {
    const std::array<int32_t, 3> o5{b->origin[0] & ~((1 << kShiftInt5) - 1), b->origin[1] & ~((1 << kShiftInt5) - 1),
                                    b->origin[2] & ~((1 << kShiftInt5) - 1)};
    const std::array<int32_t, 3> o4{b->origin[0] & ~((1 << kShiftInt4) - 1), b->origin[1] & ~((1 << kShiftInt4) - 1),
                                    b->origin[2] & ~((1 << kShiftInt4) - 1)};
    if (int5.empty() || int5.back() != o5) int5.push_back(o5);
    if (int4.empty() || int4.back() != o4) int4.push_back(o4);
  }

  // GridDescriptor::writeHeader, with the three stream positions patched at the end.
  out.string(g.name);
  out.string(g.kind == GridKind::Bool ? "Tree_bool_5_4_3" : g.kind == GridKind::Int32 ? "Tree_int32_5_4_3" : "Tree_vec3s_5_4_3");
  out.string("");  // no instance parent
  const uint64_t positionsAt = out.pos();
  const int64_t zero = 0;
  for (int k = 0; k < 3; ++k) out.pod(zero);
  const int64_t gridPos = int64_t(out.pos());
  out.pod(kCompressBloscActiveMask);

  // Grid metadata: the scene's (scene_meta.h), OpenVDB's own and Archive's statistics.
  // The level's entries first, the grid's own over them (appendSceneGrids' order).
  MetaEntries gridMeta = g.extraMeta ? *g.extraMeta : MetaEntries{};
  auto over = [&](const MetaEntries& m) {
    for (const auto& [k, v] : m) gridMeta.insert_or_assign(k, v);
  };
  if (g.kind == GridKind::Int32) over(voteGridMetadata(h.classes, g.classId));
  if (g.kind == GridKind::Vec3s) {
    over(colorGridMetadata());
    gridMeta["vector_type"] = std::string("invariant");
  }
  gridMeta["file_bbox_min"] = stats.lo;
  gridMeta["file_bbox_max"] = stats.hi;
  gridMeta["file_compression"] = std::string("blosc + active values");
  gridMeta["name"] = g.name;
  std::map<std::string, MetaBytes> meta = metaBytes(gridMeta);
  const MemSizes mem = memSizes(g.kind);
  meta["file_mem_bytes"] = metaPod("int64", int64_t(mem.treeAndRoot + mem.int5 * int5.size() + mem.int4 * int4.size() + mem.leaf * nLeaves));
  meta["file_voxel_count"] = metaPod("int64", int64_t(stats.voxels));
  meta["is_saved_as_half_float"] = metaPod("bool", char(0));
  writeMeta(out, meta);

  // Transform: voxel centre at origin + (i + 0.5) * voxelSize.
  writeTransform(out, h);

  // Topology: one buffer per leaf; root background, no tiles, the int5 children.
  out.pod(int32_t(1));
  switch (g.kind) {
    case GridKind::Bool: out.pod(char(0)); break;
    case GridKind::Int32: out.pod(int32_t(0)); break;
    case GridKind::Vec3s: out.pod(std::array<float, 3>{0, 0, 0}); break;
  }
  out.pod(uint32_t(0));
  out.pod(uint32_t(int5.size()));
  // An internal node's values: no active tiles and every inactive value is the
  // background, so metadata 0 and an empty Blosc chunk.
  std::string emptyValues;
  emptyValues.push_back(char(0));
  appendBlosc(emptyValues, nullptr, 0);
  size_t leaf = 0, node4 = 0;
  std::vector<uint64_t> childMask5(1u << (3 * kLog2Int5 - 6)), childMask4(1u << (3 * kLog2Int4 - 6));
  const std::vector<uint64_t> valueMask5(childMask5.size()), valueMask4(childMask4.size());
  for (const auto& o5 : int5) {
    out.pod(o5);
    std::fill(childMask5.begin(), childMask5.end(), 0);
    size_t n4 = node4;
    for (; n4 < int4.size() && (int4[n4][0] & ~((1 << kShiftInt5) - 1)) == o5[0] &&
           (int4[n4][1] & ~((1 << kShiftInt5) - 1)) == o5[1] && (int4[n4][2] & ~((1 << kShiftInt5) - 1)) == o5[2];
         ++n4) {
      const uint32_t c = childIndex(int4[n4], kShiftInt4, kLog2Int5);
      childMask5[c >> 6] |= uint64_t(1) << (c & 63);
    }
    out.bytes(childMask5.data(), childMask5.size() * 8);
    out.bytes(valueMask5.data(), valueMask5.size() * 8);
    out.bytes(emptyValues.data(), emptyValues.size());
    for (; node4 < n4; ++node4) {
      const auto& o4 = int4[node4];
      std::fill(childMask4.begin(), childMask4.end(), 0);
      size_t l = leaf;
      for (; l < nLeaves && (g.leaves[l]->origin[0] & ~((1 << kShiftInt4) - 1)) == o4[0] &&
             (g.leaves[l]->origin[1] & ~((1 << kShiftInt4) - 1)) == o4[1] &&
             (g.leaves[l]->origin[2] & ~((1 << kShiftInt4) - 1)) == o4[2];
           ++l) {
        const uint32_t c = childIndex(g.leaves[l]->origin, kBlockLog2, kLog2Int4);
        childMask4[c >> 6] |= uint64_t(1) << (c & 63);
      }
      out.bytes(childMask4.data(), childMask4.size() * 8);
      out.bytes(valueMask4.data(), valueMask4.size() * 8);
      out.bytes(emptyValues.data(), emptyValues.size());
      for (; leaf < l; ++leaf) {  // leaf topology
        const auto mask = activeMask(g, leaf);
        out.bytes(mask.data(), sizeof mask);
      }
    }
  }
  const int64_t blockPos = int64_t(out.pos());
  // Leaf buffers (masks, compressed values), kLeavesPerBatch leaves a batch:
  // batches made on the workers, written in order by one consumer while later
  // batches are made (the file's bytes, the content CRC and the writeback are
  // one thread's work, which the others no longer wait for). The writer holds
  // at most kBatchesPerThread batches a thread (at most 6 KB a leaf,
  // coloured), not the grid's bytes (which grew by
  // doubling and left their outgrown copies resident: 2-4x the grid's bytes at
  // the peak). The bytes do not depend on the batches or the threads.
  const size_t batches = (nLeaves + kLeavesPerBatch - 1) / kLeavesPerBatch;
  std::vector<std::string> parts(std::max<size_t>(1, std::min(batches, kBatchesPerThread * size_t(workerCount(threads)))));
  orderedPipeline(
      batches, threads, parts.size(),
      [&](size_t k) {
        std::string& part = parts[k % parts.size()];  // batch k - parts.size() is written by now
        part.clear();
        for (size_t i = k * kLeavesPerBatch, e = std::min(nLeaves, (k + 1) * kLeavesPerBatch); i < e; ++i)
          leafBuffer(g, i, activeMask(g, i), part);
      },
      [&](size_t k) {
        const std::string& part = parts[k % parts.size()];
        out.bytes(part.data(), part.size());
      });
  const int64_t endPos = int64_t(out.pos());
  const int64_t positions[3] = {gridPos, blockPos, endPos};
  out.patch(positionsAt, positions, sizeof positions);
}

/// The grids writeSceneVdb writes for one part's scene, as SceneBuilder::build()
/// makes it from these blocks: occupancy, votes.<id> by id, color; appended to `grids`.
DirectWriteSummary planPart(const DirectScenePart& part, std::vector<const VoxelBlock*>& sorted,
                            std::vector<GridPlan>& grids) {
  sorted = part.blocks;
  std::sort(sorted.begin(), sorted.end(), treeOrder);
  const std::string& pre = part.gridPrefix;
  GridPlan occ{pre + kOccupancyGridName, GridKind::Bool, 0, {}, {}, part.header, &part.gridMetadata};
  std::map<uint8_t, GridPlan> votes;
  GridPlan color{pre + kColorGridName, GridKind::Vec3s, 0, {}, {}, part.header, &part.gridMetadata};
  // The classes with votes in a block: its class blocks and its runs' class.
  std::vector<uint8_t> ids;
  auto voteClasses = [&ids](const VoxelBlock& b) -> const std::vector<uint8_t>& {
    ids.clear();
    for (const auto& cb : b.classes) ids.push_back(cb->classId);
    if (b.hasRuns() && b.runVotes && std::find(ids.begin(), ids.end(), b.runClass) == ids.end()) ids.push_back(b.runClass);
    return ids;
  };
  // Each grid's leaves counted first, so that its lists are allocated once
  // (grown by doubling, they and their outgrown copies were up to 3x).
  std::array<size_t, 256> classLeaves{};
  size_t colorLeaves = 0;
  for (const VoxelBlock* b : sorted) {
    for (uint8_t id : voteClasses(*b)) ++classLeaves[id];
    colorLeaves += !b->colors.empty();
  }
  occ.leaves.reserve(sorted.size());
  color.leaves.reserve(colorLeaves);
  for (size_t id = 0; id < classLeaves.size(); ++id)
    if (classLeaves[id]) {
      GridPlan& g = votes[uint8_t(id)];
      g = {pre + voteGridName(uint8_t(id)), GridKind::Int32, uint8_t(id), {}, {}, part.header, &part.gridMetadata};
      g.leaves.reserve(classLeaves[id]);
      g.votes.reserve(classLeaves[id]);
    }
  DirectWriteSummary summary;
  for (const VoxelBlock* b : sorted) {
    occ.leaves.push_back(b);
    for (int k = 0; k < kBlockWords; ++k) {
      summary.occupied += uint64_t(bitCount(b->occupied[size_t(k)]));
      summary.surface += uint64_t(bitCount(b->occupied[size_t(k)] & b->surface[size_t(k)]));
    }
    for (uint8_t id : voteClasses(*b)) {
      GridPlan& g = votes[id];
      g.leaves.push_back(b);
      g.votes.push_back(findClassBlock(*b, id));
    }
    if (!b->colors.empty()) color.leaves.push_back(b);
  }
  grids.push_back(std::move(occ));
  for (auto& [id, g] : votes) {
    summary.classesPresent.push_back(id);
    grids.push_back(std::move(g));
  }
  summary.color = !color.leaves.empty();
  if (summary.color || part.colorGrid) grids.push_back(std::move(color));
  return summary;
}

}  // namespace

double directWriteBytes(double leaves, double voteLeaves, double colorLeaves, double leafBytes, unsigned threads) {
  // The leaf lists: the blocks sorted, the part's copy, the plan's sorted copy
  // and the occupancy's list (8 bytes a leaf each); a vote grid's leaves and
  // class blocks; the colour grid's leaves. Two batches of leaf buffers per
  // thread (written in order while later ones are made). Fixed: the file's 1
  // MiB buffer, the compression frames and the heap pages they first touch
  // (2 MiB huge pages where the CLI advises them: tools/cli/alloc_tuning.h).
  constexpr double kFixed = 4 << 20;
  return kFixed + leaves * 4 * sizeof(void*) + voteLeaves * 2 * sizeof(void*) + colorLeaves * sizeof(void*) +
         double(std::max(1u, threads)) * double(kLeavesPerBatch * kBatchesPerThread) * leafBytes;
}

std::vector<DirectWriteSummary> writeScenesVdbDirect(
    const std::vector<DirectScenePart>& parts,
    const std::function<MetaEntries(const std::vector<DirectWriteSummary>&)>& fileMetadata, const std::string& path,
    unsigned threads, const std::string& what) {
  std::vector<GridPlan> grids;
  std::vector<std::vector<const VoxelBlock*>> sorted(parts.size());
  std::vector<DirectWriteSummary> summaries;
  for (size_t i = 0; i < parts.size(); ++i) summaries.push_back(planPart(parts[i], sorted[i], grids));

  Sink out(path, what);
  // Archive::writeHeader: magic, file and library versions, "has grid offsets",
  // then the UUID as 36 characters (patched at the end with the content digest).
  out.pod(kMagic);
  out.pod(kFileVersion);
  out.pod(kLibraryMajor);
  out.pod(kLibraryMinor);
  out.pod(char(1));
  const uint64_t uuidAt = out.pos();
  static_assert(kVdbUuidOffset == sizeof kMagic + 3 * sizeof kFileVersion + 1);
  out.bytes(std::string(kVdbUuidChars, '0').data(), kVdbUuidChars);
  out.startHashing();

  writeMeta(out, metaBytes(fileMetadata(summaries)));
  out.pod(int32_t(grids.size()));
  for (const GridPlan& g : grids) writeGrid(out, g, threads);

  const std::string text = vdbUuidText(out.digest());  // formats/scene/vdb_content_uuid.h
  out.patch(uuidAt, text.data(), text.size());
  for (DirectWriteSummary& s : summaries) s.fileBytes = out.pos();
  out.close();
  return summaries;
}

DirectWriteSummary writeSceneVdbDirect(const SceneHeader& h, VoxelBlocks& blocks, const std::string& path,
                                       unsigned threads) {
  blocks.validate(h.dims, h.classes);
  const std::vector<VoxelBlock*> sorted = blocks.sortedBlocks(treeOrder);
  DirectScenePart part;
  part.header = &h;
  part.blocks.assign(sorted.begin(), sorted.end());
  const DirectWriteSummary summary =
      writeScenesVdbDirect({part}, [&](const std::vector<DirectWriteSummary>&) { return sceneFileMetadata(h); }, path,
                           threads, "scene")[0];
  for (VoxelBlock* b : sorted) VoxelBlocks::release(*b);
  return summary;
}

}  // namespace vox
