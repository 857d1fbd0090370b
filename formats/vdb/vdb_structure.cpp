#include "formats/vdb/vdb_structure.h"

#include <blosc.h>
#include <sys/stat.h>
#include <time.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <exception>
#include <bit>
#include <climits>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <tuple>

#include "formats/core/file_util.h"
#include "libvox/core/bits.h"
#include "libvox/core/error.h"
#include "libvox/core/parallel.h"

namespace vox {

namespace {

// OpenVDB file format versions (openvdb/version.h). Older files change the
// framing of nearly every element and OpenVDB 10 warns about newer ones; vox
// reads 222 (per-grid compression, OpenVDB 3) to 224 (OpenVDB 6 and later).
constexpr uint32_t kOldestVersion = 222, kNewestVersion = 224;
constexpr int64_t kMagic = 0x56444220;

// io/Compression.h
constexpr uint32_t kZip = 0x1, kActiveMask = 0x2, kBlosc = 0x4;
enum : int8_t {
  NO_MASK_OR_INACTIVE_VALS,
  NO_MASK_AND_MINUS_BG,
  NO_MASK_AND_ONE_INACTIVE_VAL,
  MASK_AND_NO_INACTIVE_VALS,
  MASK_AND_ONE_INACTIVE_VAL,
  MASK_AND_TWO_INACTIVE_VALS,
  NO_MASK_AND_ALL_VALS
};

// Tree 5-4-3: node masks in bytes, and the log2 of the voxels a child spans.
constexpr size_t kInt5Values = 32768, kInt4Values = 4096, kLeafValues = 512;
constexpr int32_t kCoordLimit = 1 << 30;  // root tiles and children within +-2^30

/// A value type OpenVDB stores in trees (Tree_<name>_5_4_3).
struct ValueKind {
  const char* name;
  uint32_t size;      // bytes of one value
  uint32_t halfSize;  // bytes of one value saved as half float; 0 when not a real type
  bool isBool;        // values are C++ bool: every stored byte must be 0 or 1
  bool isMask;        // ValueMask leaves (the value is the mask)
  bool isInteger;     // signed integer components
  uint32_t componentSize;
};
constexpr ValueKind kValueKinds[] = {
    {"bool", 1, 0, true, false, false, 1},    {"mask", 1, 0, true, true, false, 1},
    {"float", 4, 2, false, false, false, 4},  {"double", 8, 2, false, false, false, 8},
    {"int32", 4, 0, false, false, true, 4},   {"int64", 8, 0, false, false, true, 8},
    {"vec3i", 12, 0, false, false, true, 4},  {"vec3s", 12, 6, false, false, false, 4},
    {"vec3d", 24, 6, false, false, false, 8},
};

/// Metadata types OpenVDB 10 registers with fixed sizes (openvdb.cc initialize()).
/// TypedMetadata<T>::readValue reads sizeof(T) whatever size the file gives, so
/// a size that disagrees would put OpenVDB out of step with the file.
int64_t metaTypeSize(const std::string& t) {
  static const std::map<std::string, int64_t> sizes = {
      {"bool", 1},   {"float", 4},  {"double", 8}, {"int32", 4},  {"int64", 8},   {"vec2i", 8},
      {"vec2s", 8},  {"vec2d", 16}, {"vec3i", 12}, {"vec3s", 12}, {"vec3d", 24},  {"vec4i", 16},
      {"vec4s", 16}, {"vec4d", 32}, {"mat4s", 64}, {"mat4d", 128}, {"ptidx32", 4}, {"ptidx64", 8}};
  const auto it = sizes.find(t);
  return it == sizes.end() ? -1 : it->second;
}

std::string printable(const std::string& s) {
  std::string out;
  for (char c : s.substr(0, 64)) out += (c >= 32 && c < 127) ? c : '?';
  if (s.size() > 64) out += "...";
  return out;
}

std::string coordText(const std::array<int32_t, 3>& c) {
  std::string s = "(";
  for (int k = 0; k < 3; ++k) (s += std::to_string(c[size_t(k)])) += k < 2 ? "," : ")";
  return s;
}

/// Where the walk is, for messages: built only when something is wrong.
struct Where {
  const std::string* file = nullptr;
  std::string grid;  // "grid 'NAME'", or empty at file level
  const char* node = nullptr;  // "leaf", "internal node (level 1)", ...
  std::array<int32_t, 3> origin{};
  std::string prefix() const {
    std::string s = *file + ": ";
    if (!grid.empty()) s += grid + ": ";
    if (node) s += std::string(node) + " at " + coordText(origin) + ": ";
    return s;
  }
  [[noreturn]] void fail(const std::string& what) const { throwBadInput(prefix() + what); }
};

class Reader {
 public:
  Reader(const uint8_t* d, size_t n, Where& where) : d_(d), n_(n), w_(where) {}
  size_t pos() const { return pos_; }
  size_t size() const { return n_; }
  size_t left() const { return n_ - pos_; }
  const uint8_t* here() const { return d_ + pos_; }
  Where& where() { return w_; }
  /// `what` (and `what2`, appended) name the field; messages are built on failure only.
  void need(uint64_t bytes, const char* what, const char* what2 = nullptr) {
    if (bytes > left())
      w_.fail("truncated or corrupt OpenVDB file: " + std::string(what) + (what2 ? std::string(" ") + what2 : "") +
              " needs " + std::to_string(bytes) + " bytes at offset " + std::to_string(pos_) + " but " +
              std::to_string(left()) + " are left");
  }
  template <typename T>
  T get(const char* what, const char* what2 = nullptr) {
    need(sizeof(T), what, what2);
    T v;
    std::memcpy(&v, d_ + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string str(const char* what) {
    const uint32_t len = get<uint32_t>(what);
    need(len, what);
    std::string s(reinterpret_cast<const char*>(d_ + pos_), len);
    pos_ += len;
    return s;
  }
  const uint8_t* take(uint64_t bytes, const char* what, const char* what2 = nullptr) {
    need(bytes, what, what2);
    const uint8_t* p = d_ + pos_;
    pos_ += size_t(bytes);
    return p;
  }
  bool boolByte(const char* what) {
    const uint8_t b = get<uint8_t>(what);
    if (b > 1) w_.fail(std::string(what) + " is " + std::to_string(b) + ", not a bool (0 or 1)");
    return b != 0;
  }
  void seek(size_t to) { pos_ = to; }

 private:
  const uint8_t* d_;
  size_t n_, pos_ = 0;
  Where& w_;
};

// ---------------------------------------------------------------- compressed blocks

/// One block of values found by the walk, its framing checked, not yet decoded.
struct Block {
  enum Kind : uint8_t { Raw, Blosc, Zip };
  const uint8_t* src = nullptr;  // in the walked bytes
  uint64_t stored = 0;           // bytes at src
  uint64_t bytes = 0;            // bytes it decodes to
  Kind kind = Raw;
};

/// One block as io::bloscFromStream / io::unzipFromStream / a plain read takes
/// it, for `bytes` bytes of values: every size checked against the file and
/// the mask, Blosc headers against the block; nothing decompressed.
Block frameBlock(Reader& r, uint32_t compression, uint64_t bytes, const char* what) {
  if (!(compression & (kBlosc | kZip))) return {r.take(bytes, what), bytes, bytes, Block::Raw};  // uncompressed values
  const int64_t stored = r.get<int64_t>(what, "block size");
  if (stored <= 0) {
    // Stored uncompressed: OpenVDB reads -size bytes into a buffer of `bytes`.
    const uint64_t raw = uint64_t(0) - uint64_t(stored);
    if (raw != bytes)
      r.where().fail(std::string(what) + ": an uncompressed block of " + std::to_string(raw) + " bytes where the mask implies " +
                     std::to_string(bytes));
    if (raw > r.left())
      r.where().fail(std::string(what) + ": uncompressed block of " + std::to_string(raw) + " bytes overruns the file (" +
                     std::to_string(r.left()) + " left)");
    return {r.take(raw, what), raw, raw, Block::Raw};
  }
  if (uint64_t(stored) > r.left())
    r.where().fail(std::string(what) + ": compressed block of " + std::to_string(stored) + " bytes overruns the file (" +
                   std::to_string(r.left()) + " left)");
  const uint8_t* src = r.take(uint64_t(stored), what);
  if (compression & kBlosc) {
    // Blosc 1 takes the compressed size from the block's own header: it must be
    // the block, and the decompressed size the one the mask implies.
    size_t nbytes = 0, cbytes = 0, blocksize = 0;
    if (stored < BLOSC_MIN_HEADER_LENGTH)
      r.where().fail(std::string(what) + ": compressed block of " + std::to_string(stored) + " bytes is shorter than a Blosc header");
    blosc_cbuffer_sizes(src, &nbytes, &cbytes, &blocksize);
    if (cbytes != uint64_t(stored) || blosc_cbuffer_validate(src, size_t(stored), &nbytes) != 0)
      r.where().fail(std::string(what) + ": Blosc header claims " + std::to_string(cbytes) + " compressed bytes in a block of " +
                     std::to_string(stored));
    if (nbytes != bytes)
      r.where().fail(std::string(what) + ": compressed block decompresses to " + std::to_string(nbytes) + " bytes where the mask implies " +
                     std::to_string(bytes));
    return {src, uint64_t(stored), bytes, Block::Blosc};
  }
  return {src, uint64_t(stored), bytes, Block::Zip};
}

/// The decoded bytes of a framed block (in `scratch`, or in the file when
/// stored raw), or nullptr with `why` set when it does not decompress to
/// exactly its size. Safe to call concurrently with distinct scratch buffers.
const uint8_t* decodeBlock(const Block& b, std::vector<uint8_t>& scratch, const char* what, std::string& why) {
  if (b.kind == Block::Raw) return b.src;
  if (scratch.size() < b.bytes + 1) scratch.resize(size_t(b.bytes) + 1);
  if (b.kind == Block::Blosc) {
    const int got = blosc_decompress_ctx(b.src, scratch.data(), size_t(b.bytes), 1);
    if (got >= 0 && uint64_t(got) == b.bytes) return scratch.data();
    why = std::string(what) + ": compressed block does not decompress (" + std::to_string(got) + " of " +
          std::to_string(b.bytes) + " bytes)";
    return nullptr;
  }
  uLongf got = uLongf(b.bytes);
  const int rc = uncompress(scratch.data(), &got, b.src, uLong(b.stored));
  if (rc == Z_OK && got == b.bytes) return scratch.data();
  why = std::string(what) + ": zip block does not decompress to the " + std::to_string(b.bytes) + " bytes the mask implies";
  return nullptr;
}

// ---------------------------------------------------------------- metadata

struct MetaInfo {
  std::vector<std::string> names;
  int halfFloat = -1;  // is_saved_as_half_float: -1 absent, else 0/1
};

/// io::DelayedLoadMetadata::readValue over [p, p + numBytes).
void checkDelayedLoad(Reader& r, uint32_t numBytes, const std::string& what) {
  if (numBytes == 0) return;
  const size_t end = r.pos() + numBytes;  // numBytes <= left, checked by the caller
  auto fail = [&](const std::string& why) { r.where().fail(what + ": " + why); };
  const uint32_t count = r.get<uint32_t>("delayed-load leaf count");
  if (uint64_t(count) * 64 > r.size()) fail("claims " + std::to_string(count) + " leaves, more than the file can hold");
  std::vector<uint8_t> scratch;
  auto buffer = [&](uint64_t expected, const char* name) {
    const uint32_t bytes = r.get<uint32_t>(name);
    if (bytes == 0) {
      r.take(expected, name);
      return;
    }
    if (bytes > end - std::min(end, r.pos())) fail(std::string(name) + " of " + std::to_string(bytes) + " bytes overruns the entry");
    const uint8_t* src = r.take(bytes, name);
    size_t nbytes = 0, cbytes = 0, blocksize = 0;
    if (bytes < BLOSC_MIN_HEADER_LENGTH) fail(std::string(name) + " is shorter than a Blosc header");
    blosc_cbuffer_sizes(src, &nbytes, &cbytes, &blocksize);
    // OpenVDB pads buffers of 48 to 127 bytes to 128 before compressing them
    // (points/StreamCompression.cc) and accepts 128 for any expected size up to 128.
    const bool padded = nbytes == 128 && expected <= 128;
    if (cbytes != bytes || (nbytes != expected && !padded) || blosc_cbuffer_validate(src, bytes, &nbytes) != 0)
      fail(std::string(name) + " has a Blosc header that does not match its " + std::to_string(bytes) + " bytes and " +
           std::to_string(count) + " leaves");
    scratch.resize(nbytes + 1);
    if (blosc_decompress_ctx(src, scratch.data(), nbytes, 1) != int(nbytes)) fail(std::string(name) + " does not decompress");
  };
  buffer(count, "delayed-load mask");
  const uint32_t sizesBytes = r.get<uint32_t>("delayed-load sizes");
  if (sizesBytes != 0xffffffffu) {
    r.seek(r.pos() - 4);
    buffer(uint64_t(count) * 8, "delayed-load sizes");
  }
  if (r.pos() > end) fail("its content overruns the entry's " + std::to_string(numBytes) + " bytes");
  r.seek(end);
}

MetaInfo readMeta(Reader& r, const char* level) {
  MetaInfo info;
  const std::string lv(level);
  const uint32_t count = r.get<uint32_t>((lv + " metadata count").c_str());
  std::set<std::string> seen;
  for (uint32_t i = 0; i < count; ++i) {
    const std::string what = lv + " metadata entry " + std::to_string(i);
    const std::string key = r.str((what + " name").c_str());
    const std::string named = lv + " metadata '" + printable(key) + "'";
    if (key.empty()) r.where().fail(what + " has an empty name");
    if (!seen.insert(key).second) r.where().fail(named + " appears twice");
    const std::string type = r.str((named + " type").c_str());
    const uint32_t bytes = r.get<uint32_t>((named + " size").c_str());
    r.need(bytes, (named + " value").c_str());
    const int64_t fixed = metaTypeSize(type);
    if (fixed >= 0 && bytes != uint64_t(fixed))
      r.where().fail(named + " of type " + type + " has " + std::to_string(bytes) + " bytes, expected " +
                     std::to_string(fixed));
    if (type == "__delayedload") {
      checkDelayedLoad(r, bytes, named);
    } else if (type == "bool") {
      const bool b = r.boolByte((named + " value").c_str());
      if (key == "is_saved_as_half_float") info.halfFloat = b ? 1 : 0;
    } else {
      if (key == "is_saved_as_half_float")
        r.where().fail(named + " has type " + printable(type) + ", expected bool");
      r.take(bytes, "metadata value");
    }
    info.names.push_back(key);
  }
  return info;
}

// ---------------------------------------------------------------- transform

void readMap(Reader& r, int depth) {
  const std::string type = r.str(depth ? "frustum's second map type" : "transform map type");
  auto doubles = [&](int n) {
    for (int i = 0; i < n; ++i) {
      const double v = r.get<double>("transform value");
      if (!std::isfinite(v)) r.where().fail("transform " + type + " has a value that is not finite");
    }
  };
  auto scales = [&](int vectors) {  // scale values first: none may be 0
    std::array<double, 3> s{};
    for (double& v : s) v = r.get<double>("transform scale");
    for (double v : s)
      if (!std::isfinite(v) || v == 0) r.where().fail("transform " + type + " has a scale of 0 or not finite");
    doubles(3 * (vectors - 1));
  };
  if (type == "UniformScaleMap" || type == "ScaleMap") {
    scales(5);  // scale, voxel size, inverse, inverse squared, half inverse
  } else if (type == "UniformScaleTranslateMap" || type == "ScaleTranslateMap") {
    doubles(3);  // translation
    scales(5);
  } else if (type == "TranslationMap") {
    doubles(3);
  } else if (type == "AffineMap" || type == "UnitaryMap") {
    doubles(16);  // a 4x4 matrix
  } else if (type == "NonlinearFrustumMap" && depth == 0) {
    doubles(6 + 2);  // bounding box, taper, depth
    readMap(r, 1);
  } else {
    r.where().fail("transform map type '" + printable(type) + "' is not one OpenVDB 10 reads");
  }
}

// ---------------------------------------------------------------- trees

struct Leaf {
  std::array<int32_t, 3> origin;
  size_t maskAt;  // offset of its value mask in the topology
};

/// The values io::readCompressedValues reads for one node, framed.
struct ValueFrame {
  int8_t meta = 0;                                // compression metadata
  const uint8_t* inactive[2] = {nullptr, nullptr};  // inactive values stored
  const uint8_t* selection = nullptr;             // selection mask stored
  size_t count = 0;                               // values stored
  bool hasBlock = false;                          // false when HalfReader reads nothing (no values)
  Block block;
};

/// A leaf buffer framed by the serial pass, for the parallel decoding.
struct FramedLeaf {
  const uint8_t* mask = nullptr;
  const uint8_t* boolValues = nullptr;
  ValueFrame values;
};

class TreeWalk {
 public:
  TreeWalk(Reader& r, const ValueKind& v, bool half, uint32_t compression)
      : r_(r), v_(v), half_(half && v.halfSize), compression_(compression) {}

  void topology() {
    Where& w = r_.where();
    if (r_.get<int32_t>("buffer count") != 1) w.fail("buffer count is not 1 (multi-buffer trees are not supported)");
    const uint8_t* bg = r_.take(v_.size, "background value");
    background_ = bg;
    if (v_.isBool && *bg > 1) w.fail("background value is not a bool (0 or 1)");
    // OpenVDB negates the background for inactive values (io::readCompressedValues):
    // the most negative integer has no negation.
    if (v_.isInteger)
      for (uint32_t at = 0; at < v_.size; at += v_.componentSize) {
        const bool wide = v_.componentSize == 8;
        int64_t c;
        if (wide) std::memcpy(&c, bg + at, 8);
        else {
          int32_t c32;
          std::memcpy(&c32, bg + at, 4);
          c = c32;
        }
        if (wide ? c == INT64_MIN : c == INT32_MIN) w.fail("background value " + std::to_string(c) + " has no negation");
      }
    const uint32_t tiles = r_.get<uint32_t>("root tile count");
    const uint32_t children = r_.get<uint32_t>("root child count");
    if (uint64_t(tiles) * (13 + v_.size) > r_.left())
      w.fail("root claims " + std::to_string(tiles) + " tiles, more than the file holds");
    leavesOnly_ = tiles == 0;
    std::set<std::array<int32_t, 3>> tileAt;
    std::array<int32_t, 3> prev{};
    for (uint32_t i = 0; i < tiles; ++i) {
      const auto c = rootCoord("root tile", i ? &prev : nullptr);
      const uint8_t* value = r_.take(v_.size, "root tile value");
      if (v_.isBool && *value > 1) failAt("root tile", c, "value is not a bool (0 or 1)");
      const uint8_t active = r_.get<uint8_t>("root tile active flag");
      if (active > 1) failAt("root tile", c, "active flag is " + std::to_string(active) + ", not 0 or 1");
      tileAt.insert(c);
      prev = c;
    }
    for (uint32_t i = 0; i < children; ++i) {
      const auto c = rootCoord("root child", i ? &prev : nullptr);
      if (tileAt.count(c)) failAt("root child", c, "a tile has the same origin");
      prev = c;
      internal(c, 5, 1);
    }
    w.node = nullptr;
  }

  /// The leaf buffers, framed in file order; with `decode` every block is
  /// then decompressed and checked in parallel and, with a `sink`, each leaf
  /// handed to it. The fault named is the first in file order either way.
  void buffers(bool decode, VdbWalkSink* sink, size_t gridIndex) {
    Where& w = r_.where();
    const size_t maskBytes = kLeafValues / 8;
    std::vector<FramedLeaf> framed(leaves_.size());
    size_t walked = 0;
    try {
      for (; walked < leaves_.size(); ++walked) {
        const Leaf& leaf = leaves_[walked];
        FramedLeaf& b = framed[walked];
        w.node = "leaf";
        w.origin = leaf.origin;
        b.mask = r_.take(maskBytes, "leaf value mask");
        if (std::memcmp(b.mask, topoBytes_ + leaf.maskAt, maskBytes) != 0)
          w.fail("leaf value mask differs from the one in the topology");
        if (v_.isBool) {
          std::array<int32_t, 3> o;
          std::memcpy(o.data(), r_.take(12, "leaf origin"), 12);
          if (o != leaf.origin) w.fail("stored leaf origin " + coordText(o) + " is not where the leaf is");
          if (!v_.isMask) b.boolValues = r_.take(maskBytes, "leaf values");  // bool leaves: the values as bits
          continue;
        }
        b.values = frameValues(b.mask, kLeafValues, "leaf values");
      }
    } catch (const Error&) {
      // A walk that decompressed as it went would have stopped at an earlier
      // block that does not decompress: that one is named first.
      if (decode) decodeLeaves(framed, walked, nullptr, 0);
      throw;
    }
    w.node = nullptr;
    if (decode) decodeLeaves(framed, leaves_.size(), sink, gridIndex);
  }

  void setTopologyBase(const uint8_t* base) { topoBytes_ = base; }
  uint64_t leafCount() const { return leaves_.size(); }
  uint64_t activeLeafVoxels() const { return activeVoxels_; }
  uint64_t upperNodes() const { return upperNodes_; }
  uint64_t lowerNodes() const { return lowerNodes_; }
  const uint8_t* background() const { return background_; }
  bool leavesOnly() const { return leavesOnly_; }

 private:
  std::array<int32_t, 3> rootCoord(const char* what, const std::array<int32_t, 3>* prev) {
    std::array<int32_t, 3> c;
    std::memcpy(c.data(), r_.take(12, what), 12);
    for (int32_t v : c) {
      if ((v & 4095) != 0) failAt(what, c, "origin is not a multiple of 4096");
      if (v < -kCoordLimit || v > kCoordLimit - 4096) failAt(what, c, "origin is beyond +-2^30 voxels");
    }
    if (prev && !(*prev < c)) failAt(what, c, "origins are not in increasing order");
    return c;
  }

  [[noreturn]] void failAt(const char* node, const std::array<int32_t, 3>& c, const std::string& why) {
    r_.where().node = node;
    r_.where().origin = c;
    r_.where().fail(why);
  }

  /// An internal node of log2 dimension `log2` (5 or 4).
  void internal(const std::array<int32_t, 3>& origin, int log2, int level) {
    Where& w = r_.where();
    w.node = level == 1 ? "internal node (32^3 children)" : "internal node (16^3 children)";
    w.origin = origin;
    ++(log2 == 5 ? upperNodes_ : lowerNodes_);
    const size_t count = log2 == 5 ? kInt5Values : kInt4Values;
    const size_t maskBytes = count / 8;
    const uint8_t* childMask = r_.take(maskBytes, "child mask");
    const uint8_t* valueMask = r_.take(maskBytes, "value mask");
    uint64_t anyChild = 0, anyTile = 0;
    for (size_t i = 0; i < maskBytes; i += 8) {
      uint64_t c, v;
      std::memcpy(&c, childMask + i, 8);
      std::memcpy(&v, valueMask + i, 8);
      if (c & v) w.fail("child mask and value mask overlap");
      anyChild |= c;
      anyTile |= v;
    }
    const int8_t meta = values(valueMask, count, "tile values");
    // With active-mask compression, metadata 0 and no active tiles, every
    // value of the node is the background, as in a node made for its children.
    if (!anyChild || anyTile || meta != NO_MASK_OR_INACTIVE_VALS || !(compression_ & kActiveMask)) leavesOnly_ = false;
    const int childShift = log2 == 5 ? 7 : 3;  // voxels a child spans, log2
    for (size_t word = 0; word < maskBytes / 8; ++word) {
      uint64_t bits;
      std::memcpy(&bits, childMask + word * 8, 8);
      for (; bits; bits &= bits - 1) {
        const uint32_t n = uint32_t(word * 64 + size_t(std::countr_zero(bits)));
        const int32_t dim = 1 << log2;
        const std::array<int32_t, 3> c{origin[0] + (int32_t(n >> (2 * log2)) << childShift),
                                       origin[1] + (int32_t((n >> log2) & uint32_t(dim - 1)) << childShift),
                                       origin[2] + (int32_t(n & uint32_t(dim - 1)) << childShift)};
        if (log2 == 5) {
          internal(c, 4, 2);
          w.node = "internal node (32^3 children)";
          w.origin = origin;
        } else {
          w.node = "leaf";
          w.origin = c;
          const uint8_t* mask = r_.take(kLeafValues / 8, "leaf value mask");
          leaves_.push_back({c, size_t(mask - topoBytes_)});
          for (size_t k = 0; k < kLeafValues / 64; ++k) {
            uint64_t bits;
            std::memcpy(&bits, mask + k * 8, 8);
            activeVoxels_ += uint64_t(bitCount(bits));
          }
          w.node = "internal node (16^3 children)";
          w.origin = origin;
        }
      }
    }
  }

  /// Frames io::readCompressedValues for `count` values selected by `mask`.
  ValueFrame frameValues(const uint8_t* mask, size_t count, const char* what) {
    ValueFrame f;
    const int8_t meta = f.meta = r_.get<int8_t>(what, "compression metadata");
    if (meta == NO_MASK_AND_ONE_INACTIVE_VAL || meta == MASK_AND_ONE_INACTIVE_VAL || meta == MASK_AND_TWO_INACTIVE_VALS) {
      for (int k = 0; k < (meta == MASK_AND_TWO_INACTIVE_VALS ? 2 : 1); ++k) {
        const uint8_t* v = f.inactive[k] = r_.take(v_.size, "inactive value");
        if (v_.isBool && *v > 1) r_.where().fail(std::string(what) + ": inactive value is not a bool (0 or 1)");
      }
    }
    if (meta == MASK_AND_NO_INACTIVE_VALS || meta == MASK_AND_ONE_INACTIVE_VAL || meta == MASK_AND_TWO_INACTIVE_VALS)
      f.selection = r_.take(count / 8, "selection mask");
    size_t n = count;
    if ((compression_ & kActiveMask) && meta != NO_MASK_AND_ALL_VALS) {
      n = 0;
      for (size_t i = 0; i < count / 64; ++i) {
        uint64_t bits;
        std::memcpy(&bits, mask + i * 8, 8);
        n += size_t(bitCount(bits));
      }
    }
    f.count = n;
    if (half_ && n == 0) return f;  // HalfReader reads nothing for no values
    f.block = frameBlock(r_, compression_, uint64_t(n) * (half_ ? v_.halfSize : v_.size), what);
    f.hasBlock = true;
    return f;
  }

  /// io::readCompressedValues of an internal node's tile values, decoded and
  /// checked at once (they are few). Returns the compression metadata.
  int8_t values(const uint8_t* mask, size_t count, const char* what) {
    const ValueFrame f = frameValues(mask, count, what);
    if (!f.hasBlock) return f.meta;
    std::string why;
    const uint8_t* data = decodeBlock(f.block, scratch_, what, why);
    if (!data) r_.where().fail(why);
    if (v_.isBool)  // bool values must be checked byte by byte
      for (uint64_t i = 0; i < f.block.bytes; ++i)
        if (data[i] > 1) r_.where().fail(std::string(what) + ": a value is " + std::to_string(data[i]) + ", not a bool (0 or 1)");
    return f.meta;
  }

  /// Decompresses the blocks of leaves [0, n) in parallel, handing each leaf
  /// to `sink` when there is one; throws for the first leaf in file order
  /// whose block does not decompress or whose sink call throws.
  void decodeLeaves(const std::vector<FramedLeaf>& framed, size_t n, VdbWalkSink* sink, size_t gridIndex) {
    constexpr size_t kNone = SIZE_MAX;
    std::atomic<size_t> first{kNone};
    std::mutex mutex;
    std::string firstWhy;
    std::exception_ptr firstError;
    auto fault = [&](size_t i, std::string why, std::exception_ptr error) {
      std::lock_guard<std::mutex> lock(mutex);
      if (i >= first.load()) return;
      first.store(i);
      firstWhy = std::move(why);
      firstError = error;
    };
    parallelForEach(n, 0, 64, [&](size_t i) {
      if (i > first.load(std::memory_order_relaxed)) return;  // an earlier leaf is named anyway
      try {
        const FramedLeaf& b = framed[i];
        VdbLeafValues v;
        v.origin = leaves_[i].origin;
        v.valueMask = b.mask;
        v.boolValues = b.boolValues;
        if (!v_.isBool) {
          const ValueFrame& f = b.values;
          v.compressionMeta = f.meta;
          v.inactive[0] = f.inactive[0];
          v.inactive[1] = f.inactive[1];
          v.selectionMask = f.selection;
          v.count = f.count;
          if (f.hasBlock) {
            thread_local std::vector<uint8_t> scratch;
            std::string why;
            v.values = decodeBlock(f.block, scratch, "leaf values", why);
            if (!v.values) return fault(i, std::move(why), nullptr);
          }
        }
        if (sink) sink->leaf(gridIndex, i, v);
      } catch (...) {
        fault(i, {}, std::current_exception());
      }
    });
    const size_t i = first.load();
    if (i == kNone) return;
    if (firstError) std::rethrow_exception(firstError);
    Where& w = r_.where();
    w.node = "leaf";
    w.origin = leaves_[i].origin;
    w.fail(firstWhy);
  }

  Reader& r_;
  const ValueKind& v_;
  bool half_;
  uint32_t compression_;
  const uint8_t* topoBytes_ = nullptr;
  const uint8_t* background_ = nullptr;
  bool leavesOnly_ = true;
  std::vector<Leaf> leaves_;
  uint64_t activeVoxels_ = 0;  // set bits of the leaves' value masks
  uint64_t upperNodes_ = 0, lowerNodes_ = 0;  // internal nodes: 32^3 and 16^3 children
  std::vector<uint8_t> scratch_;
};

/// The value kind of a grid type "Tree_<value>_5_4_3[_HalfFloat]", or nullptr.
const ValueKind* valueKindOf(const std::string& type, bool& halfSuffix) {
  std::string t = type;
  const std::string half = "_HalfFloat";
  halfSuffix = t.size() > half.size() && t.compare(t.size() - half.size(), half.size(), half) == 0;
  if (halfSuffix) t.resize(t.size() - half.size());
  for (const ValueKind& v : kValueKinds)
    if (t == std::string("Tree_") + v.name + "_5_4_3") return &v;
  return nullptr;
}

/// A grid walked up to its leaf buffers.
struct GridWalk {
  VdbGridLayout layout;
  std::unique_ptr<TreeWalk> tree;  // null for instances and grids of types the walk cannot check
};

/// Grid `g`'s compression flags, metadata, transform and topology, up to its
/// block offset. Marks it checked when its type is one the walk checks (the
/// caller walks its buffers next, or throws).
GridWalk walkGridTopology(Reader& r, VdbGridFrame& g, const std::vector<VdbGridFrame>& earlier) {
  GridWalk out;
  Where& w = r.where();
  const uint8_t* base = r.here() - r.pos();
  r.seek(size_t(g.gridPos));
  const uint32_t compression = r.get<uint32_t>("grid compression flags");
  if (compression & ~(kZip | kActiveMask | kBlosc))
    w.fail("unknown compression flags " + std::to_string(compression));
  out.layout.compression = compression;
  const size_t metaAt = r.pos();
  const MetaInfo meta = readMeta(r, "grid");
  out.layout.metadata = base + metaAt;
  out.layout.metadataBytes = r.pos() - metaAt;
  const size_t mapAt = r.pos();
  readMap(r, 0);
  out.layout.transform = base + mapAt;
  out.layout.transformBytes = r.pos() - mapAt;
  bool halfSuffix = false;
  const ValueKind* kind = valueKindOf(g.type, halfSuffix);
  if (!g.instanceParent.empty()) {
    // An instance shares its parent's tree: nothing more is stored.
    const auto parent = std::find_if(earlier.begin(), earlier.end(),
                                     [&](const VdbGridFrame& e) { return e.uniqueName == g.instanceParent; });
    if (parent == earlier.end() || !parent->instanceParent.empty())
      w.fail("instance parent '" + printable(g.instanceParent) + "' is not an earlier, non-instance grid of the file");
    bool parentHalf = false;
    if (valueKindOf(parent->type, parentHalf) != kind || (!kind && parent->type != g.type))
      w.fail("instance parent '" + printable(g.instanceParent) + "' has another type");
    if (r.pos() != size_t(g.blockPos) || r.pos() != size_t(g.endPos))
      w.fail("instance grid holds bytes after its transform");
    g.checked = parent->checked;
    g.uncheckedWhy = parent->uncheckedWhy;
    return out;
  }
  if (!kind) {
    g.uncheckedWhy = "grid type " + printable(g.type) + " is not one vox can check (point grids are not supported)";
    return out;
  }
  // Archive::readGrid stores the descriptor's half flag in the grid metadata,
  // which the grid's own metadata then replaces: both must agree.
  if ((meta.halfFloat == 1) != halfSuffix)
    w.fail("the type " + printable(g.type) + " and metadata 'is_saved_as_half_float' disagree about half-float storage");
  out.tree = std::make_unique<TreeWalk>(r, *kind, halfSuffix, compression);
  out.tree->setTopologyBase(base);
  out.tree->topology();
  if (r.pos() != size_t(g.blockPos))
    w.fail("the topology ends at byte " + std::to_string(r.pos()) + ", not at the grid's block offset " +
           std::to_string(g.blockPos));
  g.leafCount = out.tree->leafCount();
  g.activeLeafVoxels = out.tree->activeLeafVoxels();
  g.upperNodes = out.tree->upperNodes();
  g.lowerNodes = out.tree->lowerNodes();
  g.checked = true;
  out.layout.halfFloat = halfSuffix;
  out.layout.background = out.tree->background();
  out.layout.valueSize = kind->size;
  out.layout.leavesOnly = out.tree->leavesOnly();
  return out;
}

/// Grid `g`'s leaf buffers (TreeWalk::buffers), which must end at its end offset.
void walkGridBuffers(Reader& r, const VdbGridFrame& g, TreeWalk& tree, bool decode, VdbWalkSink* sink, size_t index) {
  r.seek(size_t(g.blockPos));
  tree.buffers(decode, sink, index);
  if (r.pos() != size_t(g.endPos))
    r.where().fail("the leaf buffers end at byte " + std::to_string(r.pos()) + ", not at the grid's end offset " +
                   std::to_string(g.endPos));
}

}  // namespace

/// A walk's state between its two passes. Not movable: the reader refers to
/// `where`, which refers to `name`, and the tree walks refer to the reader.
struct VdbWalkState {
  VdbWalkState(const uint8_t* data, size_t size, const std::string& nameForMessages)
      : name(nameForMessages), r(data, size, where) {
    where.file = &name;
  }
  VdbWalkState(const VdbWalkState&) = delete;
  VdbWalkState& operator=(const VdbWalkState&) = delete;
  std::string name;
  Where where;
  Reader r;
  VdbFrame f;
  const uint8_t* meta = nullptr;  // the file metadata as stored
  size_t metaBytes = 0;
  std::vector<GridWalk> walks;  // kept for the second pass: every grid's
};

namespace {

/// The header, file metadata and grid descriptors, and with Full every
/// grid's topology; the leaf buffers too unless `keep` (they are then walked
/// by finishWalk, the grids' walks kept in `s.walks`).
void walkFirstPass(VdbWalkState& s, VdbCheck depth, bool keep) {
  Where& where = s.where;
  Reader& r = s.r;
  VdbFrame& f = s.f;
  const std::string& name = s.name;
  if (r.size() < 8 || r.get<int64_t>("the magic number") != kMagic) throwBadInput(name + ": not an OpenVDB file (wrong magic number)");
  f.fileVersion = r.get<uint32_t>("the file version");
  if (f.fileVersion < kOldestVersion)
    throwBadInput(name + ": OpenVDB file format " + std::to_string(f.fileVersion) +
                  " is older than vox reads (222 and later, written by OpenVDB 3 or newer): open and save it "
                  "again with a current OpenVDB tool");
  if (f.fileVersion > kNewestVersion)
    throwBadInput(name + ": OpenVDB file format " + std::to_string(f.fileVersion) + " is " +
                  (f.fileVersion > 1000 ? "not plausible; the file is corrupt"
                                        : "newer than vox reads (up to 224); write it with OpenVDB 10 or earlier"));
  f.libraryMajor = r.get<uint32_t>("the library major version");
  f.libraryMinor = r.get<uint32_t>("the library minor version");
  const uint8_t hasGridOffsets = r.get<uint8_t>("the grid-offsets flag");
  r.take(36, "the file UUID");
  const size_t metaAt = r.pos();
  f.metadataNames = readMeta(r, "file").names;
  s.meta = r.here() - (r.pos() - metaAt);
  s.metaBytes = r.pos() - metaAt;
  if (!hasGridOffsets)
    throwBadInput(name + ": the OpenVDB file has no grid offsets (written as a stream); vox reads files written by "
                         "openvdb::io::File");

  const int32_t gridCount = r.get<int32_t>("the grid count");
  if (gridCount < 0) throwBadInput(name + ": the grid count is negative; the file is corrupt");
  std::set<std::string> names;
  for (int32_t i = 0; i < gridCount; ++i) {
    const std::string what = "grid descriptor " + std::to_string(i);
    where.grid.clear();
    VdbGridFrame g;
    g.uniqueName = r.str((what + " name").c_str());
    where.grid = "grid '" + printable(g.uniqueName) + "'";
    if (!names.insert(g.uniqueName).second) where.fail("two grids have this name");
    g.type = r.str("grid type");
    g.instanceParent = r.str("instance parent name");
    g.gridPos = r.get<int64_t>("grid offset");
    g.blockPos = r.get<int64_t>("block offset");
    g.endPos = r.get<int64_t>("end offset");
    // OpenVDB writes a block offset of 0 for instances (they store no blocks).
    if (!g.instanceParent.empty() && g.blockPos == 0) g.blockPos = g.endPos;
    if (g.gridPos != int64_t(r.pos()) || g.blockPos < g.gridPos || g.endPos < g.blockPos)
      where.fail("inconsistent offsets (grid " + std::to_string(g.gridPos) + ", blocks " + std::to_string(g.blockPos) +
                 ", end " + std::to_string(g.endPos) + "); the file is corrupt");
    if (g.endPos > int64_t(r.size()))
      where.fail("truncated OpenVDB file: the grid ends at byte " + std::to_string(g.endPos) + " but the file has " +
                 std::to_string(r.size()) + " bytes");
    if (depth == VdbCheck::Full) {
      GridWalk gw = walkGridTopology(r, g, f.grids);
      if (keep) s.walks.push_back(std::move(gw));
      else if (gw.tree) walkGridBuffers(r, g, *gw.tree, /*decode=*/true, nullptr, 0);
    }
    r.seek(size_t(g.endPos));
    f.grids.push_back(std::move(g));
  }
  where.grid.clear();
}

/// walkVdbInto's second pass over a first pass that kept its grids' walks.
VdbFrame finishWalk(VdbWalkState& s, VdbWalkSink& sink) {
  sink.fileMetadata(s.meta, s.metaBytes);
  const VdbFrame& f = s.f;
  std::vector<VdbGridLayout> layouts;
  for (const GridWalk& gw : s.walks) layouts.push_back(gw.layout);
  const std::vector<VdbLeafUse> use = sink.topologyWalked(f, layouts);
  if (use.size() != f.grids.size()) throw Error(ErrorKind::Internal, "walkVdbInto: the sink answered for another number of grids");
  for (size_t i = 0; i < f.grids.size(); ++i) {
    if (!s.walks[i].tree) continue;
    s.where.grid = "grid '" + printable(f.grids[i].uniqueName) + "'";
    const bool deliver = use[i] == VdbLeafUse::Deliver;
    walkGridBuffers(s.r, f.grids[i], *s.walks[i].tree, deliver, deliver ? &sink : nullptr, i);
    if (deliver) sink.gridDone(i);
  }
  return f;
}

}  // namespace

VdbFrame checkVdbStructure(const uint8_t* data, size_t size, const std::string& name, VdbCheck depth) {
  VdbWalkState s(data, size, name);
  walkFirstPass(s, depth, /*keep=*/false);
  return std::move(s.f);
}

VdbFrame walkVdbInto(const uint8_t* data, size_t size, const std::string& name, VdbWalkSink& sink) {
  VdbWalkState s(data, size, name);
  walkFirstPass(s, VdbCheck::Full, /*keep=*/true);
  return finishWalk(s, sink);
}

VdbTopologyWalk::VdbTopologyWalk(const std::string& path) : path_(path) {
  checkVdbFileOpenable(path);
  file_ = std::make_unique<FileView>(path, /*populate=*/false);
  state_ = std::make_unique<VdbWalkState>(reinterpret_cast<const uint8_t*>(file_->data()), file_->size(), path);
  walkFirstPass(*state_, VdbCheck::Full, /*keep=*/true);
  frame_ = state_->f;
}

VdbTopologyWalk::~VdbTopologyWalk() = default;

VdbFrame VdbTopologyWalk::finish(VdbWalkSink& sink) {
  if (!state_) throw Error(ErrorKind::Internal, "VdbTopologyWalk::finish: the walk was already finished");
  // Released when the read ends, however it ends: the pages, the leaf lists.
  const std::unique_ptr<FileView> file = std::move(file_);
  const std::unique_ptr<VdbWalkState> state = std::move(state_);
  return finishWalk(*state, sink);
}

namespace {

/// What identifies a file's content without reading it, for the memo below.
struct FileStamp {
  std::string path;
  uint64_t dev = 0, ino = 0, size = 0;
  int64_t mtime = 0, ctime = 0;  // ns
  bool operator<(const FileStamp& o) const {
    return std::tie(path, dev, ino, size, mtime, ctime) < std::tie(o.path, o.dev, o.ino, o.size, o.mtime, o.ctime);
  }
  bool operator==(const FileStamp& o) const { return !(*this < o) && !(o < *this); }
};

bool stampOf(const std::string& path, FileStamp& s) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return false;
  s = {path, uint64_t(st.st_dev), uint64_t(st.st_ino), uint64_t(st.st_size),
       int64_t(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec,
       int64_t(st.st_ctim.tv_sec) * 1000000000 + st.st_ctim.tv_nsec};
  return true;
}

}  // namespace

VdbFrame checkVdbStructure(const std::string& path, VdbCheck depth) {
  // A full walk decompresses every block; commands that open a file more than
  // once (info, then the scene reader) reuse it. Only for files whose status
  // last changed over two seconds before the walk: any later change of the
  // content sets the change time (which users cannot set back) to a later
  // clock tick, so a remembered walk never stands for other bytes.
  static std::mutex mutex;
  static std::map<FileStamp, VdbFrame> memo;
  FileStamp before;
  const bool stamped = depth == VdbCheck::Full && stampOf(path, before);
  if (stamped) {
    std::lock_guard<std::mutex> lock(mutex);
    const auto it = memo.find(before);
    if (it != memo.end()) return it->second;
  }
  timespec now{};
  ::clock_gettime(CLOCK_REALTIME, &now);
  VdbFrame frame;
  {
    const FileView file(path);  // mapped
    frame = checkVdbStructure(reinterpret_cast<const uint8_t*>(file.data()), file.size(), path, depth);
  }
  FileStamp after;
  const int64_t nowNs = int64_t(now.tv_sec) * 1000000000 + now.tv_nsec;
  if (stamped && stampOf(path, after) && after == before && nowNs - before.ctime > 2000000000) {
    std::lock_guard<std::mutex> lock(mutex);
    if (memo.size() >= 16) memo.clear();
    memo[before] = frame;
  }
  return frame;
}

bool looksLikeVdb(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  int32_t magic = 0;
  in.read(reinterpret_cast<char*>(&magic), sizeof magic);
  return in && magic == 0x56444220;  // OpenVDB's OPENVDB_MAGIC (" BDV")
}

void checkVdbFileOpenable(const std::string& path) {
  // A missing or unopenable file is worded as every other input's ("no such
  // file", "cannot open the file: Permission denied"); what is not a regular
  // file is told it should be a .vdb file.
  requireRegularFile(path, "is a directory, expected a .vdb file",
                     "is not a regular file (a FIFO, socket or device); vox reads .vdb files only from regular files");
  if (!looksLikeVdb(path)) throwBadInput(path + ": not an OpenVDB file (wrong magic number)");
}

}  // namespace vox
