#include "formats/pagefile/page_merge.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstring>
#include <chrono>
#include <exception>

#include "formats/pagefile/layouts.h"
#include "formats/pagefile/pack_chunks.h"
#include "formats/pagefile/pagefile_meta.h"
#include "formats/pagefile/svo_layout.h"
#include "formats/core/file_util.h"
#include "libvox/core/crc32c.h"
#include "libvox/core/error.h"
#include "libvox/core/morton.h"
#include "libvox/core/parallel.h"
#include "libvox/core/regions.h"
#include "libvox/core/version.h"
#include "libvox/scene/mip.h"
#include "libvox/scene/scene.h"

namespace vox {

namespace {

using pagefile::Reader;

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The output, written in place with pwrite from any thread.
class OutputFile {
 public:
  OutputFile(const std::string& path, uint64_t size) : path_(path) {
    fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd_ < 0) throwIo(outputName(path) + ": cannot create the file: " + std::strerror(errno));
    if (::ftruncate(fd_, off_t(size)) != 0) fail(errno);
  }
  ~OutputFile() {
    if (fd_ >= 0) ::close(fd_);
  }
  void write(uint64_t offset, const uint8_t* p, size_t n) {
    while (n > 0) {
      const ssize_t w = ::pwrite(fd_, p, n, off_t(offset));
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) fail(w < 0 ? errno : ENOSPC);
      p += w, n -= size_t(w), offset += uint64_t(w);
    }
  }
  void close() {
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) fail(errno);
  }

 private:
  [[noreturn]] void fail(int err) const {
    throwIo(outputName(path_) + ": cannot write the file: " + std::strerror(err));
  }
  std::string path_;
  int fd_ = -1;
};

// One part: its reader, metadata and the scene header checkRegionParts reads.
struct Part {
  const Reader* reader = nullptr;
  pagefile::PageMeta meta;
  SceneHeader header;
};

// The scene header a part's page file describes: placement from the file
// header, class table, sources, block world and region from the metadata.
SceneHeader sceneHeaderOf(const Reader& r, const pagefile::PageMeta& meta) {
  SceneHeader h;
  const pagefile::Header& ph = r.header();
  h.dims = {ph.dims[0], ph.dims[1], ph.dims[2]};
  h.voxelSize = ph.voxelSize;
  h.origin = ph.origin;
  h.classes = meta.classes;
  h.sources = meta.sources;
  h.blockWorld = meta.blockWorld;
  h.region = meta.region;
  return h;
}

[[noreturn]] void refuse(const Reader& r, const std::string& what) { throwBadInput(r.name() + ": " + what); }

bool contains(const IndexBox& outer, const IndexBox& inner) {
  return !outer.empty() && inner.min.u >= outer.min.u && inner.min.v >= outer.min.v && inner.min.w >= outer.min.w &&
         inner.max.u <= outer.max.u && inner.max.v <= outer.max.v && inner.max.w <= outer.max.w;
}

// The --align a part was packed with (0: auto): its record, or for parts that
// predate the record, the alignment in its header.
uint32_t alignmentAsked(const Part& p) {
  return p.meta.regionAlign ? *p.meta.regionAlign : 1u << p.reader->header().alignLog2;
}

std::string alignmentName(uint32_t asked) { return asked ? std::to_string(asked) : "auto"; }

