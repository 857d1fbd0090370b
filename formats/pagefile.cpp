#include "formats/pagefile.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "libvox/crc32c.h"
#include "libvox/error.h"
#include "libvox/morton.h"

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
  const Header& h = header_;
  const IndexEntry& e = entries_.at(i);
  if (h.layout != Layout::Bricks)
    throwBadInput(name_ + ": " + describe(i) + ": decoding the " + layoutName(h.layout) + " layout is not supported");
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

uint64_t Reader::verify() const {
  uint64_t voxels = 0;
  for (size_t i = 0; i < entries_.size(); ++i) {
    if (header_.layout == Layout::Bricks)
      voxels += decode(i).size();
    else {
      payload(i);
      voxels += entries_[i].occupied;
    }
  }
  return voxels;
}

}  // namespace vox::pagefile
