#include "formats/pagefile/pagefile.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "libvox/core/crc32c.h"
#include "libvox/core/error.h"
#include "libvox/core/morton.h"

namespace vox::pagefile {

namespace {

// Little-endian field access (the format is little-endian on every host).
template <typename T>
T load(const uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  if constexpr (std::endian::native == std::endian::big && sizeof(T) > 1) {
    uint8_t b[sizeof(T)];
    std::memcpy(b, &v, sizeof v);
    std::reverse(b, b + sizeof(T));
    std::memcpy(&v, b, sizeof v);
  }
  return v;
}

template <typename T>
void store(uint8_t* p, T v) {
  if constexpr (std::endian::native == std::endian::big && sizeof(T) > 1) {
    uint8_t b[sizeof(T)];
    std::memcpy(b, &v, sizeof v);
    std::reverse(b, b + sizeof(T));
    std::memcpy(p, b, sizeof v);
  } else {
    std::memcpy(p, &v, sizeof v);
  }
}

// CRC comparisons. Fuzz builds (libFuzzer defines the macro) ignore mismatches so
// that mutated inputs reach the bounds checks behind the checksums.
bool crcDiffers(uint32_t stored, uint32_t computed) {
#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
  (void)stored, (void)computed;
  return false;
#else
  return stored != computed;
#endif
}

uint64_t alignUp(uint64_t v, uint64_t a) { return (v + a - 1) & ~(a - 1); }

void encodeHeader(const Header& h, uint8_t* p) {
  std::memset(p, 0, kHeaderBytes);
  std::memcpy(p, kMagic, 8);
  store<uint16_t>(p + 8, kVersion);
  store<uint16_t>(p + 10, uint16_t(kHeaderBytes));
  p[12] = uint8_t(h.layout);
  p[13] = h.chunkLog2;
  p[14] = h.levelCount;
  p[15] = h.alignLog2;
  store<uint32_t>(p + 16, h.flags);
  for (int k = 0; k < 3; ++k) store<uint32_t>(p + 20 + 4 * k, h.dims[size_t(k)]);
  store<double>(p + 32, h.voxelSize);
  for (int k = 0; k < 3; ++k) store<double>(p + 40 + 8 * k, h.origin[size_t(k)]);
  store<uint64_t>(p + 64, h.chunkCount);
  store<uint64_t>(p + 72, h.indexOffset);
  store<uint64_t>(p + 80, h.metaOffset);
  store<uint64_t>(p + 88, h.metaBytes);
  store<uint64_t>(p + 96, h.payloadOffset);
  store<uint64_t>(p + 104, h.fileBytes);
  store<uint32_t>(p + 112, h.metaCrc);
  store<uint32_t>(p + 116, h.indexCrc);
  store<uint32_t>(p + 124, crc32c(p, 124));
}

void encodeEntry(const IndexEntry& e, uint8_t* p) {
  std::memset(p, 0, kIndexEntryBytes);
  p[0] = e.level;
  p[1] = e.flags;
  store<uint32_t>(p + 4, e.occupied);
  store<uint64_t>(p + 8, e.key);
  store<uint64_t>(p + 16, e.offset);
  store<uint32_t>(p + 24, e.size);
  store<uint32_t>(p + 28, e.crc);
}

std::string hex(uint32_t v) {
  char b[16];
  std::snprintf(b, sizeof b, "0x%08x", v);
  return b;
}

}  // namespace

const char* layoutName(Layout l) {
  switch (l) {
    case Layout::Bricks: return "bricks";
    case Layout::Svo: return "svo";
    case Layout::Columns: return "columns";
  }
  return "unknown";
}

bool looksLikePageFile(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  char magic[8] = {};
  const bool ok = ::read(fd, magic, 8) == 8 && std::memcmp(magic, kMagic, 8) == 0;
  ::close(fd);
  return ok;
}

std::array<uint32_t, 3> Header::levelDims(int level) const {
  std::array<uint32_t, 3> d;
  for (int k = 0; k < 3; ++k)
    d[size_t(k)] = uint32_t((uint64_t(dims[size_t(k)]) + (uint64_t(1) << level) - 1) >> level);
  return d;
}

std::array<uint32_t, 3> Header::levelChunks(int level) const {
  std::array<uint32_t, 3> d = levelDims(level);
  for (auto& a : d) a = (a + chunkSide() - 1) >> chunkLog2;
  return d;
}

std::array<uint32_t, 3> IndexEntry::chunk() const { return mortonDecode(key); }

uint64_t bricksPayloadBytes(uint32_t chunkVoxels, uint32_t occupied, bool full, uint32_t flags) {
  uint64_t n = full ? 0 : chunkVoxels / 8;
  n += 4ull * occupied;
  if (flags & kFlagColor) n += 4ull * occupied;
  if (flags & kFlagSurface) n += (uint64_t(occupied) + 7) / 8;
  return n;
}

uint64_t svoPayloadBytes(uint64_t nodes, uint64_t bitmaps, uint64_t records, uint32_t flags) {
  uint64_t n = kSvoFixedBytes + 16 * nodes + 64 * bitmaps + 4 * records;
  if (flags & kFlagColor) n += 4 * records;
  if (flags & kFlagSurface) n += (records + 7) / 8;
  return n;
}

uint32_t columnsLadderWordCount(uint32_t side) { return uint32_t((uint64_t(side) * side * side + 31) / 32); }

uint64_t columnsLadderBytes(uint32_t chunkSide) {
  uint64_t n = 0;
  for (uint32_t s = chunkSide / 2; s >= 2; s /= 2) n += 4ull * columnsLadderWordCount(s);
  return n;
}

uint64_t columnsPayloadBytes(uint32_t chunkSide, uint32_t occupied, uint32_t surfaceCount, bool full, uint32_t flags) {
  const uint64_t N = uint64_t(chunkSide) * chunkSide * chunkSide;
  uint64_t n = kColumnsFixedBytes;
  if (!full) n += N / 8 + columnsLadderBytes(chunkSide);
  if (flags & kFlagSurface) n += N / 8;
  n += 4ull * occupied;
  if (flags & kFlagColor) n += 4ull * (uint64_t(chunkSide) * chunkSide + 1) + 4ull * surfaceCount;
  return n;
}

std::vector<uint8_t> serialize(Header h, const std::string& metaJson, const std::vector<ChunkBlob>& chunks) {
  const uint64_t align = uint64_t(1) << h.alignLog2;
  h.chunkCount = chunks.size();
  h.indexOffset = kHeaderBytes;
  h.metaOffset = h.indexOffset + kIndexEntryBytes * h.chunkCount;
  h.metaBytes = metaJson.size();
  h.payloadOffset = alignUp(h.metaOffset + h.metaBytes, align);
  std::vector<IndexEntry> entries(chunks.size());
  uint64_t at = h.payloadOffset;
  for (size_t i = 0; i < chunks.size(); ++i) {
    const ChunkBlob& c = chunks[i];
    if (i > 0 && std::make_pair(chunks[i - 1].level, chunks[i - 1].key) >= std::make_pair(c.level, c.key))
      throw Error(ErrorKind::Internal, "page file: chunks not sorted by (level, key)");
    if (h.layout == Layout::Bricks &&
        c.bytes.size() != bricksPayloadBytes(h.chunkVoxels(), c.occupied, c.full, h.flags))
      throw Error(ErrorKind::Internal, "page file: chunk payload size mismatch");
    if (c.bytes.size() > 0xFFFFFFFFu || c.occupied == 0 || c.full != (c.occupied == h.chunkVoxels()))
      throw Error(ErrorKind::Internal, "page file: bad chunk (empty, full bit or size)");
    at = alignUp(at, align);
    entries[i] = {c.level, uint8_t(c.full ? kChunkFull : 0), c.occupied, c.key, at, uint32_t(c.bytes.size()),
                  crc32c(c.bytes.data(), c.bytes.size())};
    at += c.bytes.size();
  }
  h.fileBytes = chunks.empty() ? h.payloadOffset : at;
  std::vector<uint8_t> out(h.fileBytes, 0);
  for (size_t i = 0; i < entries.size(); ++i) {
    encodeEntry(entries[i], out.data() + h.indexOffset + kIndexEntryBytes * i);
    if (!chunks[i].bytes.empty()) std::memcpy(out.data() + entries[i].offset, chunks[i].bytes.data(), chunks[i].bytes.size());
  }
  std::memcpy(out.data() + h.metaOffset, metaJson.data(), metaJson.size());
  h.indexCrc = crc32c(out.data() + h.indexOffset, kIndexEntryBytes * h.chunkCount);
  h.metaCrc = crc32c(metaJson.data(), metaJson.size());
  encodeHeader(h, out.data());
  return out;
}

// ------------------------------------------------------------------ Reader

Reader::Reader(Reader&& o) noexcept
    : name_(std::move(o.name_)), data_(o.data_), size_(o.size_), map_(o.map_), mapSize_(o.mapSize_),
      header_(o.header_), entries_(std::move(o.entries_)), meta_(std::move(o.meta_)) {
  o.map_ = nullptr;
  o.mapSize_ = 0;
}

Reader::~Reader() {
  if (map_) munmap(map_, mapSize_);
}

Reader Reader::open(const std::string& path) {
  Reader r;
  r.name_ = path;
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throwBadInput(path + ": cannot open the page file (missing or unreadable)");
  struct stat st {};
  if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throwBadInput(path + ": not a regular file");
  }
  r.size_ = size_t(st.st_size);
  if (r.size_ > 0) {
    void* m = mmap(nullptr, r.size_, PROT_READ, MAP_PRIVATE, fd, 0);
    if (m == MAP_FAILED) {
      ::close(fd);
      throwIo(path + ": cannot map the page file into memory");
    }
    r.map_ = m;
    r.mapSize_ = r.size_;
    r.data_ = static_cast<const uint8_t*>(m);
  }
  ::close(fd);
  r.parse();
  return r;
}