// Every part is a part, and the parts agree on what decides the bytes of the
// merged file besides their voxels.
void checkSettingsAgree(const std::vector<Part>& parts) {
  const Part& first = parts.front();
  const pagefile::Header& a = first.reader->header();
  for (const Part& p : parts) {
    const pagefile::Header& b = p.reader->header();
    auto differs = [&](const std::string& what, const std::string& va, const std::string& vb) {
      refuse(*p.reader, what + " " + vb + ", but " + first.reader->name() + " has " + va +
                            ": pack every part with the same --chunk, --layout, --align and --mips");
    };
    if (b.chunkLog2 != a.chunkLog2)
      differs("chunk side", std::to_string(a.chunkSide()), std::to_string(b.chunkSide()));
    if (b.layout != a.layout) differs("layout", pagefile::layoutName(a.layout), pagefile::layoutName(b.layout));
    // The alignment asked, not the one a part's own payloads gave with auto:
    // the merge chooses again over the world's chunks, as the whole pack does.
    if (alignmentAsked(p) != alignmentAsked(first))
      differs("payload alignment", alignmentName(alignmentAsked(first)), alignmentName(alignmentAsked(p)));
    if (p.meta.mipOccupancy.empty() != first.meta.mipOccupancy.empty()) {
      const Part& without = p.meta.mipOccupancy.empty() ? p : first;
      const Part& with = p.meta.mipOccupancy.empty() ? first : p;
      refuse(*without.reader, "packed without --mips, but " + with.reader->name() + " has mip levels (occupancy '" +
                                  with.meta.mipOccupancy + "'): pack every part with the same --mips, --occupancy "
                                  "and --levels (pack " + without.reader->name() + " again with --mips and the "
                                  "options of the others, or " + with.reader->name() + " without --mips)");
    }
    if (p.meta.mipOccupancy != first.meta.mipOccupancy)
      differs("mip occupancy", "'" + first.meta.mipOccupancy + "'", "'" + p.meta.mipOccupancy + "'");
    if (b.levelCount != a.levelCount)
      differs("level count", std::to_string(a.levelCount), std::to_string(b.levelCount));
    if (b.levelCount == 1) continue;
    if (p.meta.mipOccupancy != "any" && p.meta.mipOccupancy != "majority")
      refuse(*p.reader, "its levels came " + p.meta.mipOccupancy +
                            ": a merge rebuilds the coarse levels, so pack the parts from their scenes with --mips "
                            "[--occupancy any|majority] [--levels N]");
    if (!p.meta.regionMips) refuse(*p.reader, "the part has mip levels but no 'region_mips' record: pack it again");
    const pagefile::RegionMips& ra = *first.meta.regionMips;
    const pagefile::RegionMips& rb = *p.meta.regionMips;
    if (rb.levelsAsked != ra.levelsAsked)
      differs("--levels", std::to_string(ra.levelsAsked), std::to_string(rb.levelsAsked));
    if (rb.seamLevel != ra.seamLevel || (rb.seamLevel && rb.seamLevel != pagefile::kRegionSeamLevel))
      differs("seam level", std::to_string(ra.seamLevel), std::to_string(rb.seamLevel));
  }
}

// The number of levels the single-process pack has: `--levels` + 1, or the
// automatic rule of buildMipPyramid (stop after the first level with at most
// one voxel) on the parts' counts per level (every voxel of a level below the
// seam lies in one part). Returns 0 when the rule has not stopped by the
// parts' last level and the seam level decides the rest.
int worldLevelCount(const std::vector<Part>& parts) {
  const int stored = parts.front().reader->header().levelCount;
  if (stored == 1) return 1;
  const pagefile::RegionMips& rm = *parts.front().meta.regionMips;
  if (rm.levelsAsked) return int(rm.levelsAsked) + 1;
  std::vector<uint64_t> counts(size_t(stored), 0);
  for (const Part& p : parts)
    for (const pagefile::IndexEntry& e : p.reader->entries()) counts[e.level] += e.occupied;
  if (counts[0] <= 1) return 1;
  for (int n = 1; n < stored; ++n)
    if (counts[size_t(n)] <= 1) return n + 1;
  return rm.seamLevel ? 0 : stored;
}

// The seam level of the world: the parts' seam voxels joined (each lies in
// its part's box), with the world's placement at that level.
Scene seamScene(const std::vector<Part>& parts, uint32_t level) {
  const Part& first = parts.front();
  SceneHeader h = first.header;
  h.region.reset();
  h.dims = mipDims(h.dims, int(level));
  for (uint32_t k = 0; k < level; ++k) h.voxelSize *= 2;
  h.mipLevel = int(level);
  SceneBuilder b(h);
  for (const Part& p : parts) {
    const IndexBox& box = p.meta.region->box;
    const std::array<uint32_t, 3> dims0 = p.reader->header().dims;
    for (size_t i = 0; i < p.meta.regionMips->voxels.size(); ++i) {
      const pagefile::SeamVoxel& v = p.meta.regionMips->voxels[i];
      const std::string outside = "metadata 'region_mips.voxels[" + std::to_string(i) + "]' lies outside the part's box";
      if (v.at[0] >= h.dims.x || v.at[1] >= h.dims.y || v.at[2] >= h.dims.z) refuse(*p.reader, outside);
      // Inside the level's grid, so its level-0 span lies inside dims0: int32 coordinates.
      auto first = [&](int a) { return int64_t(v.at[size_t(a)]) << level; };
      auto last = [&](int a) { return std::min<int64_t>(first(a) + (int64_t(1) << level), dims0[size_t(a)]) - 1; };
      IndexBox span;  // the level-0 voxels it covers
      span.min = {int32_t(first(0)), int32_t(first(1)), int32_t(first(2))};
      span.max = {int32_t(last(0)), int32_t(last(1)), int32_t(last(2))};
      if (!contains(box, span)) refuse(*p.reader, outside);
      const Coord3 c{int32_t(v.at[0]), int32_t(v.at[1]), int32_t(v.at[2])};
      for (const ClassVotes& cv : v.votes) {
        if (!h.classes.find(cv.classId))
          refuse(*p.reader, "metadata 'region_mips.voxels[" + std::to_string(i) + "]': class " +
                                std::to_string(cv.classId) + " is not in the class table");
        b.addVotes(c, cv.classId, cv.votes, v.surface);
      }
      if (v.color) b.setColor(c, {(*v.color)[0], (*v.color)[1], (*v.color)[2]});
    }
  }
  return std::move(b).build();
}

