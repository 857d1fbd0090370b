// Page files (`.vpk`): a scene and its mips cut into C^3 chunks, one file,
// specified in formats/pagefile/PAGEFILE.md. This header has no OpenVDB: the reader is
// light (mmap, bounds-checked, CRC32C-verified) so streamers and the fuzz
// target link it alone. Packing a Scene is in formats/pagefile/pack_chunks.h.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace vox::pagefile {

inline constexpr char kMagic[8] = {'V', 'O', 'X', 'P', 'A', 'G', 'E', 'S'};
inline constexpr uint16_t kVersion = 1;
inline constexpr uint32_t kHeaderBytes = 128;
inline constexpr uint32_t kIndexEntryBytes = 32;

enum class Layout : uint8_t { Bricks = 1, Svo = 2, Columns = 3 };
const char* layoutName(Layout l);  // "bricks", "svo", "columns"

// Header flags: which per-voxel channels the payloads carry.
inline constexpr uint32_t kFlagColor = 1;    // RGBA8 per occupied voxel
inline constexpr uint32_t kFlagSurface = 2;  // 1 surface bit per occupied voxel (absent: all are surface)
inline constexpr uint32_t kKnownFlags = kFlagColor | kFlagSurface;

// Index entry flags.
inline constexpr uint8_t kChunkFull = 1;  // every voxel occupied: no occupancy bitmap

struct Header {
  Layout layout = Layout::Bricks;
  uint8_t chunkLog2 = 4;  // C = 1 << chunkLog2: 3, 4 or 5
  uint8_t levelCount = 1;
  uint8_t alignLog2 = 12;  // payloads start at multiples of 1 << alignLog2 (3..16)
  uint32_t flags = 0;
  std::array<uint32_t, 3> dims{};  // level 0
  double voxelSize = 1.0;
  std::array<double, 3> origin{};
  uint64_t chunkCount = 0;
  uint64_t indexOffset = kHeaderBytes;
  uint64_t metaOffset = 0, metaBytes = 0;
  uint64_t payloadOffset = 0;  // first payload byte (aligned)
  uint64_t fileBytes = 0;
  uint32_t metaCrc = 0, indexCrc = 0;

  uint32_t chunkSide() const { return 1u << chunkLog2; }
  uint32_t chunkVoxels() const { return 1u << (3 * chunkLog2); }
  std::array<uint32_t, 3> levelDims(int level) const;
  std::array<uint32_t, 3> levelChunks(int level) const;  // ceil(levelDims / C)
};

struct IndexEntry {
  uint8_t level = 0;
  uint8_t flags = 0;
  uint32_t occupied = 0;  // voxels in the chunk, 1..C^3
  uint64_t key = 0;       // Morton key of the chunk coordinates (libvox/core/morton.h)
  uint64_t offset = 0;    // of the payload, from the start of the file
  uint32_t size = 0;      // payload bytes
  uint32_t crc = 0;       // CRC32C of the payload
  std::array<uint32_t, 3> chunk() const;  // decoded key
};

/// True when the file starts with the page file magic (cheap sniffing).
bool looksLikePageFile(const std::string& path);

/// Bytes of a bricks-layout payload.
uint64_t bricksPayloadBytes(uint32_t chunkVoxels, uint32_t occupied, bool full, uint32_t flags);

/// The `svo` layout (PAGEFILE.md): node flags, the brick table's "no bitmap"
/// slot, the fixed part of a payload.
inline constexpr uint8_t kSvoNodeFull = 1;   // the node's brick has all 512 voxels (no bitmap stored)
inline constexpr uint8_t kSvoNodeColor = 2;  // some voxel of the node's brick has a colour
inline constexpr uint32_t kSvoNoBitmap = 0xFFFFFFFFu;
inline constexpr uint32_t kSvoFixedBytes = 16;
/// Bytes of an svo payload with `nodes` nodes (= bricks), `bitmaps` stored
/// bitmaps and `records` voxel records (leaf and mip voxels).
uint64_t svoPayloadBytes(uint64_t nodes, uint64_t bitmaps, uint64_t records, uint32_t flags);

/// The `columns` layout (PAGEFILE.md).
inline constexpr uint32_t kColumnsFixedBytes = 8;
/// u32 words of a mask of side^3 bits: ceil(side^3 / 32).
uint32_t columnsLadderWordCount(uint32_t side);
/// Bytes of the mip ladder of a chunk of side C (levels 1 .. log2 C - 1).
uint64_t columnsLadderBytes(uint32_t chunkSide);
/// Bytes of a columns payload.
uint64_t columnsPayloadBytes(uint32_t chunkSide, uint32_t occupied, uint32_t surfaceCount, bool full, uint32_t flags);

