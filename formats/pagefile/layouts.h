// The payload layouts of a page file (formats/pagefile/PAGEFILE.md): how one
// chunk's voxels become the bytes of its payload and back.
//
// Each layout lives in one file pair that holds its encoder, its decoder and its
// size rules: the brick layout (bricks_layout.h), the sparse-voxel-octree layout
// (svo_layout.h) and the column layout (columns_layout.h). The table in
// layouts.cpp is the only place that lists them; the container (pagefile.h),
// the packer (pack_chunks.h) and the CLI find a layout through it. Adding a
// layout touches its own file pair, this enum and the table, PAGEFILE.md and
// the tests.
//
// No OpenVDB here: the reader and the fuzz target link the layouts alone.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "libvox/core/scene_header.h"

namespace vox::pagefile {

/// The header's `layout` byte. Values are the table's ids, 1, 2, 3, ... with no gap.
enum class Layout : uint8_t { Bricks = 1, Svo = 2, Columns = 3 };

struct Header;
struct IndexEntry;
struct DecodedVoxel;
class Reader;

/// One chunk's voxels, dense, at the chunk-local index k = x + C * (y + C * z):
/// what every encoder reads. packChunks fills it from a scene; an encoder may
/// use only the voxels whose bit is set.
struct ChunkVoxels {
  uint32_t side = 0;   // C
  uint32_t count = 0;  // occupied voxels
  std::vector<uint64_t> bits;  // C^3 / 64 words, bit k % 64 of word k / 64
  std::vector<std::array<uint8_t, 4>> summary;  // cls, conf, obs, mrg
  std::vector<std::array<uint8_t, 4>> color;    // sRGB8 + alpha 255, or 0,0,0,0 without colour
  std::vector<uint8_t> surface;                 // 1: surface voxel
  // Only with `withVotes` (LayoutCodec::encoderNeedsVotes):
  bool withVotes = false;
  std::vector<uint32_t> voteBegin, voteEnd;  // range of voxel k in `votes`
  std::vector<ClassVotes> votes;
  std::vector<std::array<float, 3>> linear;  // linear colour of voxel k when color[k][3] == 255

  bool occupied(uint32_t k) const { return (bits[k >> 6] >> (k & 63)) & 1; }
};

/// Where a chunk is, for an encoder's error messages.
struct ChunkPlace {
  int level = 0;
  std::array<uint32_t, 3> chunk{};
};

/// One chunk's payload as a decoder reads it: CRC already checked, the index
/// entry already validated (level, key, occupied, full bit, fixed size).
struct ChunkPayload {
  const Reader& reader;  // for messages
  size_t index;          // of the entry in the index
  const Header& header;
  const IndexEntry& entry;
  std::span<const uint8_t> bytes;

  /// Throws vox::Error (BadInput) "<file>: chunk i (level l, chunk (x, y, z)): <what>".
  [[noreturn]] void fail(const std::string& what) const;
};

/// A layout: its name, its size rules, its encoder and its decoder.
struct LayoutCodec {
  Layout id;
  const char* name;     // in messages, `vox info` and the CLI: "bricks"
  const char* summary;  // one line for help texts
  /// The encoder reads ChunkVoxels::votes and ::linear (packChunks fills them only then).
  bool encoderNeedsVotes;
  /// Every payload has at least this many bytes; the reader refuses shorter ones on opening.
  uint32_t fixedBytes;
  /// The exact payload size that the header and the index entry determine; the
  /// reader checks it on opening and serialize() on writing. nullptr when the
  /// size depends on counts inside the payload (decode checks it then).
  uint64_t (*sizeFromIndex)(const Header& header, const IndexEntry& entry);
  /// The payload of one non-empty chunk; `flags` are the header's channel flags.
  /// Throws vox::Error (Usage) for voxels the layout cannot hold, naming `place`.
  std::vector<uint8_t> (*encode)(const ChunkVoxels& chunk, uint32_t flags, const ChunkPlace& place);
  /// The occupied voxels of a payload in ascending chunk-local index, after
  /// every check of PAGEFILE.md's "What a reader must check" for the layout.
  std::vector<DecodedVoxel> (*decode)(const ChunkPayload& payload);
};

/// Every layout, by ascending id.
std::span<const LayoutCodec> layoutTable();
/// The layout with header byte `id`, or nullptr.
const LayoutCodec* findLayout(uint8_t id);
/// The layout called `name` ("bricks", "svo", "columns"), or nullptr.
const LayoutCodec* findLayout(std::string_view name);
/// The table row of `layout`; throws vox::Error (Internal) for a value outside the table.
const LayoutCodec& codecOf(Layout layout);
/// "bricks", "svo", "columns"; "unknown" outside the table.
const char* layoutName(Layout layout);
/// The names for messages: "bricks, svo or columns".
std::string layoutNameList();

}  // namespace vox::pagefile