// A chunk of the output and where its voxels come from: (part, entry) pairs,
// one per part that holds the chunk.
struct OutChunk {
  uint8_t level = 0;
  uint64_t key = 0;
  std::vector<std::pair<uint32_t, uint32_t>> sources;
  bool copy = false;
};

// The level-0 voxel box of chunk `cc` (C^3 at level 0), clipped to the domain.
// A corner past int32 (a chunk beyond any grid) is held at INT32_MAX, where no
// part's box reaches.
IndexBox chunkBox(const std::array<uint32_t, 3>& cc, uint32_t C, const std::array<uint32_t, 3>& dims) {
  auto held = [](int64_t x) { return int32_t(std::min<int64_t>(x, INT32_MAX)); };
  auto first = [&](int a) { return int64_t(cc[size_t(a)]) * C; };
  auto last = [&](int a) { return std::min<int64_t>(first(a) + C, dims[size_t(a)]) - 1; };
  IndexBox b;
  b.min = {held(first(0)), held(first(1)), held(first(2))};
  b.max = {held(last(0)), held(last(1)), held(last(2))};
  return b;
}

// Chunks of every part, sorted by (level, key); a level-0 chunk has one source
// and must lie inside its part's box.
std::vector<OutChunk> collectChunks(const std::vector<Part>& parts, int below) {
  struct Item {
    uint8_t level;
    uint64_t key;
    uint32_t part, entry;
  };
  std::vector<Item> items;
  for (uint32_t pi = 0; pi < parts.size(); ++pi) {
    const Reader& r = *parts[pi].reader;
    const IndexBox& box = parts[pi].meta.region->box;
    const auto& entries = r.entries();
    for (uint32_t ei = 0; ei < entries.size(); ++ei) {
      const pagefile::IndexEntry& e = entries[ei];
      if (e.level >= below) continue;
      if (e.level == 0 && !contains(box, chunkBox(e.chunk(), r.header().chunkSide(), r.header().dims)))
        refuse(r, r.describe(ei) + " lies outside the part's box: the file is not the part its 'region' says");
      items.push_back({e.level, e.key, pi, ei});
    }
  }
  std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
    return a.level != b.level ? a.level < b.level : a.key != b.key ? a.key < b.key : a.part < b.part;
  });
  std::vector<OutChunk> out;
  for (const Item& it : items) {
    if (out.empty() || out.back().level != it.level || out.back().key != it.key) out.push_back({it.level, it.key, {}, false});
    out.back().sources.push_back({it.part, it.entry});
  }
  for (const OutChunk& c : out)
    if (c.level == 0 && c.sources.size() > 1) {
      const Reader& r = *parts[c.sources[1].first].reader;
      refuse(r, r.describe(c.sources[1].second) + " is also in " + parts[c.sources[0].first].reader->name() +
                    ": the parts overlap");
    }
  return out;
}

