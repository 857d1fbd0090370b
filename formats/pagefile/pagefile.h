// Page files (`.vpk`): a scene and its mips cut into C^3 chunks, one file,
// specified in formats/pagefile/PAGEFILE.md. This is the container: header,
// index, metadata text and payloads at aligned offsets, written by serialize()
// and read by Reader. What a payload holds is its layout's business
// (formats/pagefile/layouts.h); the metadata text is formats/pagefile/pagefile_meta.h;
// packing a Scene is formats/pagefile/pack_chunks.h.
//
// No OpenVDB: the reader is light (mmap, bounds-checked, CRC32C-verified) so
// streamers and the fuzz target link it (and the layouts) alone.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "formats/pagefile/layouts.h"
#include "libvox/core/version.h"

namespace vox::pagefile {

inline constexpr char kMagic[8] = {'V', 'O', 'X', 'P', 'A', 'G', 'E', 'S'};
inline constexpr uint16_t kVersion = kPageFileFormatVersion;
inline constexpr uint32_t kHeaderBytes = 128;
inline constexpr uint32_t kIndexEntryBytes = 32;

/// Byte offsets of the header fields (PAGEFILE.md "Header"), for the writer and the reader.
namespace header_field {
inline constexpr size_t kMagic = 0;          // 8 bytes "VOXPAGES"
inline constexpr size_t kVersion = 8;        // u16
inline constexpr size_t kHeaderBytes = 10;   // u16
inline constexpr size_t kLayout = 12;        // u8
inline constexpr size_t kChunkLog2 = 13;     // u8
inline constexpr size_t kLevelCount = 14;    // u8
inline constexpr size_t kAlignLog2 = 15;     // u8
inline constexpr size_t kFlags = 16;         // u32
inline constexpr size_t kDims = 20;          // 3 x u32
inline constexpr size_t kVoxelSize = 32;     // f64
inline constexpr size_t kOrigin = 40;        // 3 x f64
inline constexpr size_t kChunkCount = 64;    // u64
inline constexpr size_t kIndexOffset = 72;   // u64
inline constexpr size_t kMetaOffset = 80;    // u64
inline constexpr size_t kMetaBytes = 88;     // u64
inline constexpr size_t kPayloadOffset = 96; // u64
inline constexpr size_t kFileBytes = 104;    // u64
inline constexpr size_t kMetaCrc = 112;      // u32
inline constexpr size_t kIndexCrc = 116;     // u32
inline constexpr size_t kReserved = 120;     // u32, 0
inline constexpr size_t kHeaderCrc = 124;    // u32, CRC32C of bytes [0, kHeaderCrc)
}  // namespace header_field

/// Byte offsets of the fields of an index entry (PAGEFILE.md "Index entry").
namespace entry_field {
inline constexpr size_t kLevel = 0;     // u8
inline constexpr size_t kFlags = 1;     // u8
inline constexpr size_t kReserved = 2;  // u16, 0
inline constexpr size_t kOccupied = 4;  // u32
inline constexpr size_t kKey = 8;       // u64
inline constexpr size_t kOffset = 16;   // u64
inline constexpr size_t kSize = 24;     // u32
inline constexpr size_t kCrc = 28;      // u32
}  // namespace entry_field

/// Chunk sides C = 1 << chunkLog2 a file may have (8, 16, 32).
inline constexpr uint8_t kMinChunkLog2 = 3, kMaxChunkLog2 = 5;
/// Payload alignments 1 << alignLog2 a file may have (8 .. 65536 bytes).
inline constexpr uint8_t kMinAlignLog2 = 3, kMaxAlignLog2 = 16;
/// Header::alignLog2 of a file still to be laid out: planFile chooses the
/// alignment from the payload sizes (chooseAlignLog2). Never in a written file.
inline constexpr uint8_t kAlignAuto = 0;
/// The two alignments the automatic choice picks between: 4 KiB (a page, so
/// every payload can be read with O_DIRECT or mapped page by page) and 64
/// bytes (a cache line; compact for the small chunks of sparse surfaces).
inline constexpr uint8_t kAutoAlignPageLog2 = 12, kAutoAlignCompactLog2 = 6;
/// Level-0 dims per axis: 1 .. kMaxDim.
inline constexpr uint32_t kMaxDim = 1u << 20;

// Header flags: which per-voxel channels the payloads carry.
inline constexpr uint32_t kFlagColor = 1;    // RGBA8 per occupied voxel
inline constexpr uint32_t kFlagSurface = 2;  // 1 surface bit per occupied voxel (absent: all are surface)
inline constexpr uint32_t kKnownFlags = kFlagColor | kFlagSurface;

// Index entry flags.
inline constexpr uint8_t kChunkFull = 1;  // every voxel occupied: no occupancy bitmap

struct Header {
  Layout layout = Layout::Bricks;
  uint8_t chunkLog2 = 4;  // C = 1 << chunkLog2: kMinChunkLog2 .. kMaxChunkLog2
  uint8_t levelCount = 1;
  uint8_t alignLog2 = 12;  // payloads start at multiples of 1 << alignLog2 (kMinAlignLog2 .. kMaxAlignLog2;
                           // kAlignAuto before planFile lays the file out)
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

/// A chunk ready to be written (packing fills these, sorted by (level, key)).
struct ChunkBlob {
  uint8_t level = 0;
  uint64_t key = 0;
  uint32_t occupied = 0;
  bool full = false;
  std::vector<uint8_t> bytes;
};

/// One chunk of a file being laid out: its index entry but the offset.
struct ChunkSlot {
  uint8_t level = 0;
  uint64_t key = 0;
  uint32_t occupied = 0;
  bool full = false;
  uint64_t size = 0;  // payload bytes
  uint32_t crc = 0;   // CRC32C of the payload
};

/// A page file laid out before its payloads are written: the header with
/// every offset, size and CRC; the index entries with their offsets; and the
/// file's first header.payloadOffset bytes (header, index, metadata, zero
/// padding). Payload i goes at entries[i].offset, zero bytes between payloads,
/// the file ends with the last payload (header.fileBytes). serialize() is this
/// plan plus the payloads; a writer that streams payloads (the merge of region
/// parts) uses it directly. Same checks as serialize().
struct FilePlan {
  Header header;
  std::vector<IndexEntry> entries;
  std::vector<uint8_t> prefix;
};
/// A header.alignLog2 of kAlignAuto is replaced by chooseAlignLog2(chunks).
FilePlan planFile(Header header, const std::string& metaJson, std::span<const ChunkSlot> chunks);

/// The automatic payload alignment of a file holding `chunks` (every level):
/// kAutoAlignPageLog2 when padding each payload to 4 KiB makes the payload
/// area at most 1/8 larger than padding to 64 bytes, else
/// kAutoAlignCompactLog2. Dense scenes (chunks of several KiB) keep page
/// alignment for almost nothing; sparse surfaces, whose chunks hold a few
/// hundred bytes, would be mostly padding. A function of the payload sizes
/// only, so a region bake's merge, which lays out the same chunks, makes the
/// same choice as the single-process pack.
uint8_t chooseAlignLog2(std::span<const ChunkSlot> chunks);

/// Serializes a whole page file: header, index, metadata (JSON text, see
/// PAGEFILE.md), payloads at aligned offsets. `header` gives layout, chunkLog2,
/// levelCount, alignLog2, flags, dims, voxelSize, origin; the rest is computed.
/// Throws vox::Error (Internal) when chunks are not sorted or sizes are wrong.
std::vector<uint8_t> serialize(Header header, const std::string& metaJson, const std::vector<ChunkBlob>& chunks);

/// The plan serialize() makes for `chunks` (their CRCs computed here).
FilePlan planChunks(Header header, const std::string& metaJson, const std::vector<ChunkBlob>& chunks);

/// Writes the file serialize() would return, without assembling it in memory:
/// the plan's prefix, then each payload at its offset. The zero bytes between
/// payloads (most of a file with 4 KiB alignment) are not written: the file
/// system reads them back as zeros (a sparse file). Throws vox::Error (Io)
/// naming `nameForMessages` when a write fails.
void writePlannedFile(const std::string& path, const FilePlan& plan, const std::vector<ChunkBlob>& chunks,
                      const std::string& nameForMessages);

/// One occupied voxel of a decoded chunk (any layout).
struct DecodedVoxel {
  uint32_t index = 0;  // x + C * (y + C * z), chunk-local
  std::array<uint8_t, 4> summary{};  // cls, conf, obs, mrg
  bool surface = true;
  std::array<uint8_t, 4> color{};  // sRGB8 + alpha (255: has colour, 0: none); zeros without kFlagColor
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
  /// Decodes entry i with the file's layout (LayoutCodec::decode) into its
  /// occupied voxels in rank order (ascending chunk-local index); checks the
  /// payload against its masks: popcount = occupied, no voxel outside the
  /// level's domain, classes 1..255, colour alpha 0 or 255, padding bits zero,
  /// and the layout's own structure (svo: node tree, brick table, mip bricks;
  /// columns: masks, ladder, offsets).
  std::vector<DecodedVoxel> decode(size_t i) const;
  /// Every payload: CRC and decode(); then checkPadding(). Returns the
  /// number of voxels checked.
  uint64_t verify() const;
  /// The bytes between the end of the metadata and the first payload, and
  /// between payloads, are zero (PAGEFILE.md "File layout"): what a writer
  /// leaves there is not covered by any CRC, so a non-zero byte is damage (or
  /// a writer hiding data) that nothing else would see. Throws naming the
  /// byte's offset and the chunk it precedes.
  void checkPadding() const;

  /// "chunk 12 (level 0, chunk (3, 1, 2))" for messages.
  std::string describe(size_t i) const;

 private:
  Reader() = default;
  void parse();
  void parseHeader();
  void parseIndex();
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