/// A chunk ready to be written (packing fills these, sorted by (level, key)).
struct ChunkBlob {
  uint8_t level = 0;
  uint64_t key = 0;
  uint32_t occupied = 0;
  bool full = false;
  std::vector<uint8_t> bytes;
};

/// Serializes a whole page file: header, index, metadata (JSON text, see
/// PAGEFILE.md), payloads at aligned offsets. `header` gives layout, chunkLog2,
/// levelCount, alignLog2, flags, dims, voxelSize, origin; the rest is computed.
/// Throws vox::Error (Internal) when chunks are not sorted or sizes are wrong.
std::vector<uint8_t> serialize(Header header, const std::string& metaJson, const std::vector<ChunkBlob>& chunks);

/// One decoded chunk (any layout): occupied voxels in rank order.
struct DecodedVoxel {
  uint32_t index = 0;  // x + C * (y + C * z), chunk-local
  std::array<uint8_t, 4> summary{};  // cls, conf, obs, mrg
  bool surface = true;
  std::array<uint8_t, 4> color{};  // sRGB8 + alpha (255: has colour, 0: none); zeros without kFlagColor
};

/// One node of an svo-layout chunk with its decoded brick (Reader::svoBricks).
struct SvoBrick {
  uint32_t node = 0;      // index in the node pool (= brick index)
  uint8_t level = 0;      // 0: a leaf brick (voxels of the chunk); L > 0: a mip brick, voxels 2^L wide
  uint8_t childMask = 0;  // octants of the brick that hold an occupied voxel (inner nodes: the children)
  uint8_t flags = 0;      // kSvoNodeFull, kSvoNodeColor
  uint32_t childPtr = 0;  // inner nodes: first child; leaves: the brick (= node)
  std::array<uint32_t, 3> origin{};  // chunk-local level-0 voxel at the node's min corner
  std::vector<DecodedVoxel> voxels;  // index = bx + 8 * (by + 8 * bz) within the brick, ascending
};

/// A page file opened for reading. Opening checks the header, the index and
/// the metadata (CRCs, every bound, sort order, sizes); payload CRCs are
/// checked when a payload is read (payload()) or by verify(). Every error is a
/// vox::Error (BadInput) naming the file, the chunk and the field.
class Reader {
 public:
  /// Maps `path` read-only.
  static Reader open(const std::string& path);
  /// Reads from memory the caller keeps alive (tests, fuzzing).
  static Reader fromMemory(const uint8_t* data, size_t size, const std::string& name);
  Reader(Reader&&) noexcept;
  ~Reader();

  const Header& header() const { return header_; }
  const std::vector<IndexEntry>& entries() const { return entries_; }
  const std::string& metaJson() const { return meta_; }
  const std::string& name() const { return name_; }

  /// O(log n): the entry of chunk (x, y, z) of `level`, or nullptr when the
  /// chunk is empty (absent).
  const IndexEntry* find(int level, uint32_t x, uint32_t y, uint32_t z) const;
  /// [first, last) entries of a level.
  std::pair<size_t, size_t> levelRange(int level) const;

  /// The payload bytes of entry i, after checking its CRC32C.
  std::span<const uint8_t> payload(size_t i) const;
  /// Decodes entry i, any layout, into its occupied voxels in rank order
  /// (ascending chunk-local index); checks the payload against its masks:
  /// popcount = occupied, no voxel outside the level's domain, classes 1..255,
  /// colour alpha 0 or 255, padding bits zero, and the layout's own structure
  /// (svo: node tree, brick table, mip bricks; columns: masks, ladder, offsets).
  std::vector<DecodedVoxel> decode(size_t i) const;
  /// svo layout only: every node of entry i with its brick, in node order (the
  /// same checks as decode()).
  std::vector<SvoBrick> svoBricks(size_t i) const;
  /// Every payload: CRC and decode(). Returns the number of voxels checked.
  uint64_t verify() const;

  /// "chunk 12 (level 0, chunk (3, 1, 2))" for messages.
  std::string describe(size_t i) const;

 private:
  Reader() = default;
  void parse();
  std::vector<DecodedVoxel> decodeBricks(size_t i) const;
  std::vector<DecodedVoxel> decodeSvo(size_t i, std::vector<SvoBrick>* bricks) const;
  std::vector<DecodedVoxel> decodeColumns(size_t i) const;
  std::string name_;
  const uint8_t* data_ = nullptr;
  size_t size_ = 0;
  void* map_ = nullptr;
  size_t mapSize_ = 0;
  Header header_;
  std::vector<IndexEntry> entries_;
  std::string meta_;
};

}  // namespace vox::pagefile
