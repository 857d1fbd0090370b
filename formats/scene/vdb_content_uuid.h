// The UUID in an OpenVDB file's header, made from the file's content rather
// than drawn at random, so a scene written twice from the same input is the
// same bytes (golden-file diffs, build caches). OpenVDB's own writer
// (openvdb::io::File) draws a random UUID on every write.
//
// The file header (Archive::writeHeader) is: the magic number (8 bytes), the
// file version and the library's major and minor versions (4 bytes each),
// "has grid offsets" (1 byte), then the UUID as 36 characters at byte 21.
// The UUID's 16 bytes are four CRC32C of what follows it (metadata and
// grids), each started from its own seed, as 8-4-4-4-12 hex digits with the
// version 4 and variant 1 bits set. stampVdbContentUuid hashes the finished
// file; the direct scene writer (scene_vdb_direct.h) hashes its stream as it
// writes it, before it patches each grid's stream positions in, so the two
// writers give different UUIDs for the same content, each the same every time.
//
// Thread-safety: pure functions and a file the caller owns.
#pragma once

#include <array>
#include <cstdint>
#include <string>

namespace vox {

/// Where the UUID's 36 characters start in an OpenVDB file, and their count.
inline constexpr uint64_t kVdbUuidOffset = 21;
inline constexpr size_t kVdbUuidChars = 36;

/// The four CRC32C seeds of the digest (CRC32C of the content continues from each).
inline constexpr std::array<uint32_t, 4> kVdbUuidSeeds{0x01234567u, 0x89abcdefu, 0xfedcba98u, 0x76543210u};

/// The 36-character UUID text for a digest (the four CRC32C, seeded with kVdbUuidSeeds).
std::string vdbUuidText(const std::array<uint32_t, 4>& digest);

/// Replaces the UUID of the OpenVDB file at `path` (written by openvdb::io::File,
/// complete) with the one its content gives. Throws vox::Error (Io), naming
/// `shownName`, when the file cannot be read or written or is too short for a header.
void stampVdbContentUuid(const std::string& path, const std::string& shownName);

}  // namespace vox