Reader Reader::fromMemory(const uint8_t* data, size_t size, const std::string& name) {
  Reader r;
  r.name_ = name;
  r.data_ = data;
  r.size_ = size;
  r.parse();
  return r;
}

std::string Reader::describe(size_t i) const {
  const IndexEntry& e = entries_[i];
  const auto c = e.chunk();
  return "chunk " + std::to_string(i) + " (level " + std::to_string(e.level) + ", chunk (" + std::to_string(c[0]) +
         ", " + std::to_string(c[1]) + ", " + std::to_string(c[2]) + "))";
}

void Reader::parse() {
  auto fail = [&](const std::string& what) { throwBadInput(name_ + ": " + what); };
  if (size_ < kHeaderBytes)
    fail("header: the file has " + std::to_string(size_) + " bytes, a page file header needs " +
         std::to_string(kHeaderBytes) + " (truncated, or not a page file)");
  const uint8_t* p = data_;
  if (std::memcmp(p, kMagic, 8) != 0) fail("header field 'magic': not a voxbake page file (expected VOXPAGES)");
  const uint32_t headerCrc = crc32c(p, 124);
  if (crcDiffers(load<uint32_t>(p + 124), headerCrc))
    fail("header field 'header_crc32c': stored " + hex(load<uint32_t>(p + 124)) + ", computed " + hex(headerCrc) +
         " (the header is corrupt)");
  const uint16_t version = load<uint16_t>(p + 8);
  if (version != kVersion)
    fail("header field 'version': " + std::to_string(version) + "; this vox reads version " + std::to_string(kVersion) +
         (version > kVersion ? " (upgrade vox)" : ""));
  if (load<uint16_t>(p + 10) != kHeaderBytes) fail("header field 'header_bytes': expected 128");
  Header& h = header_;
  const uint8_t layout = p[12];
  if (layout < 1 || layout > 3) fail("header field 'layout': " + std::to_string(layout) + ", expected 1..3");
  h.layout = Layout(layout);
  h.chunkLog2 = p[13];
  if (h.chunkLog2 < 3 || h.chunkLog2 > 5) fail("header field 'chunk_log2': " + std::to_string(h.chunkLog2) + ", expected 3..5");
  h.levelCount = p[14];
  h.alignLog2 = p[15];
  if (h.alignLog2 < 3 || h.alignLog2 > 16) fail("header field 'align_log2': " + std::to_string(h.alignLog2) + ", expected 3..16");
  h.flags = load<uint32_t>(p + 16);
  if (h.flags & ~kKnownFlags) fail("header field 'flags': unknown bits " + hex(h.flags & ~kKnownFlags));
  for (int k = 0; k < 3; ++k) {
    h.dims[size_t(k)] = load<uint32_t>(p + 20 + 4 * k);
    if (h.dims[size_t(k)] < 1 || h.dims[size_t(k)] > (1u << 20))
      fail("header field 'dims': axis " + std::to_string(k) + " is " + std::to_string(h.dims[size_t(k)]) +
           ", expected 1..2^20");
  }
  uint32_t maxAxis = std::max({h.dims[0], h.dims[1], h.dims[2]});
  int maxLevels = 1;
  while (maxAxis > 1) maxAxis = (maxAxis + 1) / 2, ++maxLevels;
  if (h.levelCount < 1 || h.levelCount > maxLevels)
    fail("header field 'level_count': " + std::to_string(h.levelCount) + ", expected 1.." + std::to_string(maxLevels));
  h.voxelSize = load<double>(p + 32);
  if (!(h.voxelSize > 0) || !std::isfinite(h.voxelSize)) fail("header field 'voxel_size': must be finite and > 0");
  for (int k = 0; k < 3; ++k) {
    h.origin[size_t(k)] = load<double>(p + 40 + 8 * k);
    if (!std::isfinite(h.origin[size_t(k)])) fail("header field 'origin': must be finite");
  }
  h.chunkCount = load<uint64_t>(p + 64);
  h.indexOffset = load<uint64_t>(p + 72);
  h.metaOffset = load<uint64_t>(p + 80);
  h.metaBytes = load<uint64_t>(p + 88);
  h.payloadOffset = load<uint64_t>(p + 96);
  h.fileBytes = load<uint64_t>(p + 104);
  h.metaCrc = load<uint32_t>(p + 112);
  h.indexCrc = load<uint32_t>(p + 116);
  if (h.fileBytes != size_)
    fail("header field 'file_bytes': " + std::to_string(h.fileBytes) + ", but the file has " + std::to_string(size_) +
         " bytes (" + (size_ < h.fileBytes ? "truncated" : "trailing bytes") + ")");
  if (h.indexOffset != kHeaderBytes) fail("header field 'index_offset': expected 128");
  if (h.chunkCount > (size_ - kHeaderBytes) / kIndexEntryBytes)
    fail("header field 'chunk_count': " + std::to_string(h.chunkCount) + " entries do not fit in the file");
  const uint64_t indexEnd = h.indexOffset + h.chunkCount * kIndexEntryBytes;
  if (h.metaOffset != indexEnd) fail("header field 'meta_offset': expected the end of the index, " + std::to_string(indexEnd));
  if (h.metaBytes > size_ - h.metaOffset) fail("header field 'meta_bytes': runs past the end of the file");
  const uint64_t align = uint64_t(1) << h.alignLog2;
  if (h.payloadOffset != ((h.metaOffset + h.metaBytes + align - 1) & ~(align - 1)) || h.payloadOffset > size_)
    fail("header field 'payload_offset': expected the aligned end of the metadata");
  const uint32_t indexCrc = crc32c(p + h.indexOffset, h.chunkCount * kIndexEntryBytes);
  if (crcDiffers(h.indexCrc, indexCrc))
    fail("index: field 'index_crc32c': stored " + hex(h.indexCrc) + ", computed " + hex(indexCrc) + " (the index is corrupt)");
  const uint32_t metaCrc = crc32c(p + h.metaOffset, h.metaBytes);
  if (crcDiffers(h.metaCrc, metaCrc))
    fail("metadata: field 'meta_crc32c': stored " + hex(h.metaCrc) + ", computed " + hex(metaCrc));
  meta_.assign(reinterpret_cast<const char*>(p + h.metaOffset), h.metaBytes);

  entries_.resize(h.chunkCount);
  uint64_t prevEnd = h.payloadOffset;
  for (size_t i = 0; i < entries_.size(); ++i) {
    const uint8_t* q = p + h.indexOffset + i * kIndexEntryBytes;
    IndexEntry& e = entries_[i];
    e.level = q[0];
    e.flags = q[1];
    e.occupied = load<uint32_t>(q + 4);
    e.key = load<uint64_t>(q + 8);
    e.offset = load<uint64_t>(q + 16);
    e.size = load<uint32_t>(q + 24);
    e.crc = load<uint32_t>(q + 28);
    const std::string where = "index entry " + std::to_string(i);
    if (e.level >= h.levelCount)
      fail(where + ": field 'level': " + std::to_string(e.level) + " >= level_count " + std::to_string(h.levelCount));
    if (e.flags & ~kChunkFull) fail(where + ": field 'flags': unknown bits");
    if (load<uint16_t>(q + 2) != 0) fail(where + ": field 'reserved': must be 0");
    if (e.key >> 63) fail(where + ": field 'key': bit 63 set");
    const auto c = e.chunk();
    const auto lc = h.levelChunks(e.level);
    if (c[0] >= lc[0] || c[1] >= lc[1] || c[2] >= lc[2]) fail(describe(i) + ": field 'key': chunk outside the level's grid");
    if (i > 0 && std::make_pair(entries_[i - 1].level, entries_[i - 1].key) >= std::make_pair(e.level, e.key))
      fail(describe(i) + ": field 'key': index not sorted by (level, key)");
    if (e.occupied < 1 || e.occupied > h.chunkVoxels())
      fail(describe(i) + ": field 'occupied': " + std::to_string(e.occupied) + ", expected 1.." + std::to_string(h.chunkVoxels()));
    if (bool(e.flags & kChunkFull) != (e.occupied == h.chunkVoxels()))
      fail(describe(i) + ": field 'flags': the full bit must be set exactly when every voxel is occupied");
    if (e.offset % align != 0) fail(describe(i) + ": field 'offset': not a multiple of the alignment " + std::to_string(align));
    if (e.offset < prevEnd) fail(describe(i) + ": field 'offset': overlaps the previous payload or the metadata");
    if (e.size > size_ || e.offset > size_ - e.size) fail(describe(i) + ": field 'size': the payload runs past the end of the file");
    if (h.layout == Layout::Svo && e.size < kSvoFixedBytes)
      fail(describe(i) + ": field 'size': " + std::to_string(e.size) + " bytes, an svo payload has at least " +
           std::to_string(kSvoFixedBytes));
    if (h.layout == Layout::Columns && e.size < kColumnsFixedBytes)
      fail(describe(i) + ": field 'size': " + std::to_string(e.size) + " bytes, a columns payload has at least " +
           std::to_string(kColumnsFixedBytes));
    if (h.layout == Layout::Bricks && e.size != bricksPayloadBytes(h.chunkVoxels(), e.occupied, e.flags & kChunkFull, h.flags))
      fail(describe(i) + ": field 'size': " + std::to_string(e.size) + " bytes, the bricks layout needs " +
           std::to_string(bricksPayloadBytes(h.chunkVoxels(), e.occupied, e.flags & kChunkFull, h.flags)));
    prevEnd = e.offset + e.size;
  }
  if (!entries_.empty() && prevEnd != size_) fail("header field 'file_bytes': the last payload does not end the file");
}

