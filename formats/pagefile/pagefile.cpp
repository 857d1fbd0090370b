#include "formats/pagefile/pagefile.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <bit>
#include <cmath>
#include <cstring>

#include "formats/core/file_util.h"
#include "libvox/core/crc32c.h"
#include "libvox/core/error.h"
#include "libvox/core/morton.h"
#include "formats/pagefile/layout_io.h"

namespace vox::pagefile {

namespace {

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

namespace hf = header_field;
namespace ef = entry_field;

void encodeHeader(const Header& h, uint8_t* p) {
  std::memset(p, 0, kHeaderBytes);
  std::memcpy(p + hf::kMagic, kMagic, sizeof kMagic);
  storeLE<uint16_t>(p + hf::kVersion, kVersion);
  storeLE<uint16_t>(p + hf::kHeaderBytes, uint16_t(kHeaderBytes));
  p[hf::kLayout] = uint8_t(h.layout);
  p[hf::kChunkLog2] = h.chunkLog2;
  p[hf::kLevelCount] = h.levelCount;
  p[hf::kAlignLog2] = h.alignLog2;
  storeLE<uint32_t>(p + hf::kFlags, h.flags);
  for (size_t k = 0; k < 3; ++k) storeLE<uint32_t>(p + hf::kDims + 4 * k, h.dims[k]);
  storeLE<double>(p + hf::kVoxelSize, h.voxelSize);
  for (size_t k = 0; k < 3; ++k) storeLE<double>(p + hf::kOrigin + 8 * k, h.origin[k]);
  storeLE<uint64_t>(p + hf::kChunkCount, h.chunkCount);
  storeLE<uint64_t>(p + hf::kIndexOffset, h.indexOffset);
  storeLE<uint64_t>(p + hf::kMetaOffset, h.metaOffset);
  storeLE<uint64_t>(p + hf::kMetaBytes, h.metaBytes);
  storeLE<uint64_t>(p + hf::kPayloadOffset, h.payloadOffset);
  storeLE<uint64_t>(p + hf::kFileBytes, h.fileBytes);
  storeLE<uint32_t>(p + hf::kMetaCrc, h.metaCrc);
  storeLE<uint32_t>(p + hf::kIndexCrc, h.indexCrc);
  storeLE<uint32_t>(p + hf::kHeaderCrc, crc32c(p, hf::kHeaderCrc));
}

void encodeEntry(const IndexEntry& e, uint8_t* p) {
  std::memset(p, 0, kIndexEntryBytes);
  p[ef::kLevel] = e.level;
  p[ef::kFlags] = e.flags;
  storeLE<uint32_t>(p + ef::kOccupied, e.occupied);
  storeLE<uint64_t>(p + ef::kKey, e.key);
  storeLE<uint64_t>(p + ef::kOffset, e.offset);
  storeLE<uint32_t>(p + ef::kSize, e.size);
  storeLE<uint32_t>(p + ef::kCrc, e.crc);
}

std::string hex(uint32_t v) {
  char b[16];
  std::snprintf(b, sizeof b, "0x%08x", v);
  return b;
}

}  // namespace

bool looksLikePageFile(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return false;  // never block on a FIFO
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

uint8_t chooseAlignLog2(std::span<const ChunkSlot> chunks) {
  uint64_t page = 0, compact = 0;
  for (const ChunkSlot& c : chunks) {
    page += alignUp(c.size, uint64_t(1) << kAutoAlignPageLog2);
    compact += alignUp(c.size, uint64_t(1) << kAutoAlignCompactLog2);
  }
  return page <= compact + compact / 8 ? kAutoAlignPageLog2 : kAutoAlignCompactLog2;
}

FilePlan planFile(Header h, const std::string& metaJson, std::span<const ChunkSlot> chunks) {
  if (h.alignLog2 == kAlignAuto) h.alignLog2 = chooseAlignLog2(chunks);
  const uint64_t align = uint64_t(1) << h.alignLog2;
  const LayoutCodec& codec = codecOf(h.layout);
  h.chunkCount = chunks.size();
  h.indexOffset = kHeaderBytes;
  h.metaOffset = h.indexOffset + kIndexEntryBytes * h.chunkCount;
  h.metaBytes = metaJson.size();
  h.payloadOffset = alignUp(h.metaOffset + h.metaBytes, align);
  FilePlan plan;
  plan.entries.resize(chunks.size());
  uint64_t at = h.payloadOffset;
  for (size_t i = 0; i < chunks.size(); ++i) {
    const ChunkSlot& c = chunks[i];
    if (i > 0 && std::make_pair(chunks[i - 1].level, chunks[i - 1].key) >= std::make_pair(c.level, c.key))
      throw Error(ErrorKind::Internal, "page file: chunks not sorted by (level, key)");
    const IndexEntry sizing{c.level, uint8_t(c.full ? kChunkFull : 0), c.occupied, c.key, 0, 0, 0};
    if (codec.sizeFromIndex && c.size != codec.sizeFromIndex(h, sizing))
      throw Error(ErrorKind::Internal, "page file: chunk payload size mismatch");
    if (c.size > 0xFFFFFFFFu || c.occupied == 0 || c.full != (c.occupied == h.chunkVoxels()))
      throw Error(ErrorKind::Internal, "page file: bad chunk (empty, full bit or size)");
    at = alignUp(at, align);
    plan.entries[i] = {c.level, uint8_t(c.full ? kChunkFull : 0), c.occupied, c.key, at, uint32_t(c.size), c.crc};
    at += c.size;
  }
  h.fileBytes = chunks.empty() ? h.payloadOffset : at;
  plan.prefix.assign(h.payloadOffset, 0);
  for (size_t i = 0; i < plan.entries.size(); ++i)
    encodeEntry(plan.entries[i], plan.prefix.data() + h.indexOffset + kIndexEntryBytes * i);
  std::memcpy(plan.prefix.data() + h.metaOffset, metaJson.data(), metaJson.size());
  h.indexCrc = crc32c(plan.prefix.data() + h.indexOffset, kIndexEntryBytes * h.chunkCount);
  h.metaCrc = crc32c(metaJson.data(), metaJson.size());
  encodeHeader(h, plan.prefix.data());
  plan.header = h;
  return plan;
}

FilePlan planChunks(Header h, const std::string& metaJson, const std::vector<ChunkBlob>& chunks) {
  std::vector<ChunkSlot> slots(chunks.size());
  for (size_t i = 0; i < chunks.size(); ++i) {
    const ChunkBlob& c = chunks[i];
    slots[i] = {c.level, c.key, c.occupied, c.full, c.bytes.size(), crc32c(c.bytes.data(), c.bytes.size())};
  }
  return planFile(h, metaJson, slots);
}

void writePlannedFile(const std::string& path, const FilePlan& plan, const std::vector<ChunkBlob>& chunks,
                      const std::string& nameForMessages) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) throwIo(nameForMessages + ": cannot create the file: " + std::strerror(errno));
  auto fail = [&](int err) {
    ::close(fd);
    throwIo(nameForMessages + ": cannot write the file: " + std::strerror(err));
  };
  auto put = [&](const uint8_t* p, size_t n, uint64_t at) {
    while (n > 0) {
      const ssize_t w = ::pwrite(fd, p, n, off_t(at));
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) fail(w < 0 ? errno : ENOSPC);
      p += w;
      n -= size_t(w);
      at += uint64_t(w);
    }
  };
  put(plan.prefix.data(), plan.prefix.size(), 0);
  for (size_t i = 0; i < chunks.size(); ++i) put(chunks[i].bytes.data(), chunks[i].bytes.size(), plan.entries[i].offset);
  if (::ftruncate(fd, off_t(plan.header.fileBytes)) != 0) fail(errno);  // the file's length, whatever was written
  if (::close(fd) != 0) throwIo(nameForMessages + ": cannot write the file: " + std::strerror(errno));
}