// The payload of `c` in the world's flags, from its sources' decoded voxels
// through the layout's encoder (svo: from the decoded bricks, leaf and mip).
std::vector<uint8_t> reencode(const std::vector<Part>& parts, const OutChunk& c, const pagefile::Header& world) {
  const pagefile::LayoutCodec& codec = pagefile::codecOf(world.layout);
  const uint32_t C = world.chunkSide();
  if (world.layout == pagefile::Layout::Svo) {
    std::vector<pagefile::SvoBrick> bricks;
    for (const auto& [pi, ei] : c.sources) {
      std::vector<pagefile::SvoBrick> b = pagefile::svoBricks(*parts[pi].reader, ei);
      bricks.insert(bricks.end(), std::make_move_iterator(b.begin()), std::make_move_iterator(b.end()));
    }
    return pagefile::encodeSvoFromBricks(bricks, C, world.flags);
  }
  pagefile::ChunkVoxels v;
  const uint32_t N = world.chunkVoxels();
  v.side = C;
  v.bits.assign(N / 64, 0);
  v.summary.assign(N, {0, 0, 0, 0});
  v.color.assign(N, {0, 0, 0, 0});
  v.surface.assign(N, 0);
  for (const auto& [pi, ei] : c.sources)
    for (const pagefile::DecodedVoxel& d : parts[pi].reader->decode(ei)) {
      v.bits[d.index >> 6] |= uint64_t(1) << (d.index & 63);
      ++v.count;
      v.summary[d.index] = d.summary;
      v.color[d.index] = d.color;
      v.surface[d.index] = d.surface ? 1 : 0;
    }
  return codec.encode(v, world.flags, {c.level, mortonDecode(c.key)});
}

// Runs `work(i)` for the chunks in `which`, in parallel; the first error in
// chunk order is rethrown, so the message does not depend on the threads.
template <typename Fn>
void forChunks(const std::vector<size_t>& which, unsigned threads, Fn&& work) {
  std::vector<std::exception_ptr> errors(which.size());
  parallelForEach(which.size(), threads, 16, [&](size_t i) {
    try {
      work(which[i]);
    } catch (...) {
      errors[i] = std::current_exception();
    }
  });
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

// The CRC of every chunk of the levels the merge rebuilds (from `rebuilt` on),
// which it never reads otherwise: a part with a corrupt chunk is refused
// whichever level the damage is in, as `--verify` refuses it.
void checkRebuiltLevelCrcs(const std::vector<Part>& parts, int rebuilt, unsigned threads) {
  std::vector<std::pair<uint32_t, uint32_t>> skipped;  // (part, entry)
  for (uint32_t pi = 0; pi < parts.size(); ++pi) {
    const auto& entries = parts[pi].reader->entries();
    for (uint32_t ei = 0; ei < entries.size(); ++ei)
      if (entries[ei].level >= rebuilt) skipped.push_back({pi, ei});
  }
  std::vector<size_t> which(skipped.size());
  for (size_t k = 0; k < which.size(); ++k) which[k] = k;
  forChunks(which, threads, [&](size_t k) { parts[skipped[k].first].reader->payload(skipped[k].second); });
}

}  // namespace