const IndexEntry* Reader::find(int level, uint32_t x, uint32_t y, uint32_t z) const {
  if (level < 0 || level > 255 || x > kMortonAxisMax || y > kMortonAxisMax || z > kMortonAxisMax) return nullptr;
  const auto want = std::make_pair(uint8_t(level), mortonEncode(x, y, z));
  auto it = std::lower_bound(entries_.begin(), entries_.end(), want, [](const IndexEntry& e, const auto& w) {
    return std::make_pair(e.level, e.key) < w;
  });
  if (it == entries_.end() || it->level != want.first || it->key != want.second) return nullptr;
  return &*it;
}

std::pair<size_t, size_t> Reader::levelRange(int level) const {
  auto lo = std::lower_bound(entries_.begin(), entries_.end(), level, [](const IndexEntry& e, int l) { return e.level < l; });
  auto hi = std::lower_bound(lo, entries_.end(), level + 1, [](const IndexEntry& e, int l) { return e.level < l; });
  return {size_t(lo - entries_.begin()), size_t(hi - entries_.begin())};
}

std::span<const uint8_t> Reader::payload(size_t i) const {
  const IndexEntry& e = entries_.at(i);
  const uint8_t* p = data_ + e.offset;  // bounds checked in parse()
  const uint32_t crc = crc32c(p, e.size);
  if (crcDiffers(e.crc, crc))
    throwBadInput(name_ + ": " + describe(i) + ": field 'crc32c': stored " + hex(e.crc) + ", payload has " + hex(crc) +
                  " (the payload is corrupt)");
  return {p, e.size};
}