std::vector<uint8_t> serialize(Header h, const std::string& metaJson, const std::vector<ChunkBlob>& chunks) {
  const FilePlan plan = planChunks(h, metaJson, chunks);
  std::vector<uint8_t> out(plan.header.fileBytes, 0);
  std::memcpy(out.data(), plan.prefix.data(), plan.prefix.size());
  for (size_t i = 0; i < chunks.size(); ++i)
    if (!chunks[i].bytes.empty())
      std::memcpy(out.data() + plan.entries[i].offset, chunks[i].bytes.data(), chunks[i].bytes.size());
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
  requireRegularFile(path);
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throwBadInput(path + ": cannot open the page file: " + std::strerror(errno));
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
  parseHeader();
  parseIndex();
}

// The header's fields in range and consistent with the file's size; the index
// and the metadata inside the file with matching CRCs.
void Reader::parseHeader() {
  auto fail = [&](const std::string& what) { throwBadInput(name_ + ": " + what); };
  if (size_ < kHeaderBytes)
    fail("header: the file has " + std::to_string(size_) + " bytes, a page file header needs " +
         std::to_string(kHeaderBytes) + " (truncated, or not a page file)");
  const uint8_t* p = data_;
  if (std::memcmp(p + hf::kMagic, kMagic, sizeof kMagic) != 0)
    fail("header field 'magic': not a voxbake page file (expected VOXPAGES)");
  const uint32_t headerCrc = crc32c(p, hf::kHeaderCrc);
  if (crcDiffers(loadLE<uint32_t>(p + hf::kHeaderCrc), headerCrc))
    fail("header field 'header_crc32c': stored " + hex(loadLE<uint32_t>(p + hf::kHeaderCrc)) + ", computed " +
         hex(headerCrc) + " (the header is corrupt)");
  const uint16_t version = loadLE<uint16_t>(p + hf::kVersion);
  if (version != kVersion)
    fail("header field 'version': " + std::to_string(version) + "; this vox reads version " + std::to_string(kVersion) +
         (version > kVersion ? " (upgrade vox)" : ""));
  if (loadLE<uint16_t>(p + hf::kHeaderBytes) != kHeaderBytes)
    fail("header field 'header_bytes': expected " + std::to_string(kHeaderBytes));
  Header& h = header_;
  const uint8_t layout = p[hf::kLayout];
  if (!findLayout(layout))
    fail("header field 'layout': " + std::to_string(layout) + ", expected 1.." + std::to_string(layoutTable().size()));
  h.layout = Layout(layout);
  h.chunkLog2 = p[hf::kChunkLog2];
  if (h.chunkLog2 < kMinChunkLog2 || h.chunkLog2 > kMaxChunkLog2)
    fail("header field 'chunk_log2': " + std::to_string(h.chunkLog2) + ", expected " + std::to_string(kMinChunkLog2) +
         ".." + std::to_string(kMaxChunkLog2));
  h.levelCount = p[hf::kLevelCount];
  h.alignLog2 = p[hf::kAlignLog2];
  if (h.alignLog2 < kMinAlignLog2 || h.alignLog2 > kMaxAlignLog2)
    fail("header field 'align_log2': " + std::to_string(h.alignLog2) + ", expected " + std::to_string(kMinAlignLog2) +
         ".." + std::to_string(kMaxAlignLog2));
  h.flags = loadLE<uint32_t>(p + hf::kFlags);
  if (h.flags & ~kKnownFlags) fail("header field 'flags': unknown bits " + hex(h.flags & ~kKnownFlags));
  for (size_t k = 0; k < 3; ++k) {
    h.dims[k] = loadLE<uint32_t>(p + hf::kDims + 4 * k);
    if (h.dims[k] < 1 || h.dims[k] > kMaxDim)
      fail("header field 'dims': axis " + std::to_string(k) + " is " + std::to_string(h.dims[k]) + ", expected 1..2^20");
  }
  uint32_t maxAxis = std::max({h.dims[0], h.dims[1], h.dims[2]});
  int maxLevels = 1;
  while (maxAxis > 1) maxAxis = (maxAxis + 1) / 2, ++maxLevels;
  if (h.levelCount < 1 || h.levelCount > maxLevels)
    fail("header field 'level_count': " + std::to_string(h.levelCount) + ", expected 1.." + std::to_string(maxLevels));
  h.voxelSize = loadLE<double>(p + hf::kVoxelSize);
  if (!(h.voxelSize > 0) || !std::isfinite(h.voxelSize)) fail("header field 'voxel_size': must be finite and > 0");
  for (size_t k = 0; k < 3; ++k) {
    h.origin[k] = loadLE<double>(p + hf::kOrigin + 8 * k);
    if (!std::isfinite(h.origin[k])) fail("header field 'origin': must be finite");
  }
  h.chunkCount = loadLE<uint64_t>(p + hf::kChunkCount);
  h.indexOffset = loadLE<uint64_t>(p + hf::kIndexOffset);
  h.metaOffset = loadLE<uint64_t>(p + hf::kMetaOffset);
  h.metaBytes = loadLE<uint64_t>(p + hf::kMetaBytes);
  h.payloadOffset = loadLE<uint64_t>(p + hf::kPayloadOffset);
  h.fileBytes = loadLE<uint64_t>(p + hf::kFileBytes);
  h.metaCrc = loadLE<uint32_t>(p + hf::kMetaCrc);
  h.indexCrc = loadLE<uint32_t>(p + hf::kIndexCrc);
  // Zero in version 1: a later version may give it a meaning, which this reader would miss.
  if (const uint32_t reserved = loadLE<uint32_t>(p + hf::kReserved); reserved != 0)
    fail("header field 'reserved' (offset " + std::to_string(hf::kReserved) + "): " + std::to_string(reserved) +
         ", must be 0 (the header is corrupt, or was written by another tool)");
  if (h.fileBytes != size_)
    fail("header field 'file_bytes': " + std::to_string(h.fileBytes) + ", but the file has " + std::to_string(size_) +
         " bytes (" + (size_ < h.fileBytes ? "truncated" : "trailing bytes") + ")");
  if (h.indexOffset != kHeaderBytes) fail("header field 'index_offset': expected " + std::to_string(kHeaderBytes));
  if (h.chunkCount > (size_ - kHeaderBytes) / kIndexEntryBytes)
    fail("header field 'chunk_count': " + std::to_string(h.chunkCount) + " entries do not fit in the file");
  const uint64_t indexEnd = h.indexOffset + h.chunkCount * kIndexEntryBytes;
  if (h.metaOffset != indexEnd) fail("header field 'meta_offset': expected the end of the index, " + std::to_string(indexEnd));
  if (h.metaBytes > size_ - h.metaOffset) fail("header field 'meta_bytes': runs past the end of the file");
  const uint64_t align = uint64_t(1) << h.alignLog2;
  if (h.payloadOffset != alignUp(h.metaOffset + h.metaBytes, align) || h.payloadOffset > size_)
    fail("header field 'payload_offset': expected the aligned end of the metadata");
  const uint32_t indexCrc = crc32c(p + h.indexOffset, h.chunkCount * kIndexEntryBytes);
  if (crcDiffers(h.indexCrc, indexCrc))
    fail("index: field 'index_crc32c': stored " + hex(h.indexCrc) + ", computed " + hex(indexCrc) + " (the index is corrupt)");
  const uint32_t metaCrc = crc32c(p + h.metaOffset, h.metaBytes);
  if (crcDiffers(h.metaCrc, metaCrc))
    fail("metadata: field 'meta_crc32c': stored " + hex(h.metaCrc) + ", computed " + hex(metaCrc));
  meta_.assign(reinterpret_cast<const char*>(p + h.metaOffset), h.metaBytes);
}