MergeResult mergePageFiles(std::span<const Reader* const> readers, const MergeSettings& settings,
                           const std::string& outputPath) {
  if (readers.empty()) throw Error(ErrorKind::Internal, "mergePageFiles: no parts");
  MergeResult result;
  MergeStats& st = result.stats;
  auto t0 = std::chrono::steady_clock::now();

  // Check: every file a part, one bake, the same settings, chunks in their tiles.
  std::vector<Part> parts(readers.size());
  for (size_t i = 0; i < readers.size(); ++i) {
    Part& p = parts[i];
    p.reader = readers[i];
    p.meta = pagefile::readPageMeta(p.reader->metaJson(), p.reader->name());
    if (!p.meta.region)
      refuse(*p.reader, "a whole page file, not a part of a region bake (its metadata has no 'region'); --merge "
                        "joins the page files of the parts (vox voxelize --region I/N, then vox pack-chunks)");
    p.header = sceneHeaderOf(*p.reader, p.meta);
    st.partFileBytes += p.reader->header().fileBytes;
  }
  std::vector<RegionPart> rp;
  for (size_t i = 0; i < parts.size(); ++i) rp.push_back({parts[i].reader->name(), &parts[i].header});
  checkRegionParts(rp);
  checkSettingsAgree(parts);
  const Part& keeper = parts[worldHeaderPart(rp)];  // gives the sources, whatever the parts' order

  const Part& first = parts.front();
  pagefile::Header h;
  h.layout = first.reader->header().layout;
  h.chunkLog2 = first.reader->header().chunkLog2;
  const uint32_t align = alignmentAsked(first);
  h.alignLog2 = align ? uint8_t(std::countr_zero(align)) : pagefile::kAlignAuto;
  h.levelCount = first.reader->header().levelCount;  // the parts'; the world's is set below
  h.dims = first.reader->header().dims;
  h.voxelSize = first.reader->header().voxelSize;
  h.origin = first.reader->header().origin;
  // A channel is in the world when a part has it: colour when some part has
  // colour, the surface bit when some part has an interior voxel.
  for (const Part& p : parts) h.flags |= p.reader->header().flags;
  st.flagsFromParts = h.flags;

  // Levels: those below the seam level from the parts' chunks, the others
  // rebuilt from the seam voxels.
  int levelCount = worldLevelCount(parts);
  const uint32_t seam = h.levelCount > 1 ? first.meta.regionMips->seamLevel : 0;
  const int fromParts = seam ? std::min<int>(levelCount ? levelCount : int(seam), int(seam)) : levelCount;
  std::vector<OutChunk> chunks = collectChunks(parts, fromParts);
  checkRebuiltLevelCrcs(parts, fromParts, settings.threads);
  std::vector<size_t> toCopy, toEncode;
  for (size_t i = 0; i < chunks.size(); ++i) {
    OutChunk& c = chunks[i];
    c.copy = c.sources.size() == 1 && parts[c.sources[0].first].reader->header().flags == h.flags;
    (c.copy ? toCopy : toEncode).push_back(i);
  }
  st.checkSeconds = secondsSince(t0);

  // Re-encode: chunks of parts that lack a channel of the world, and chunks
  // of mip levels that several parts hold.
  std::vector<pagefile::ChunkBlob> blobs(chunks.size());  // only toEncode's are filled
  t0 = std::chrono::steady_clock::now();
  forChunks(toEncode, settings.threads, [&](size_t i) {
    uint32_t occupied = 0;
    for (const auto& [pi, ei] : chunks[i].sources) occupied += parts[pi].reader->entries()[ei].occupied;
    blobs[i].level = chunks[i].level;
    blobs[i].key = chunks[i].key;
    blobs[i].occupied = occupied;
    blobs[i].full = occupied == h.chunkVoxels();
    blobs[i].bytes = reencode(parts, chunks[i], h);
  });
  st.reencodeSeconds = secondsSince(t0);

  // Mips: the seam level joined, the coarser levels reduced from it as
  // buildMipPyramid does, each level packed as packChunks does.
  t0 = std::chrono::steady_clock::now();
  std::vector<pagefile::ChunkBlob> rebuilt;
  if (seam && levelCount != fromParts) {
    std::vector<Scene> levels;
    levels.push_back(seamScene(parts, seam));
    MipSettings ms;
    ms.occupancy = first.meta.mipOccupancy == "majority" ? MipOccupancy::Majority : MipOccupancy::Any;
    ms.levels = levelCount ? levelCount - 1 - int(seam) : 0;
    ms.threads = settings.threads;
    if (levelCount == 0 || ms.levels > 0)
      for (Scene& l : buildMipPyramid(levels[0], ms)) levels.push_back(std::move(l));
    levelCount = int(seam) + int(levels.size());
    st.seamVoxels = levels[0].occupiedCount();
    for (size_t k = 0; k < levels.size(); ++k)
      for (pagefile::ChunkBlob& b : packLevel(levels[k], int(seam + k), h, settings.threads)) {
        ++st.rebuiltChunks;
        st.rebuiltBytes += b.bytes.size();
        rebuilt.push_back(std::move(b));
      }
  }
  h.levelCount = uint8_t(levelCount);
  st.mipsSeconds = secondsSince(t0);

  // The file's chunks in index order: copied payloads are described by their
  // part's index entry (their CRC is checked when they are copied), the others
  // by their new bytes.
  t0 = std::chrono::steady_clock::now();
  const size_t total = chunks.size() + rebuilt.size();
  std::vector<pagefile::ChunkSlot> slots(total);
  std::vector<const std::vector<uint8_t>*> bytesOf(total, nullptr);
  for (size_t i = 0; i < chunks.size(); ++i) {
    if (chunks[i].copy) {
      const auto [pi, ei] = chunks[i].sources[0];
      const pagefile::IndexEntry& e = parts[pi].reader->entries()[ei];
      slots[i] = {e.level, e.key, e.occupied, bool(e.flags & pagefile::kChunkFull), e.size, e.crc};
      ++st.copiedChunks;
      st.copiedBytes += e.size;
    } else {
      const pagefile::ChunkBlob& b = blobs[i];
      slots[i] = {b.level, b.key, b.occupied, b.full, b.bytes.size(), 0};
      bytesOf[i] = &b.bytes;
      ++st.reencodedChunks;
      st.reencodedBytes += b.bytes.size();
      st.joinedChunks += chunks[i].sources.size() > 1 ? 1 : 0;
    }
  }
  for (size_t k = 0; k < rebuilt.size(); ++k) {
    const pagefile::ChunkBlob& b = rebuilt[k];
    slots[chunks.size() + k] = {b.level, b.key, b.occupied, b.full, b.bytes.size(), 0};
    bytesOf[chunks.size() + k] = &b.bytes;
  }
  std::vector<size_t> computed;
  for (size_t i = 0; i < total; ++i)
    if (bytesOf[i]) computed.push_back(i);
  parallelForEach(computed.size(), settings.threads, 64, [&](size_t j) {
    const std::vector<uint8_t>& b = *bytesOf[computed[j]];
    slots[computed[j]].crc = crc32c(b.data(), b.size());
  });

  // The metadata the single-process pack writes: the parts' class table,
  // sources and block world, no region, the levels counted here.
  pagefile::PageMeta meta;
  meta.toolVersion = kToolVersion;
  meta.classes = first.meta.classes;
  meta.sources = keeper.meta.sources;
  meta.mipOccupancy = first.meta.mipOccupancy;
  meta.blockWorld = first.meta.blockWorld;
  for (int l = 0; l < h.levelCount; ++l) {
    MergeResult::Level lv;
    lv.level = l;
    for (const pagefile::ChunkSlot& c : slots)
      if (c.level == l) {
        ++lv.chunks;
        lv.fullChunks += c.full ? 1 : 0;
        lv.voxels += c.occupied;
        lv.payloadBytes += c.size;
      }
    result.levels.push_back(lv);
    double vs = h.voxelSize;
    for (int k = 0; k < l; ++k) vs *= 2;
    meta.levels.push_back({uint32_t(l), h.levelDims(l), vs, lv.chunks, lv.voxels});
  }
  const pagefile::FilePlan plan = pagefile::planFile(h, pagefile::writePageMeta(meta), slots);
  result.fileBytes = plan.header.fileBytes;
  result.alignment = 1u << plan.header.alignLog2;

  // Write: the file at its final size, header, index and metadata, then the
  // payloads in runs of consecutive chunks of about kRunBytes: each run is
  // assembled in a buffer (copied payloads straight from the part's mapping
  // once their CRC is checked, zeros between payloads) and written with one
  // pwrite, runs in parallel. Few large writes, not one per chunk: buffered
  // writes to one file serialise on its inode.
  OutputFile out(outputPath, plan.header.fileBytes);
  out.write(0, plan.prefix.data(), plan.prefix.size());
  st.writeSeconds = secondsSince(t0);
  t0 = std::chrono::steady_clock::now();
  constexpr uint64_t kRunBytes = uint64_t(4) << 20;
  std::vector<size_t> runStart;  // first chunk of each run
  for (size_t i = 0; i < total; ++i)
    if (runStart.empty() ||
        plan.entries[i].offset + plan.entries[i].size - plan.entries[runStart.back()].offset > kRunBytes)
      runStart.push_back(i);
  std::vector<size_t> runs(runStart.size());
  for (size_t r = 0; r < runs.size(); ++r) runs[r] = r;
  std::vector<std::exception_ptr> errors(runs.size());
  parallelForEach(runs.size(), settings.threads, 1, [&](size_t r) {
    try {
      const size_t first = runStart[r], last = r + 1 < runStart.size() ? runStart[r + 1] : total;
      const uint64_t base = plan.entries[first].offset;
      const uint64_t end = plan.entries[last - 1].offset + plan.entries[last - 1].size;
      thread_local std::vector<uint8_t> buf;
      buf.resize(end - base);
      uint64_t filled = 0;  // bytes of the run set so far
      for (size_t i = first; i < last; ++i) {
        const uint64_t at = plan.entries[i].offset - base;
        std::memset(buf.data() + filled, 0, at - filled);  // the padding before payload i
        std::span<const uint8_t> bytes;
        if (bytesOf[i]) {
          bytes = {bytesOf[i]->data(), bytesOf[i]->size()};
        } else {
          const auto [pi, ei] = chunks[i].sources[0];
          bytes = parts[pi].reader->payload(ei);  // checks the CRC
        }
        std::memcpy(buf.data() + at, bytes.data(), bytes.size());
        filled = at + bytes.size();
      }
      out.write(base, buf.data(), buf.size());
    } catch (...) {
      errors[r] = std::current_exception();
    }
  });
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
  out.close();
  st.copySeconds = secondsSince(t0);
  return result;
}

}  // namespace vox