std::vector<DecodedVoxel> Reader::decode(size_t i) const {
  switch (header_.layout) {
    case Layout::Svo: return decodeSvo(i, nullptr);
    case Layout::Columns: return decodeColumns(i);
    case Layout::Bricks: break;
  }
  return decodeBricks(i);
}

std::vector<SvoBrick> Reader::svoBricks(size_t i) const {
  if (header_.layout != Layout::Svo)
    throwBadInput(name_ + ": svoBricks: the file has the " + std::string(layoutName(header_.layout)) + " layout, not svo");
  std::vector<SvoBrick> bricks;
  decodeSvo(i, &bricks);
  return bricks;
}

std::vector<DecodedVoxel> Reader::decodeBricks(size_t i) const {
  const Header& h = header_;
  const IndexEntry& e = entries_.at(i);
  const std::span<const uint8_t> bytes = payload(i);
  auto fail = [&](const std::string& what) { throwBadInput(name_ + ": " + describe(i) + ": " + what); };
  const uint32_t C = h.chunkSide(), N = h.chunkVoxels();
  const bool full = e.flags & kChunkFull;
  const uint8_t* p = bytes.data();
  std::vector<DecodedVoxel> out;
  out.reserve(e.occupied);
  // Which voxels of this chunk lie inside the level's domain.
  const auto ld = h.levelDims(e.level);
  const auto c = e.chunk();
  const uint32_t limX = std::min(C, ld[0] - c[0] * C), limY = std::min(C, ld[1] - c[1] * C),
                 limZ = std::min(C, ld[2] - c[2] * C);
  if (full) {
    if (limX != C || limY != C || limZ != C) fail("field 'flags': a full chunk that crosses the edge of the domain");
    for (uint32_t k = 0; k < N; ++k) out.push_back({k, {}, true, {}});
  } else {
    uint64_t count = 0;
    for (uint32_t w = 0; w < N / 64; ++w) {
      uint64_t word = load<uint64_t>(p + 8 * w);
      count += uint64_t(std::popcount(word));
      while (word) {
        const uint32_t k = w * 64 + uint32_t(std::countr_zero(word));
        word &= word - 1;
        const uint32_t x = k & (C - 1), y = (k >> h.chunkLog2) & (C - 1), z = k >> (2 * h.chunkLog2);
        if (x >= limX || y >= limY || z >= limZ)
          fail("field 'bitmap': voxel (" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z) +
               ") of the chunk lies outside the level's dims");
        out.push_back({k, {}, true, {}});
      }
    }
    if (count != e.occupied)
      fail("field 'bitmap': " + std::to_string(count) + " bits set, the index says " + std::to_string(e.occupied) +
           " occupied voxels");
    p += N / 8;
  }
  for (DecodedVoxel& v : out) {
    std::memcpy(v.summary.data(), p, 4);
    p += 4;
    if (v.summary[0] == 0) fail("field 'summary': voxel " + std::to_string(v.index) + " is occupied but has class 0");
  }
  if (h.flags & kFlagColor)
    for (DecodedVoxel& v : out) {
      std::memcpy(v.color.data(), p, 4);
      p += 4;
      if (v.color[3] != 0 && v.color[3] != 255) fail("field 'color': alpha must be 0 or 255");
      if (v.color[3] == 0 && (v.color[0] | v.color[1] | v.color[2])) fail("field 'color': an uncoloured voxel must be 0,0,0,0");
    }
  if (h.flags & kFlagSurface) {
    for (size_t k = 0; k < out.size(); ++k) out[k].surface = (p[k / 8] >> (k % 8)) & 1;
    const size_t rest = out.size() % 8;
    if (rest && (p[out.size() / 8] >> rest)) fail("field 'surface': padding bits must be 0");
  }
  return out;
}