// Every entry: fields in range, sorted by (level, key), payloads aligned, in
// order, inside the file and of the size the layout allows.
void Reader::parseIndex() {
  auto fail = [&](const std::string& what) { throwBadInput(name_ + ": " + what); };
  const Header& h = header_;
  const LayoutCodec& codec = codecOf(h.layout);
  const uint64_t align = uint64_t(1) << h.alignLog2;
  entries_.resize(h.chunkCount);
  uint64_t prevEnd = h.payloadOffset;
  for (size_t i = 0; i < entries_.size(); ++i) {
    const uint8_t* q = data_ + h.indexOffset + i * kIndexEntryBytes;
    IndexEntry& e = entries_[i];
    e.level = q[ef::kLevel];
    e.flags = q[ef::kFlags];
    e.occupied = loadLE<uint32_t>(q + ef::kOccupied);
    e.key = loadLE<uint64_t>(q + ef::kKey);
    e.offset = loadLE<uint64_t>(q + ef::kOffset);
    e.size = loadLE<uint32_t>(q + ef::kSize);
    e.crc = loadLE<uint32_t>(q + ef::kCrc);
    const std::string where = "index entry " + std::to_string(i);
    if (e.level >= h.levelCount)
      fail(where + ": field 'level': " + std::to_string(e.level) + " >= level_count " + std::to_string(h.levelCount));
    if (e.flags & ~kChunkFull) fail(where + ": field 'flags': unknown bits");
    if (loadLE<uint16_t>(q + ef::kReserved) != 0) fail(where + ": field 'reserved': must be 0");
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
    if (e.size < codec.fixedBytes)
      fail(describe(i) + ": field 'size': " + std::to_string(e.size) + " bytes, the " + codec.name +
           " layout needs at least " + std::to_string(codec.fixedBytes));
    if (codec.sizeFromIndex && e.size != codec.sizeFromIndex(h, e))
      fail(describe(i) + ": field 'size': " + std::to_string(e.size) + " bytes, the " + codec.name + " layout needs " +
           std::to_string(codec.sizeFromIndex(h, e)));
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
  return codecOf(header_.layout).decode({*this, i, header_, entries_.at(i), payload(i)});
}

void ChunkPayload::fail(const std::string& what) const {
  throwBadInput(reader.name() + ": " + reader.describe(index) + ": " + what);
}

uint64_t Reader::verify() const {
  uint64_t voxels = 0;
  for (size_t i = 0; i < entries_.size(); ++i) voxels += decode(i).size();
  checkPadding();
  return voxels;
}

void Reader::checkPadding() const {
  // [from, to) must be zeros; `before` names what follows the gap.
  auto zeros = [&](uint64_t from, uint64_t to, const std::string& before) {
    const uint8_t* end = data_ + to;  // bounds checked in parse()
    const uint8_t* at = data_ + from;
    // Blocks OR-ed first (a loop the compiler vectorizes): 4 KiB alignment
    // makes padding most of a sparse surface's file.
    constexpr size_t kBlock = 4096;
    for (; end - at >= std::ptrdiff_t(kBlock); at += kBlock) {
      uint8_t any = 0;
      for (size_t k = 0; k < kBlock; ++k) any |= at[k];
      if (any) break;
    }
    const uint8_t* nonzero = std::find_if(at, end, [](uint8_t b) { return b != 0; });
    if (nonzero != end)
      throwBadInput(name_ + ": padding before " + before + ": byte " + std::to_string(nonzero - data_) + " is " +
                    std::to_string(*nonzero) + ", must be 0 (the bytes between the metadata and the payloads and "
                    "between payloads are zeros; the file is corrupt: pack it again)");
  };
  uint64_t at = header_.metaOffset + header_.metaBytes;
  for (size_t i = 0; i < entries_.size(); ++i) {
    zeros(at, entries_[i].offset, describe(i));
    at = entries_[i].offset + entries_[i].size;
  }
  zeros(at, size_, "the end of the file");  // an empty file's, after its metadata
}

}  // namespace vox::pagefile