namespace {

// Chunk-local voxels inside the level's domain: [0, lim) per axis.
std::array<uint32_t, 3> chunkLimits(const Header& h, const IndexEntry& e) {
  const auto ld = h.levelDims(e.level);
  const auto c = e.chunk();
  const uint32_t C = h.chunkSide();
  return {std::min(C, ld[0] - c[0] * C), std::min(C, ld[1] - c[1] * C), std::min(C, ld[2] - c[2] * C)};
}

// Alpha 0 or 255, RGB 0 without colour.
const char* colorProblem(const std::array<uint8_t, 4>& c) {
  if (c[3] != 0 && c[3] != 255) return "alpha must be 0 or 255";
  if (c[3] == 0 && (c[0] | c[1] | c[2])) return "an uncoloured voxel must be 0,0,0,0";
  return nullptr;
}

bool bitOf(const uint8_t* bytes, uint64_t bit) { return (bytes[bit >> 3] >> (bit & 7)) & 1; }

}  // namespace

std::vector<DecodedVoxel> Reader::decodeSvo(size_t i, std::vector<SvoBrick>* bricksOut) const {
  const Header& h = header_;
  const IndexEntry& e = entries_.at(i);
  const std::span<const uint8_t> bytes = payload(i);
  auto fail = [&](const std::string& what) { throwBadInput(name_ + ": " + describe(i) + ": " + what); };
  const uint8_t* p = bytes.data();
  if (bytes.size() < kSvoFixedBytes) fail("field 'size': shorter than the svo payload's fixed part");
  const uint32_t C = h.chunkSide(), depth = h.chunkLog2 - 3u;
  const uint64_t B = load<uint32_t>(p), M = load<uint32_t>(p + 4), T = load<uint32_t>(p + 8);
  uint64_t maxNodes = 0;
  for (uint32_t d = 0; d <= depth; ++d) maxNodes += uint64_t(1) << (3 * d);
  if (B < 1 || B > maxNodes)
    fail("svo field 'node_count': " + std::to_string(B) + ", expected 1.." + std::to_string(maxNodes));
  if (M > B) fail("svo field 'bitmap_count': " + std::to_string(M) + " > node_count " + std::to_string(B));
  if (T < B || T > 512 * B)
    fail("svo field 'record_count': " + std::to_string(T) + ", expected node_count.." + std::to_string(512 * B));
  if (load<uint32_t>(p + 12) != 0) fail("svo field 'reserved': must be 0");
  const uint64_t want = svoPayloadBytes(B, M, T, h.flags);
  if (bytes.size() != want)
    fail("field 'size': " + std::to_string(bytes.size()) + " bytes, the svo counts (node_count " + std::to_string(B) +
         ", bitmap_count " + std::to_string(M) + ", record_count " + std::to_string(T) + ") need " + std::to_string(want));
  const uint8_t* nodeP = p + kSvoFixedBytes;
  const uint8_t* brickP = nodeP + 8 * B;
  const uint8_t* bitmapP = brickP + 8 * B;
  const uint8_t* sumP = bitmapP + 64 * M;
  const uint8_t* colP = sumP + 4 * T;
  const uint8_t* surfP = colP + ((h.flags & kFlagColor) ? 4 * T : 0);
  const bool color = h.flags & kFlagColor, surfaceCh = h.flags & kFlagSurface;
  const auto lim = chunkLimits(h, e);

  struct N {
    uint32_t level = 0;
    std::array<uint32_t, 3> origin{};
    uint8_t mask = 0, flags = 0;
    uint32_t ptr = 0, first = 0, count = 0;
    std::array<uint64_t, 8> bits{};
  };
  std::vector<N> nodes(B);
  nodes[0].level = depth;
  uint64_t next = 1, slot = 0, records = 0, leafVoxels = 0;
  for (uint64_t n = 0; n < B; ++n) {
    N& nd = nodes[n];
    const std::string where = "svo node " + std::to_string(n) + ": field ";
    if (n >= next) fail(where + "'child_ptr': the node is not a child of any earlier node (unreachable)");
    const uint64_t raw = load<uint64_t>(nodeP + 8 * n);
    nd.mask = uint8_t(raw);
    nd.flags = uint8_t(raw >> 8);
    nd.ptr = uint32_t(raw >> 32);
    if (uint8_t(raw >> 16) != 0) fail(where + "'reserved': must be 0");
    if (uint8_t(raw >> 24) != nd.level)
      fail(where + "'level': " + std::to_string(uint8_t(raw >> 24)) + ", expected " + std::to_string(nd.level));
    if (nd.flags & ~(kSvoNodeFull | kSvoNodeColor)) fail(where + "'flags': unknown bits");
    if (nd.level > 0) {
      if (nd.ptr != next)
        fail(where + "'child_ptr': " + std::to_string(nd.ptr) + ", expected " + std::to_string(next) +
             " (children follow breadth first)");
      const uint32_t half = 8u << (nd.level - 1);
      for (uint32_t oct = 0; oct < 8; ++oct) {
        if (!(nd.mask >> oct & 1)) continue;
        if (next >= B) fail(where + "'child_mask': children past node_count " + std::to_string(B));
        N& c = nodes[next++];
        c.level = nd.level - 1;
        c.origin = {nd.origin[0] + half * (oct & 1), nd.origin[1] + half * ((oct >> 1) & 1), nd.origin[2] + half * (oct >> 2)};
      }
    } else if (nd.ptr != n) {
      fail(where + "'child_ptr': a leaf must point at its own brick " + std::to_string(n));
    }
    // The brick table entry and the bitmap.
    const std::string bwhere = "svo brick " + std::to_string(n) + ": field ";
    nd.first = load<uint32_t>(brickP + 8 * n);
    const uint32_t bslot = load<uint32_t>(brickP + 8 * n + 4);
    if (nd.first != records)
      fail(bwhere + "'first': " + std::to_string(nd.first) + ", expected " + std::to_string(records));
    const bool full = nd.flags & kSvoNodeFull;
    if (full != (bslot == kSvoNoBitmap))
      fail(bwhere + "'bitmap': the node's full flag and the bitmap slot disagree");
    if (full) {
      nd.bits.fill(~uint64_t(0));
    } else {
      if (bslot != slot || slot >= M)
        fail(bwhere + "'bitmap': slot " + std::to_string(bslot) + ", expected " + std::to_string(slot) +
             " (bitmaps are stored in brick order, bitmap_count " + std::to_string(M) + ")");
      for (int w = 0; w < 8; ++w) nd.bits[size_t(w)] = load<uint64_t>(bitmapP + 64 * slot + 8 * w);
      ++slot;
    }
    uint32_t count = 0;
    uint8_t octants = 0;
    const uint32_t step = 1u << nd.level;
    for (uint32_t w = 0; w < 8; ++w) {
      count += uint32_t(std::popcount(nd.bits[w]));
      for (uint64_t word = nd.bits[w]; word; word &= word - 1) {
        const uint32_t b = w * 64 + uint32_t(std::countr_zero(word));
        const uint32_t bx = b & 7, by = (b >> 3) & 7, bz = b >> 6;
        octants |= uint8_t(1u << ((bx >> 2) | ((by >> 2) << 1) | ((bz >> 2) << 2)));
        if (nd.origin[0] + bx * step >= lim[0] || nd.origin[1] + by * step >= lim[1] || nd.origin[2] + bz * step >= lim[2])
          fail(bwhere + "'bitmap': voxel (" + std::to_string(bx) + ", " + std::to_string(by) + ", " + std::to_string(bz) +
               ") of the brick lies outside the level's dims");
      }
    }
    if (count == 0) fail(bwhere + "'bitmap': an empty brick");
    if (!full && count == 512) fail(bwhere + "'bitmap': all 512 bits set, but the node is not flagged full");
    if (nd.mask != octants)
      fail(where + "'child_mask': " + std::to_string(nd.mask) + ", the brick's occupied octants are " + std::to_string(octants));
    nd.count = count;
    if (records + count > T)
      fail(bwhere + "'bitmap': the bricks hold more voxels than record_count " + std::to_string(T));
    bool anyColor = false;
    for (uint64_t r = records; r < records + count; ++r) {
      if (sumP[4 * r] == 0) fail("field 'summary': record " + std::to_string(r) + " (svo brick " + std::to_string(n) + ") has class 0");
      if (color) {
        const std::array<uint8_t, 4> c{colP[4 * r], colP[4 * r + 1], colP[4 * r + 2], colP[4 * r + 3]};
        if (const char* why = colorProblem(c)) fail(std::string("field 'color': record ") + std::to_string(r) + ": " + why);
        anyColor |= c[3] == 255;
      }
    }
    if (anyColor != bool(nd.flags & kSvoNodeColor))
      fail(where + "'flags': the colour bit does not match the brick's colours");
    records += count;
    if (nd.level == 0) leafVoxels += count;
  }
  if (next != B) fail("svo field 'node_count': " + std::to_string(B) + ", the tree has " + std::to_string(next) + " nodes");
  if (slot != M) fail("svo field 'bitmap_count': " + std::to_string(M) + ", the bricks store " + std::to_string(slot));
  if (records != T) fail("svo field 'record_count': " + std::to_string(T) + ", the bricks hold " + std::to_string(records));
  if (leafVoxels != e.occupied)
    fail("field 'occupied': the index says " + std::to_string(e.occupied) + ", the leaf bricks hold " + std::to_string(leafVoxels));
  if (surfaceCh && T % 8 && (surfP[T / 8] >> (T % 8))) fail("field 'surface': padding bits must be 0");

  // Record r of brick n: the rank of brick voxel b among the brick's bits.
  auto recordOf = [&](const N& nd, uint32_t b) {
    uint32_t r = 0;
    for (uint32_t w = 0; w < b / 64; ++w) r += uint32_t(std::popcount(nd.bits[w]));
    return nd.first + r + uint32_t(std::popcount(nd.bits[b / 64] & ((uint64_t(1) << (b % 64)) - 1)));
  };
  auto has = [](const N& nd, uint32_t b) { return (nd.bits[b >> 6] >> (b & 63)) & 1; };
  // Mip bricks: a voxel is occupied exactly when one of its 8 children is; its
  // surface bit is their OR; it has a colour exactly when one of them has.
  for (uint64_t n = 0; n < B; ++n) {
    const N& nd = nodes[n];
    if (nd.level == 0) continue;
    std::array<const N*, 8> kids{};
    for (uint32_t oct = 0, c = nd.ptr; oct < 8; ++oct)
      if (nd.mask >> oct & 1) kids[oct] = &nodes[c++];
    for (uint32_t b = 0; b < 512; ++b) {
      const uint32_t bx = b & 7, by = (b >> 3) & 7, bz = b >> 6;
      const N* kid = kids[(bx >> 2) | ((by >> 2) << 1) | ((bz >> 2) << 2)];
      bool any = false, surf = false, col = false;
      if (kid)
        for (uint32_t d = 0; d < 8; ++d) {
          const uint32_t cb = (2 * (bx & 3) + (d & 1)) + 8 * ((2 * (by & 3) + ((d >> 1) & 1)) + 8 * (2 * (bz & 3) + (d >> 2)));
          if (!has(*kid, cb)) continue;
          any = true;
          const uint32_t r = recordOf(*kid, cb);
          if (surfaceCh) surf |= bitOf(surfP, r);
          if (color) col |= colP[4ull * r + 3] == 255;
        }
      const std::string where = "svo brick " + std::to_string(n) + " (mip, level " + std::to_string(nd.level) + "): ";
      if (bool(has(nd, b)) != any)
        fail(where + "field 'bitmap': voxel " + std::to_string(b) + " disagrees with the children's occupancy");
      if (!any) continue;
      const uint32_t r = recordOf(nd, b);
      if (surfaceCh && bitOf(surfP, r) != surf) fail(where + "field 'surface': voxel " + std::to_string(b) + " is not the OR of its children");
      if (color && (colP[4ull * r + 3] == 255) != col)
        fail(where + "field 'color': voxel " + std::to_string(b) + " has a colour exactly when a child has one");
    }
  }

  auto voxelOf = [&](uint32_t index, uint64_t r) {
    DecodedVoxel v;
    v.index = index;
    std::memcpy(v.summary.data(), sumP + 4 * r, 4);
    if (color) std::memcpy(v.color.data(), colP + 4 * r, 4);
    v.surface = surfaceCh ? bitOf(surfP, r) : true;
    return v;
  };
  std::vector<DecodedVoxel> out;
  out.reserve(e.occupied);
  if (bricksOut) bricksOut->clear();
  for (uint64_t n = 0; n < B; ++n) {
    const N& nd = nodes[n];
    SvoBrick* sb = nullptr;
    if (bricksOut) {
      bricksOut->push_back({uint32_t(n), uint8_t(nd.level), nd.mask, nd.flags, nd.ptr, nd.origin, {}});
      sb = &bricksOut->back();
      sb->voxels.reserve(nd.count);
    }
    uint64_t r = nd.first;
    for (uint32_t w = 0; w < 8; ++w)
      for (uint64_t word = nd.bits[w]; word; word &= word - 1, ++r) {
        const uint32_t b = w * 64 + uint32_t(std::countr_zero(word));
        if (sb) sb->voxels.push_back(voxelOf(b, r));
        if (nd.level == 0) {
          const uint32_t x = nd.origin[0] + (b & 7), y = nd.origin[1] + ((b >> 3) & 7), z = nd.origin[2] + (b >> 6);
          out.push_back(voxelOf(x + C * (y + C * z), r));
        }
      }
  }
  std::sort(out.begin(), out.end(), [](const DecodedVoxel& a, const DecodedVoxel& b) { return a.index < b.index; });
  return out;
}

std::vector<DecodedVoxel> Reader::decodeColumns(size_t i) const {
  const Header& h = header_;
  const IndexEntry& e = entries_.at(i);
  const std::span<const uint8_t> bytes = payload(i);
  auto fail = [&](const std::string& what) { throwBadInput(name_ + ": " + describe(i) + ": " + what); };
  const uint8_t* p = bytes.data();
  if (bytes.size() < kColumnsFixedBytes) fail("field 'size': shorter than the columns payload's fixed part");
  const uint32_t C = h.chunkSide(), N = h.chunkVoxels(), log2C = h.chunkLog2;
  const bool full = e.flags & kChunkFull, color = h.flags & kFlagColor, surfaceCh = h.flags & kFlagSurface;
  const uint32_t n = e.occupied, S = load<uint32_t>(p);
  if (S > n || (!surfaceCh && S != n))
    fail("columns field 'surface_count': " + std::to_string(S) + ", expected " +
         (surfaceCh ? "0.." + std::to_string(n) : std::to_string(n) + " (no surface channel: every voxel is a surface voxel)"));
  if (load<uint32_t>(p + 4) != 0) fail("columns field 'reserved': must be 0");
  const uint64_t want = columnsPayloadBytes(C, n, S, full, h.flags);
  if (bytes.size() != want)
    fail("field 'size': " + std::to_string(bytes.size()) + " bytes, the columns layout needs " + std::to_string(want) +
         " (occupied " + std::to_string(n) + ", surface_count " + std::to_string(S) + ")");
  const auto lim = chunkLimits(h, e);
  p += kColumnsFixedBytes;
  // Solid mask (all ones when full).
  std::vector<uint8_t> ones;
  const uint8_t* solid = p;
  if (full) {
    if (lim[0] != C || lim[1] != C || lim[2] != C) fail("field 'flags': a full chunk that crosses the edge of the domain");
    ones.assign(N / 8, 0xFF);
    solid = ones.data();
  } else {
    p += N / 8;
  }
  const uint8_t* surface = surfaceCh ? p : solid;
  if (surfaceCh) p += N / 8;
  uint64_t solidCount = 0, surfCount = 0;
  for (uint32_t w = 0; w < N / 32; ++w) {
    const uint32_t sw = load<uint32_t>(solid + 4 * w), fw = load<uint32_t>(surface + 4 * w);
    solidCount += uint32_t(std::popcount(sw));
    surfCount += uint32_t(std::popcount(fw));
    if (fw & ~sw) fail("columns field 'surface_mask': word " + std::to_string(w) + " has a voxel that is not in the solid mask");
    for (uint32_t word = sw; word; word &= word - 1) {
      const uint32_t bit = w * 32 + uint32_t(std::countr_zero(word));
      const uint32_t z = bit & (C - 1), x = (bit >> log2C) & (C - 1), y = bit >> (2 * log2C);
      if (x >= lim[0] || y >= lim[1] || z >= lim[2])
        fail("columns field 'solid_mask': voxel (" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z) +
             ") of the chunk lies outside the level's dims");
    }
  }
  if (solidCount != n)
    fail("columns field 'solid_mask': " + std::to_string(solidCount) + " bits set, the index says " + std::to_string(n) +
         " occupied voxels");
  if (surfCount != S)
    fail("columns field 'surface_mask': " + std::to_string(surfCount) + " bits set, surface_count says " + std::to_string(S));
  // The mip ladder, recomputed from the solid mask.
  if (!full) {
    std::vector<uint8_t> expect;
    for (uint32_t m = 1; m < log2C; ++m) {
      const uint32_t s = C >> m, words = columnsLadderWordCount(s);
      expect.assign(4ull * words, 0);
      for (uint32_t w = 0; w < N / 32; ++w)
        for (uint32_t word = load<uint32_t>(solid + 4 * w); word; word &= word - 1) {
          const uint32_t bit = w * 32 + uint32_t(std::countr_zero(word));
          const uint32_t z = (bit & (C - 1)) >> m, x = ((bit >> log2C) & (C - 1)) >> m, y = (bit >> (2 * log2C)) >> m;
          const uint32_t b = z + s * (x + s * y);
          expect[b >> 3] |= uint8_t(1u << (b & 7));
        }
      if (std::memcmp(expect.data(), p, expect.size()) != 0)
        fail("columns field 'ladder': level " + std::to_string(m) + " (" + std::to_string(s) + "^3) does not match the solid mask");
      p += expect.size();
    }
  }
  const uint8_t* sum = p;
  const uint8_t* offsets = sum + 4ull * n;
  const uint8_t* colors = offsets + 4ull * (C * C + 1);
  std::vector<DecodedVoxel> out;
  out.reserve(n);
  uint32_t rank = 0, colorRank = 0;
  for (uint32_t col = 0; col < C * C; ++col) {
    if (color && load<uint32_t>(offsets + 4ull * col) != colorRank)
      fail("columns field 'color_offsets': column " + std::to_string(col) + " says " +
           std::to_string(load<uint32_t>(offsets + 4ull * col)) + ", the surface mask gives " + std::to_string(colorRank));
    for (uint32_t z = 0; z < C; ++z) {
      const uint32_t bit = z + C * col;
      if (!bitOf(solid, bit)) continue;
      const uint32_t x = col & (C - 1), y = col >> log2C;
      DecodedVoxel v;
      v.index = x + C * (y + C * z);
      std::memcpy(v.summary.data(), sum + 4ull * rank, 4);
      if (v.summary[0] == 0) fail("field 'summary': voxel " + std::to_string(v.index) + " is occupied but has class 0");
      ++rank;
      v.surface = bitOf(surface, bit);
      if (color && v.surface) {
        std::memcpy(v.color.data(), colors + 4ull * colorRank, 4);
        if (const char* why = colorProblem(v.color)) fail(std::string("field 'color': colour ") + std::to_string(colorRank) + ": " + why);
        ++colorRank;
      }
      out.push_back(v);
    }
  }
  if (color && load<uint32_t>(offsets + 4ull * C * C) != S)
    fail("columns field 'color_offsets': the sentinel must be surface_count " + std::to_string(S));
  std::sort(out.begin(), out.end(), [](const DecodedVoxel& a, const DecodedVoxel& b) { return a.index < b.index; });
  return out;
}

uint64_t Reader::verify() const {
  uint64_t voxels = 0;
  for (size_t i = 0; i < entries_.size(); ++i) voxels += decode(i).size();
  return voxels;
}

}  // namespace vox::pagefile
